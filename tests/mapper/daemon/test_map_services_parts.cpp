// The pure parts of ogf-mapper's map services: export names, a box summarised in chunks, the command MAC,
// the replay rule and log sanitising. (The processes under attack: tests/reliability/test_services.cpp.)
#include <gtest/gtest.h>

#include <set>

#include "ogf/mapper_daemon/command_auth.hpp"
#include "ogf/mapper_daemon/log_text.hpp"
#include "ogf/mapper_daemon/map_export.hpp"
#include "ogf/mapper_daemon/map_query_answer.hpp"
#include "ogf/mapper_daemon/mapper_options.hpp"

namespace ogf::mapper_daemon {
namespace {

TEST(ExportName, OnlyPlainNamesWithTheFormatsExtensionPass) {
  EXPECT_TRUE(checkExportName("map.ply", "ply").ok());
  EXPECT_TRUE(checkExportName("run_2-3.v1.ogfm", "ogfm").ok());
  for (const std::string bad : {"/tmp/map.ply", "../map.ply", "a/map.ply", ".map.ply", "map.csv", "map.ply\n",
                                "ma p.ply", "..", ".", "", "snapshot.ogfs", "map.PLY"}) {
    EXPECT_FALSE(checkExportName(bad, "ply").ok()) << bad;
  }
  EXPECT_FALSE(checkExportName(std::string(200, 'a') + ".ply", "ply").ok());
  EXPECT_FALSE(checkExportName("map.exe", "exe").ok());
}

TEST(ChunkedBox, ChunksCoverEveryCellOnceAndSumToTheWholeBox) {
  filter::FilterConfig config;
  auto map = filter::BandedOgf::create(config);
  ASSERT_TRUE(map.ok());
  std::vector<Measurement> batch;
  for (int x = -3; x < 9; ++x)
    for (int y = 0; y < 5; ++y) batch.push_back({CellKey{x, y, x % 3}, x == 8 ? Measurement::kOccupied : Measurement::kFree});
  for (int i = 0; i < 4; ++i) map->update(batch);
  const KeyBox box{{-5, -2, -3}, {10, 7, 4}, 16 * 10 * 8};
  const auto whole = filter::summariseBox(*map, box.lo, box.hi);
  ASSERT_TRUE(whole.ok());
  for (const std::int64_t chunk : {1, 7, 8, 79, 80, 81, 800, 5000}) {
    ChunkedBox chunks(box, chunk);
    std::set<std::tuple<int, int, int>> seen;
    while (auto c = chunks.next()) {
      EXPECT_LE(c->cells, chunk);
      for (int x = c->lo.x; x <= c->hi.x; ++x)
        for (int y = c->lo.y; y <= c->hi.y; ++y)
          for (int z = c->lo.z; z <= c->hi.z; ++z) EXPECT_TRUE(seen.insert({x, y, z}).second) << "twice";
      auto part = filter::summariseBox(*map, c->lo, c->hi);
      ASSERT_TRUE(part.ok());
      chunks.add(*part);
    }
    EXPECT_EQ(static_cast<std::int64_t>(seen.size()), box.cells) << "chunk " << chunk;
    ogf::map_query_reply_t r{};
    chunks.fill(r, 0.2);
    EXPECT_EQ(r.box_cells, box.cells);
    EXPECT_EQ(r.box_occupied, static_cast<std::int64_t>(whole->occupied));
    EXPECT_EQ(r.box_free, static_cast<std::int64_t>(whole->free));
    EXPECT_NEAR(r.mean_variance, whole->meanVariance, 1e-9);
    EXPECT_NEAR(r.mean_entropy_bits, whole->entropyBits / static_cast<double>(whole->cells), 1e-9);
  }
}

TEST(BoxKeys, ABoxBeyondTheLimitIsRefusedFromItsCorners) {
  ogf::map_query_t q{};
  q.kind = ogf::map_query_t::KIND_BOX;
  const float lo[3] = {0, 0, 0}, hi[3] = {1.99f, 1.99f, 1.99f};  // 10 x 10 x 10 cells of 0.2 m
  std::copy(lo, lo + 3, q.box_min);
  std::copy(hi, hi + 3, q.box_max);
  const auto ok = boxKeysOf(q, 0.2, 3, 1000);
  ASSERT_TRUE(ok.ok());
  EXPECT_EQ(ok->cells, 1000);
  EXPECT_FALSE(boxKeysOf(q, 0.2, 3, 999).ok());
}

ogf::map_command_t aCommand() {
  ogf::map_command_t c{};
  c.utime = 1'700'000'000'000'000;
  c.request_id = 5;
  c.requester = "planner";
  c.command = "export";
  c.format = "ply";
  c.path = "map.ply";
  c.nonce = 99;
  return c;
}

TEST(CommandMac, EveryFieldIsCoveredAndOnlyTheKeyVerifies) {
  CommandKey key;
  for (std::size_t i = 0; i < key.bytes.size(); ++i) key.bytes[i] = static_cast<unsigned char>(i * 7 + 1);
  auto c = aCommand();
  signCommand(c, key);
  EXPECT_TRUE(commandMacValid(c, key));
  CommandKey other = key;
  other.bytes[31] ^= 0x80;
  EXPECT_FALSE(commandMacValid(c, other));
  const std::vector<std::function<void(ogf::map_command_t&)>> changes = {
      [](auto& m) { m.utime += 1; },          [](auto& m) { m.request_id += 1; },
      [](auto& m) { m.requester += "x"; },    [](auto& m) { m.command = "reset"; },
      [](auto& m) { m.format = "csv"; },      [](auto& m) { m.path = "other.ply"; },
      [](auto& m) { m.nonce += 1; },          [](auto& m) { m.mac[0] = static_cast<std::int8_t>(m.mac[0] ^ 1); }};
  for (std::size_t i = 0; i < changes.size(); ++i) {
    auto changed = c;
    changes[i](changed);
    EXPECT_FALSE(commandMacValid(changed, key)) << "field " << i << " is not covered";
  }
}

TEST(ReplayGuard, RefusesOutsideTheWindowBeforeTheStartAndASecondCopy) {
  const std::int64_t start = 1'700'000'000'000'000, window = 30'000'000;
  ReplayGuard guard(start, window);
  auto c = aCommand();
  c.utime = start + 1'000'000;
  c.mac[0] = 1;
  EXPECT_EQ(guard.admit(c, start + 2'000'000), ReplayGuard::Verdict::kFresh);
  EXPECT_EQ(guard.admit(c, start + 3'000'000), ReplayGuard::Verdict::kReplayed);
  EXPECT_EQ(guard.admit(c, start + 40'000'000), ReplayGuard::Verdict::kOutsideWindow);
  auto early = c;
  early.utime = start - 1'000'000;
  early.mac[0] = 2;
  EXPECT_EQ(guard.admit(early, start + 1'000'000), ReplayGuard::Verdict::kBeforeStart);
  auto later = c;
  later.mac[0] = 3;
  EXPECT_EQ(guard.admit(later, start + 2'000'000), ReplayGuard::Verdict::kFresh);
}

TEST(LogText, ControlCharactersBecomeQuestionMarksAndLengthIsBounded) {
  EXPECT_EQ(sanitisedForLog("a\nb\r\x1b[2J\t"), "a?b??[2J?");
  EXPECT_EQ(sanitisedForLog("caf\xc3\xa9"), "caf??");
  const auto long_name = sanitisedForLog(std::string(500, 'x'));
  EXPECT_EQ(long_name.size(), kMaxLoggedName);
  EXPECT_EQ(long_name.substr(long_name.size() - 3), "...");
}

TEST(ServicesSection, TheExampleParsesBackAndEveryKeyIsRead) {
  MapperOptions o;
  ASSERT_TRUE(parseMapperOptions(mapperConfigYaml(), "example.yaml", o).ok());
  EXPECT_FALSE(o.services.commands_enabled);
  const std::string yaml =
      "services:\n  commands_enabled: true\n  key_file: /k\n  export_dir: /x\n  export_min_free_bytes: 5\n"
      "  max_query_cells: 1000\n  budget_ms_per_scan: 2.5\n  box_chunk_cells: 2000\n";
  ASSERT_TRUE(parseMapperOptions(yaml, "s.yaml", o).ok());
  EXPECT_TRUE(o.services.commands_enabled);
  EXPECT_EQ(o.services.key_file, "/k");
  EXPECT_EQ(o.services.exportDirFor("/state"), "/x");
  EXPECT_EQ(o.services.export_min_free_bytes, 5u);
  EXPECT_EQ(o.services.max_query_cells, 1000);
  EXPECT_EQ(o.services.budget_ms_per_scan, 2.5);
  EXPECT_EQ(o.services.box_chunk_cells, 2000);
  EXPECT_TRUE(o.validate().ok());
  const auto bad = parseMapperOptions("services:\n  budget_ms: 3\n", "b.yaml", o);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.error().message.find("services.budget_ms"), std::string::npos) << bad.error().message;
}

TEST(ServicesSection, CommandsWithoutAKeyAndExportsIntoTheStateDirectoryAreRefused) {
  MapperOptions o;
  EXPECT_EQ(o.services.exportDirFor("/var/lib/ogf"), std::filesystem::path("/var/lib/ogf/exports"));
  EXPECT_TRUE(o.services.exportDirFor("").empty());
  o.services.commands_enabled = true;
  EXPECT_FALSE(o.validate().ok());
  o.services.commands_enabled = false;
  o.state_dir = "/var/lib/ogf";
  o.services.export_dir = "/var/lib/ogf/";
  EXPECT_FALSE(o.validate().ok());
  o.services.export_dir = "/var/lib/ogf/pages";
  EXPECT_FALSE(o.validate().ok());
  o.services.export_dir = "/var/lib/ogf/exports";
  EXPECT_TRUE(o.validate().ok());
}

// A directory the system cannot resolve, here a name longer than a file name may be, is a configuration
// error naming the key and the path, not an exception.
TEST(ServicesSection, AStateOrExportDirectoryTheSystemCannotResolveIsAnErrorNamingIt) {
  const std::string tooLong(300, 'x');
  MapperOptions o;
  o.state_dir = "/tmp/" + tooLong;
  const auto state = o.validate();
  ASSERT_FALSE(state.ok());
  EXPECT_NE(state.error().message.find("state_dir: /tmp/" + tooLong + ": "), std::string::npos)
      << state.error().message;
  o.state_dir = "/var/lib/ogf";
  o.services.export_dir = "/tmp/" + tooLong + "/exports";
  const auto exports = o.validate();
  ASSERT_FALSE(exports.ok());
  EXPECT_NE(exports.error().message.find("services.export_dir: /tmp/" + tooLong), std::string::npos)
      << exports.error().message;
}

}  // namespace
}  // namespace ogf::mapper_daemon
