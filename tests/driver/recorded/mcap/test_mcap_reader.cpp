// ogf::mcap::McapReader on MCAP files assembled record by record (MCAP specification, "Records"), so each
// test holds exactly the damage or the hostile length it is about: none of them makes the reader allocate
// what the file claims, each is reported with the offset of the record, and the messages around it are read.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ogf/mcap/chunk_codec.hpp"
#include "ogf/mcap/mcap_reader.hpp"

namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<std::uint8_t>;
using ogf::mcap::McapReader;
using ogf::mcap::Opcode;

void le(Bytes& b, std::uint64_t v, int n) {
  for (int i = 0; i < n; ++i) b.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
}
void str(Bytes& b, const std::string& s) {
  le(b, s.size(), 4);
  b.insert(b.end(), s.begin(), s.end());
}
Bytes record(Opcode op, const Bytes& content, std::uint64_t claimed_length = UINT64_MAX) {
  Bytes b{static_cast<std::uint8_t>(op)};
  le(b, claimed_length == UINT64_MAX ? content.size() : claimed_length, 8);
  b.insert(b.end(), content.begin(), content.end());
  return b;
}
Bytes schema(std::uint16_t id, const std::string& name) {
  Bytes c;
  le(c, id, 2);
  str(c, name);
  str(c, "ros2msg");
  le(c, 0, 4);
  return record(Opcode::schema, c);
}
Bytes channel(std::uint16_t id, std::uint16_t schema_id, const std::string& topic) {
  Bytes c;
  le(c, id, 2);
  le(c, schema_id, 2);
  str(c, topic);
  str(c, "cdr");
  le(c, 0, 4);
  return record(Opcode::channel, c);
}
Bytes message(std::uint16_t channel_id, std::uint64_t time, std::uint8_t payload) {
  Bytes c;
  le(c, channel_id, 2);
  le(c, 0, 4);
  le(c, time, 8);
  le(c, time, 8);
  c.push_back(payload);
  return record(Opcode::message, c);
}
Bytes chunk(const Bytes& records, std::uint64_t start, std::uint64_t end,
            std::uint64_t declared_size = UINT64_MAX, bool with_crc = true) {
  Bytes c;
  le(c, start, 8);
  le(c, end, 8);
  le(c, declared_size == UINT64_MAX ? records.size() : declared_size, 8);
  le(c, with_crc ? ogf::mcap::crc32(records) : 0, 4);
  str(c, "");
  le(c, records.size(), 8);
  c.insert(c.end(), records.begin(), records.end());
  return record(Opcode::chunk, c);
}
Bytes header() {
  Bytes b(ogf::mcap::kMagic.begin(), ogf::mcap::kMagic.end());
  Bytes c;
  str(c, "ros2");
  str(c, "test");
  const Bytes h = record(Opcode::header, c);
  b.insert(b.end(), h.begin(), h.end());
  return b;
}
void append(Bytes& b, const Bytes& more) { b.insert(b.end(), more.begin(), more.end()); }
Bytes cat(std::initializer_list<Bytes> parts) {
  Bytes b;
  for (const auto& p : parts) append(b, p);
  return b;
}
// The end of a file without a summary: Data End, Footer, magic.
void finish(Bytes& b) {
  Bytes d;
  le(d, 0, 4);
  append(b, record(Opcode::data_end, d));
  Bytes f;
  le(f, 0, 8);
  le(f, 0, 8);
  le(f, 0, 4);
  append(b, record(Opcode::footer, f));
  b.insert(b.end(), ogf::mcap::kMagic.begin(), ogf::mcap::kMagic.end());
}

class McapFile : public ::testing::Test {
 protected:
  fs::path write(const Bytes& b) {
    const auto p = fs::temp_directory_path() /
                   ("ogf-mcap-" + std::to_string(::getpid()) + "-" + std::to_string(files_.size()) + ".mcap");
    std::ofstream(p, std::ios::binary)
        .write(reinterpret_cast<const char*>(b.data()), static_cast<std::streamsize>(b.size()));
    files_.push_back(p);
    return p;
  }
  void TearDown() override {
    for (const auto& f : files_) fs::remove(f);
  }
  struct Read {
    std::vector<std::pair<std::uint64_t, std::uint8_t>> messages;  // log time, payload
    std::vector<std::string> damage;
  };
  static Read readAll(const McapReader& r, std::set<std::uint16_t> channels = {1}) {
    Read out;
    auto st = r.forEachMessage(
        channels, [&](const ogf::mcap::MessageView& m) { out.messages.emplace_back(m.log_time, m.data[0]); },
        [&](const std::string& d) { out.damage.push_back(d); });
    EXPECT_TRUE(st.ok()) << st.error().message;
    return out;
  }
  static std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const auto& x : v) s += x + "\n";
    return s;
  }
  std::vector<fs::path> files_;
};

TEST_F(McapFile, MessagesInAndOutOfChunksComeOutInLogTimeOrderTiesInFileOrder) {
  Bytes b = cat({header(), schema(1, "std_msgs/msg/String"), channel(1, 1, "/a")});
  // Two chunks overlapping in time, and a message outside chunks between them.
  append(b, chunk(cat({message(1, 30, 3), message(1, 10, 1), message(1, 50, 6)}), 10, 50));
  append(b, message(1, 20, 2));
  append(b, chunk(cat({message(1, 30, 4), message(1, 40, 5)}), 30, 40));
  finish(b);
  auto r = McapReader::open(write(b));
  ASSERT_TRUE(r.ok()) << r.error().message;
  EXPECT_FALSE(r->indexed());
  ASSERT_EQ(r->channels().size(), 1u);
  EXPECT_EQ(r->channels()[0].schema_name, "std_msgs/msg/String");
  EXPECT_EQ(r->channels()[0].message_count, 6u);
  const auto read = readAll(*r);
  EXPECT_TRUE(read.damage.empty()) << joined(read.damage);
  const std::vector<std::pair<std::uint64_t, std::uint8_t>> expected = {{10, 1}, {20, 2}, {30, 3},
                                                                        {30, 4}, {40, 5}, {50, 6}};
  EXPECT_EQ(read.messages, expected);
}

TEST_F(McapFile, AChunkFailingItsCrcIsNamedByOffsetAndTheOthersAreRead) {
  Bytes b = cat({header(), schema(1, "t"), channel(1, 1, "/a")});
  append(b, chunk(cat({message(1, 1, 1)}), 1, 1));
  const std::size_t bad_at = b.size();
  Bytes second = chunk(cat({message(1, 2, 2)}), 2, 2);
  second[second.size() - 1] ^= 0x01;  // the message's payload byte
  append(b, second);
  append(b, chunk(cat({message(1, 3, 3)}), 3, 3));
  finish(b);
  auto r = McapReader::open(write(b));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto read = readAll(*r);
  EXPECT_EQ(read.messages, (std::vector<std::pair<std::uint64_t, std::uint8_t>>{{1, 1}, {3, 3}}));
  ASSERT_EQ(read.damage.size(), 1u) << joined(read.damage);
  EXPECT_NE(read.damage[0].find("chunk at byte " + std::to_string(bad_at) + ": CRC-32"), std::string::npos)
      << read.damage[0];
}

TEST_F(McapFile, HostileSizesAreRefusedWithoutAllocatingThem) {
  Bytes b = cat({header(), schema(1, "t"), channel(1, 1, "/a")});
  append(b, chunk(cat({message(1, 1, 1)}), 1, 1));
  // A chunk declaring 2^60 bytes uncompressed, a schema whose name claims 4 GiB, a chunk whose records
  // claim more than its record holds.
  const std::size_t huge_at = b.size();
  append(b, chunk(cat({message(1, 2, 2)}), 2, 2, std::uint64_t{1} << 60));
  const std::size_t name_at = b.size();
  Bytes bad_schema;
  le(bad_schema, 2, 2);
  le(bad_schema, 0xFFFFFFFF, 4);
  append(b, record(Opcode::schema, bad_schema));
  Bytes lying = chunk(cat({message(1, 3, 3)}), 3, 3);
  lying[9 + 8 + 8 + 8 + 4 + 4] = 0xFF;  // the records' length
  const std::size_t lying_at = b.size();
  append(b, lying);
  append(b, chunk(cat({message(1, 4, 4)}), 4, 4));
  finish(b);
  auto r = McapReader::open(write(b));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto read = readAll(*r);
  EXPECT_EQ(read.messages, (std::vector<std::pair<std::uint64_t, std::uint8_t>>{{1, 1}, {4, 4}}));
  const std::string all = joined(read.damage);
  EXPECT_NE(all.find("chunk at byte " + std::to_string(huge_at)), std::string::npos) << all;
  EXPECT_NE(all.find("Schema record at byte " + std::to_string(name_at)), std::string::npos) << all;
  EXPECT_NE(all.find("chunk at byte " + std::to_string(lying_at)), std::string::npos) << all;
}

TEST_F(McapFile, ARecordClaimingMoreThanTheFileIsACutAndWhatCameBeforeIsRead) {
  Bytes b = cat({header(), schema(1, "t"), channel(1, 1, "/a"), chunk(cat({message(1, 1, 1)}), 1, 1)});
  const std::size_t cut_at = b.size();
  append(b, record(Opcode::chunk, Bytes(40, 0), std::uint64_t{1} << 62));
  auto r = McapReader::open(write(b));
  ASSERT_TRUE(r.ok()) << r.error().message;
  const auto read = readAll(*r);
  EXPECT_EQ(read.messages, (std::vector<std::pair<std::uint64_t, std::uint8_t>>{{1, 1}}));
  const std::string all = joined(read.damage);
  EXPECT_NE(all.find("Chunk record at byte " + std::to_string(cut_at)), std::string::npos) << all;
  EXPECT_NE(all.find("cut short"), std::string::npos) << all;
}

TEST_F(McapFile, ASummaryFailingItsCrcIsReportedAndTheDataSectionIsReadInstead) {
  Bytes b = cat({header(), schema(1, "t"), channel(1, 1, "/a")});
  const std::size_t chunk_at = b.size();
  const Bytes c = chunk(cat({message(1, 7, 7)}), 7, 7);
  append(b, c);
  Bytes d;
  le(d, 0, 4);
  append(b, record(Opcode::data_end, d));
  const std::size_t summary_at = b.size();
  Bytes summary = cat({schema(1, "t"), channel(1, 1, "/a")});
  Bytes index;
  le(index, 7, 8);
  le(index, 7, 8);
  le(index, chunk_at, 8);
  le(index, c.size(), 8);
  le(index, 0, 4);
  le(index, 0, 8);
  str(index, "");
  le(index, 0, 8);
  le(index, 0, 8);
  append(summary, record(Opcode::chunk_index, index));
  Bytes stats;
  le(stats, 1, 8);
  le(stats, 1, 2);
  le(stats, 1, 4);
  le(stats, 0, 4);
  le(stats, 0, 4);
  le(stats, 1, 4);
  le(stats, 7, 8);
  le(stats, 7, 8);
  le(stats, 10, 4);
  le(stats, 1, 2);
  le(stats, 1, 8);
  append(summary, record(Opcode::statistics, stats));
  append(b, summary);
  Bytes f;
  le(f, summary_at, 8);
  le(f, 0, 8);
  Bytes footer_start = {static_cast<std::uint8_t>(Opcode::footer)};
  le(footer_start, 20, 8);
  append(footer_start, f);
  const std::uint32_t crc = ogf::mcap::crc32(footer_start, ogf::mcap::crc32(summary));
  le(f, crc, 4);
  Bytes good = b;
  append(good, record(Opcode::footer, f));
  good.insert(good.end(), ogf::mcap::kMagic.begin(), ogf::mcap::kMagic.end());
  auto indexed = McapReader::open(write(good));
  ASSERT_TRUE(indexed.ok()) << indexed.error().message;
  EXPECT_TRUE(indexed->indexed());
  EXPECT_EQ(readAll(*indexed).messages, (std::vector<std::pair<std::uint64_t, std::uint8_t>>{{7, 7}}));

  Bytes damaged = good;
  damaged[summary_at + 20] ^= 0x40;  // inside the summary's Schema record
  auto scanned = McapReader::open(write(damaged));
  ASSERT_TRUE(scanned.ok()) << scanned.error().message;
  EXPECT_FALSE(scanned->indexed());
  const auto read = readAll(*scanned);
  EXPECT_EQ(read.messages, (std::vector<std::pair<std::uint64_t, std::uint8_t>>{{7, 7}}));
  const std::string all = joined(read.damage);
  EXPECT_NE(all.find("summary section at byte " + std::to_string(summary_at) + ": CRC-32"), std::string::npos)
      << all;
}

TEST_F(McapFile, AFileThatIsNoMcapIsRefusedByName) {
  const auto p = write(Bytes(100, 'x'));
  auto r = McapReader::open(p);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.error().message, p.string() + ": not an MCAP file (no MCAP magic at its start)");
}

TEST(ChunkCodec, ZstdAndLz4RoundTripAndRefuseAWrongDeclaredSize) {
  Bytes records;
  for (int i = 0; i < 5000; ++i) records.push_back(static_cast<std::uint8_t>(i * 7 % 251));
  for (const char* c : {"zstd", "lz4"}) {
    auto packed = ogf::mcap::compressRecords(c, records);
    ASSERT_TRUE(packed.ok()) << c;
    auto back = ogf::mcap::decompressRecords(c, *packed, records.size());
    ASSERT_TRUE(back.ok()) << c << ": " << back.error().message;
    EXPECT_EQ(*back, records) << c;
    EXPECT_FALSE(ogf::mcap::decompressRecords(c, *packed, records.size() - 1).ok()) << c;
    EXPECT_FALSE(ogf::mcap::decompressRecords(c, *packed, records.size() + 1).ok()) << c;
  }
}

}  // namespace
