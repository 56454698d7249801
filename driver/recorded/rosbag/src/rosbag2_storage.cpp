#include "ogf/rosbag/rosbag2_storage.hpp"

#include <fmt/format.h>
#include <sqlite3.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <array>
#include <fstream>
#include <memory>

#include "ogf/mcap/mcap_reader.hpp"

namespace ogf::rosbag {
namespace {

namespace fs = std::filesystem;

struct CloseDatabase {
  void operator()(sqlite3* db) const { sqlite3_close(db); }
};
struct FinalizeStatement {
  void operator()(sqlite3_stmt* s) const { sqlite3_finalize(s); }
};
using Database = std::unique_ptr<sqlite3, CloseDatabase>;
using Statement = std::unique_ptr<sqlite3_stmt, FinalizeStatement>;

Result<Database> openDatabase(const fs::path& file) {
  std::error_code ec;
  if (!fs::is_regular_file(file, ec)) return Error{fmt::format("{}: no such file", file.string())};
  sqlite3* raw = nullptr;
  const int rc = sqlite3_open_v2(file.c_str(), &raw, SQLITE_OPEN_READONLY, nullptr);
  Database db(raw);
  if (rc != SQLITE_OK)
    return Error{
        fmt::format("{}: cannot open: {}", file.string(), raw ? sqlite3_errmsg(raw) : sqlite3_errstr(rc))};
  return db;
}

Result<Statement> prepare(sqlite3* db, const fs::path& file, const std::string& sql) {
  sqlite3_stmt* raw = nullptr;
  if (sqlite3_prepare_v2(db, sql.c_str(), -1, &raw, nullptr) != SQLITE_OK) {
    Statement guard(raw);
    return Error{fmt::format("{}: not a rosbag2 sqlite3 file ({})", file.string(), sqlite3_errmsg(db))};
  }
  return Statement(raw);
}

std::string text(sqlite3_stmt* s, int column) {
  const unsigned char* t = sqlite3_column_text(s, column);
  return t ? std::string(reinterpret_cast<const char*>(t)) : std::string();
}

Error stepError(sqlite3* db, const fs::path& file, const char* doing) {
  return Error{fmt::format("{}: {}: {}", file.string(), doing, sqlite3_errmsg(db))};
}

// Every *.db3 and *.mcap of `dir`, shortest name first then by name, so x_2.db3 comes before x_10.db3.
std::vector<fs::path> globBagFiles(const fs::path& dir) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec))
    if (entry.path().extension() == ".db3" || entry.path().extension() == ".mcap")
      found.push_back(entry.path());
  std::sort(found.begin(), found.end(), [](const fs::path& a, const fs::path& b) {
    const auto an = a.filename().string(), bn = b.filename().string();
    return an.size() != bn.size() ? an.size() < bn.size() : an < bn;
  });
  return found;
}

// Whether `file` starts as an MCAP file does (rosbag2 names them .mcap, but the bytes decide).
bool isMcapFile(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::array<char, mcap::kMagic.size()> head{};
  if (!in.read(head.data(), head.size())) return false;
  return std::equal(head.begin(), head.end(), mcap::kMagic.begin(),
                    [](char a, std::uint8_t b) { return static_cast<std::uint8_t>(a) == b; });
}

// The files metadata.yaml lists, after checking that the bag is one this reader can read.
Result<std::vector<fs::path>> filesFromMetadata(const fs::path& dir, const fs::path& metadata) {
  const std::string where = metadata.string();
  try {
    const YAML::Node root = YAML::LoadFile(metadata.string());
    const YAML::Node info = root["rosbag2_bagfile_information"];
    if (!info || !info.IsMap()) return Error{where + ": no rosbag2_bagfile_information map"};
    if (const YAML::Node storage = info["storage_identifier"];
        storage && storage.as<std::string>() != "sqlite3" && storage.as<std::string>() != "mcap")
      return Error{fmt::format("{}: storage_identifier is '{}': only sqlite3 and mcap bags are read", where,
                               storage.as<std::string>())};
    if (const YAML::Node c = info["compression_format"]; c && !c.as<std::string>().empty())
      return Error{fmt::format("{}: compressed bag ({}): decompress it first (ros2 bag convert)", where,
                               c.as<std::string>())};
    const YAML::Node paths = info["relative_file_paths"];
    if (!paths || !paths.IsSequence() || paths.size() == 0)
      return Error{where + ": relative_file_paths lists no file"};
    std::vector<fs::path> files;
    for (const YAML::Node& p : paths) {
      const fs::path relative = p.as<std::string>();
      fs::path file = dir / relative;
      // Bags of early rosbag2 versions list the files with the bag folder's name in front.
      if (std::error_code ec; !fs::exists(file, ec) && fs::exists(dir / relative.filename(), ec))
        file = dir / relative.filename();
      if (std::error_code ec; !fs::is_regular_file(file, ec))
        return Error{
            fmt::format("{}: listed in {} but missing", file.string(), metadata.filename().string())};
      files.push_back(file);
    }
    return files;
  } catch (const YAML::Exception& e) {
    return Error{fmt::format("{}:{}: {}", where, e.mark.line + 1, e.msg)};
  }
}

// The subfolders of `dir` that look like bags (a metadata.yaml, a .db3 or an .mcap file in them), by name.
std::vector<fs::path> bagSubfolders(const fs::path& dir) {
  std::vector<fs::path> found;
  std::error_code ec;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    std::error_code sub_ec;
    if (!entry.is_directory(sub_ec)) continue;
    if (fs::exists(entry.path() / "metadata.yaml", sub_ec) || !globBagFiles(entry.path()).empty())
      found.push_back(entry.path());
  }
  std::sort(found.begin(), found.end());
  return found;
}

}  // namespace

Result<Rosbag2Storage> Rosbag2Storage::open(const fs::path& path) {
  Rosbag2Storage bag;
  bag.path_ = path;
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) {
    bag.files_ = {path};
  } else if (!fs::is_directory(path, ec)) {
    return Error{fmt::format("{}: no such bag folder", path.string())};
  } else if (const fs::path metadata = path / "metadata.yaml"; fs::exists(metadata, ec)) {
    auto files = filesFromMetadata(path, metadata);
    if (!files) return files.error();
    bag.files_ = std::move(*files);
  } else {
    bag.files_ = globBagFiles(path);
    if (bag.files_.empty()) {
      // The folder above a bag (ros2 bag record names the bag's folder after the time): the one bag inside.
      const std::vector<fs::path> inside = bagSubfolders(path);
      if (inside.size() == 1) {
        auto inner = open(inside.front());
        if (inner) inner->searched_folder_ = path;
        return inner;
      }
      if (inside.empty())
        return Error{
            fmt::format("{}: no metadata.yaml, no .db3 or .mcap file and no subfolder holding one: not a "
                        "rosbag2 bag",
                        path.string())};
      std::string names;
      for (const fs::path& p : inside) names += (names.empty() ? "" : ", ") + p.filename().string();
      return Error{fmt::format(
          "{}: no metadata.yaml and no .db3 or .mcap file; {} subfolders hold bags ({}): give one "
          "of them",
          path.string(), inside.size(), names)};
    }
  }

  for (const fs::path& file : bag.files_) {
    auto st = isMcapFile(file) ? bag.openMcap(file) : bag.openSqlite(file);
    if (!st) return st.error();
  }
  return bag;
}

Status Rosbag2Storage::addTopic(BagTopic t, std::int64_t id, const fs::path& file) {
  auto known =
      std::find_if(topics_.begin(), topics_.end(), [&](const BagTopic& k) { return k.name == t.name; });
  if (known == topics_.end()) {
    topics_.push_back(std::move(t));
    known = topics_.end() - 1;
  } else if (known->type != t.type) {
    return Error{fmt::format("{}: topic {} has type {} here and {} in an earlier file", file.string(), t.name,
                             t.type, known->type)};
  } else {
    known->message_count += t.message_count;
  }
  file_topics_.back().emplace_back(id, static_cast<std::size_t>(known - topics_.begin()));
  return okStatus();
}

Status Rosbag2Storage::openSqlite(const fs::path& file) {
  mcap_files_.push_back(nullptr);
  file_topics_.emplace_back();
  auto db = openDatabase(file);
  if (!db) return db.error();
  auto topics = prepare(db->get(), file, "SELECT id, name, type, serialization_format FROM topics");
  if (!topics) return topics.error();
  int rc;
  while ((rc = sqlite3_step(topics->get())) == SQLITE_ROW) {
    BagTopic t{text(topics->get(), 1), text(topics->get(), 2), text(topics->get(), 3), 0};
    if (auto st = addTopic(std::move(t), sqlite3_column_int64(topics->get(), 0), file); !st) return st;
  }
  if (rc != SQLITE_DONE) return stepError(db->get(), file, "reading table topics");
  auto counts = prepare(db->get(), file, "SELECT topic_id, COUNT(*) FROM messages GROUP BY topic_id");
  if (!counts) return counts.error();
  const auto& ids = file_topics_.back();
  while ((rc = sqlite3_step(counts->get())) == SQLITE_ROW) {
    const std::int64_t id = sqlite3_column_int64(counts->get(), 0);
    const auto it = std::find_if(ids.begin(), ids.end(), [&](const auto& p) { return p.first == id; });
    if (it != ids.end()) topics_[it->second].message_count += sqlite3_column_int64(counts->get(), 1);
  }
  if (rc != SQLITE_DONE) return stepError(db->get(), file, "counting messages");
  return okStatus();
}

Status Rosbag2Storage::openMcap(const fs::path& file) {
  auto reader = mcap::McapReader::open(file);
  if (!reader) return reader.error();
  auto shared = std::make_shared<const mcap::McapReader>(std::move(*reader));
  mcap_files_.push_back(shared);
  file_topics_.emplace_back();
  for (const mcap::ChannelInfo& c : shared->channels()) {
    BagTopic t{c.topic, c.schema_name, c.message_encoding, static_cast<std::int64_t>(c.message_count)};
    if (auto st = addTopic(std::move(t), c.id, file); !st) return st;
  }
  return okStatus();
}

std::string BagMessage::where() const {
  if (!in_mcap) return fmt::format("message {}", id);
  if (chunk_offset == 0) return fmt::format("the message at byte {}", record_offset);
  return fmt::format("the message at byte {} of the chunk at byte {}", record_offset, chunk_offset);
}

std::string Rosbag2Storage::whereFound() const {
  if (searched_folder_.empty()) return {};
  return fmt::format("{} holds no bag itself; reading the bag in its subfolder {}", searched_folder_.string(),
                     path_.string());
}

const BagTopic* Rosbag2Storage::topic(std::string_view name) const {
  for (const BagTopic& t : topics_)
    if (t.name == name) return &t;
  return nullptr;
}

std::vector<const BagTopic*> Rosbag2Storage::topicsOfType(std::string_view type) const {
  std::vector<const BagTopic*> out;
  for (const BagTopic& t : topics_)
    if (t.type == type) out.push_back(&t);
  return out;
}

Status Rosbag2Storage::forEachMessage(const std::vector<std::string>& topic_names,
                                      const std::function<void(const BagMessage&)>& visit,
                                      const std::function<void(const std::string&)>& damaged) const {
  for (std::size_t f = 0; f < files_.size(); ++f) {
    const fs::path& file = files_[f];
    if (mcap_files_[f]) {
      std::set<std::uint16_t> channels;
      for (const auto& [id, index] : file_topics_[f])
        if (std::find(topic_names.begin(), topic_names.end(), topics_[index].name) != topic_names.end())
          channels.insert(static_cast<std::uint16_t>(id));
      if (channels.empty()) continue;
      const auto& ids = file_topics_[f];
      auto st = mcap_files_[f]->forEachMessage(
          channels,
          [&](const mcap::MessageView& v) {
            const auto it =
                std::find_if(ids.begin(), ids.end(), [&](const auto& p) { return p.first == v.channel->id; });
            BagMessage m;
            m.topic = &topics_[it->second];
            m.file = &file;
            m.timestamp_ns = static_cast<std::int64_t>(v.log_time);
            m.data = v.data;
            m.in_mcap = true;
            m.chunk_offset = v.chunk_offset;
            m.record_offset = v.record_offset;
            visit(m);
          },
          [&](const std::string& what) {
            if (reported_->insert(what).second && damaged) damaged(what);
          });
      if (!st) return st;
      continue;
    }
    // The topic ids of this file wanted, as integers in the query (no text from the bag goes into SQL).
    std::string wanted;
    for (const auto& [id, index] : file_topics_[f]) {
      if (std::find(topic_names.begin(), topic_names.end(), topics_[index].name) == topic_names.end())
        continue;
      wanted += (wanted.empty() ? "" : ",") + std::to_string(id);
    }
    if (wanted.empty()) continue;
    auto db = openDatabase(file);
    if (!db) return db.error();
    auto rows = prepare(db->get(), file,
                        "SELECT id, topic_id, timestamp, data FROM messages WHERE topic_id IN (" + wanted +
                            ") ORDER BY timestamp, id");
    if (!rows) return rows.error();
    sqlite3_stmt* s = rows->get();
    int rc;
    while ((rc = sqlite3_step(s)) == SQLITE_ROW) {
      const std::int64_t topic_id = sqlite3_column_int64(s, 1);
      const auto it = std::find_if(file_topics_[f].begin(), file_topics_[f].end(),
                                   [&](const auto& p) { return p.first == topic_id; });
      if (it == file_topics_[f].end()) continue;
      const auto* bytes = static_cast<const std::uint8_t*>(sqlite3_column_blob(s, 3));
      const int size = sqlite3_column_bytes(s, 3);
      BagMessage m;
      m.topic = &topics_[it->second];
      m.file = &file;
      m.id = sqlite3_column_int64(s, 0);
      m.timestamp_ns = sqlite3_column_int64(s, 2);
      if (bytes != nullptr && size > 0)
        m.data = std::span<const std::uint8_t>(bytes, static_cast<std::size_t>(size));
      visit(m);
    }
    if (rc != SQLITE_DONE) return stepError(db->get(), file, "reading table messages");
  }
  return okStatus();
}

}  // namespace ogf::rosbag
