// SPDX-License-Identifier: Apache-2.0
#include "recording/rosbag2/internal/rosbag2_sqlite_reader.h"

#include <sqlite3.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "io/config/rosbag2_metadata.h"
#include "io/types.h"
#include "recording/mcap/internal/mcap_reader.h"
#include "recording/rosbag2/internal/rosbag2_folder.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;

std::string TopicList(const std::vector<TopicInfo>& topics) {
  std::string list;
  for (const TopicInfo& t : topics) list += (list.empty() ? "" : ", ") + t.name;
  return list.empty() ? "none" : list;
}

const TopicInfo* FindTopic(const std::vector<TopicInfo>& topics, const std::string& name) {
  for (const TopicInfo& t : topics) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

// One prepared statement, finalized on scope exit.
class Statement {
 public:
  Statement(sqlite3* db, const std::string& sql, const std::string& path) : db_(db), path_(path) {
    if (sqlite3_prepare_v2(db, sql.c_str(), -1, &stmt_, nullptr) != SQLITE_OK) {
      const int code = sqlite3_errcode(db);
      const std::string what = sqlite3_errmsg(db);
      sqlite3_finalize(stmt_);
      stmt_ = nullptr;
      throw io::InputError(io::Where(path, 0,
                                     code == SQLITE_NOTADB
                                         ? "not an SQLite database; expected a rosbag2 .db3 file"
                                         : "cannot read the rosbag2 database: " + what));
    }
  }
  ~Statement() { sqlite3_finalize(stmt_); }
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;
  // True with a row, false when done; throws on an error (`where`: what was being read).
  bool Step(const std::string& where) {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc == SQLITE_DONE) return false;
    throw io::InputError(io::Where(path_, 0, where + ": " + sqlite3_errmsg(db_)));
  }
  int64_t Int(int col) const { return sqlite3_column_int64(stmt_, col); }
  int Type(int col) const { return sqlite3_column_type(stmt_, col); }
  std::string Text(int col) const {
    const unsigned char* p = sqlite3_column_text(stmt_, col);
    return p != nullptr ? std::string(reinterpret_cast<const char*>(p),
                                      static_cast<size_t>(sqlite3_column_bytes(stmt_, col)))
                        : std::string();
  }
  sqlite3_stmt* get() const { return stmt_; }

 private:
  sqlite3* db_;
  const std::string& path_;
  sqlite3_stmt* stmt_ = nullptr;
};

class Db3Recording : public Recording {
 public:
  explicit Db3Recording(const std::string& path) {
    path_ = path;
    std::ifstream probe(path, std::ios::binary);
    char magic[16] = {};
    probe.read(magic, sizeof magic);
    if (!probe || std::memcmp(magic, "SQLite format 3", 16) != 0) {
      throw io::InputError(io::Where(path, 0,
                                     probe.is_open() ? "not an SQLite database; expected a "
                                                       "rosbag2 .db3 file"
                                                     : "cannot open the file"));
    }
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string what = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw io::InputError(io::Where(path, 0, "cannot open the database: " + what));
    }
    try {
      ReadTopics();
    } catch (...) {
      sqlite3_close(db_);
      throw;
    }
  }
  ~Db3Recording() override { sqlite3_close(db_); }
  Db3Recording(const Db3Recording&) = delete;
  Db3Recording& operator=(const Db3Recording&) = delete;

  RecordingFormat format() const override { return RecordingFormat::kRosbag2Sqlite; }

  void ForEach(const std::set<std::string>& topic_names,
               const std::function<void(const RecordedMessage&)>& fn) override {
    std::string ids;
    for (const std::string& name : topic_names) {
      const TopicInfo* topic = FindTopic(topics_, name);
      if (topic == nullptr) {
        throw io::InputError(path_ + ": no topic " + name +
                             " in the recording (topics: " + TopicList(topics_) + ")");
      }
      if (topic->encoding != "cdr") {
        throw io::InputError(path_ + ": topic " + name + " is serialized as '" + topic->encoding +
                             "'; only 'cdr' (ROS 2) messages are read");
      }
      for (const auto& kv : slot_of_id_) {
        if (&topics_[kv.second] == topic)
          ids += (ids.empty() ? "" : ",") + std::to_string(kv.first);
      }
    }
    if (ids.empty()) return;
    Statement rows(db_,
                   "SELECT id, topic_id, timestamp, data FROM messages WHERE topic_id IN (" + ids +
                       ") ORDER BY timestamp, id",
                   path_);
    std::vector<int64_t> emitted(topics_.size(), 0);
    int64_t last_id = 0;
    while (rows.Step("reading the messages after message id " + std::to_string(last_id))) {
      last_id = rows.Int(0);
      const auto slot = slot_of_id_.find(rows.Int(1));
      if (slot == slot_of_id_.end()) continue;  // cannot happen: the query selects these ids
      const int data_type = rows.Type(3);
      if (rows.Type(2) != SQLITE_INTEGER ||
          (data_type != SQLITE_BLOB && data_type != SQLITE_TEXT)) {
        throw io::InputError(path_ + ": message id " + std::to_string(last_id) +
                             ": expected an integer timestamp (ns) and a data blob");
      }
      RecordedMessage message;
      message.topic = &topics_[slot->second];
      message.wire = WireFormat::kCdr;
      message.receive_s = static_cast<double>(rows.Int(2)) * 1e-9;
      message.data = static_cast<const uint8_t*>(sqlite3_column_blob(rows.get(), 3));
      message.size = static_cast<size_t>(sqlite3_column_bytes(rows.get(), 3));
      message.index = emitted[slot->second]++;
      message.file_offset = static_cast<uint64_t>(last_id);
      fn(message);
    }
  }

 private:
  void ReadTopics() {
    std::set<std::string> tables;
    {
      Statement list(db_, "SELECT name FROM sqlite_master WHERE type = 'table'", path_);
      while (list.Step("listing the tables")) tables.insert(list.Text(0));
    }
    for (const char* needed : {"topics", "messages"}) {
      if (tables.count(needed) == 0) {
        throw io::InputError(io::Where(path_, 0,
                                       std::string("no '") + needed +
                                           "' table: not a rosbag2 "
                                           "database (expected tables topics and messages)"));
      }
    }
    std::map<int64_t, TopicInfo> by_id;
    {
      Statement rows(db_, "SELECT id, name, type, serialization_format FROM topics", path_);
      while (rows.Step("reading the topics table")) {
        TopicInfo topic;
        topic.name = rows.Text(1);
        topic.type = rows.Text(2);
        topic.encoding = rows.Text(3);
        if (topic.name.empty()) {
          throw io::InputError(
              io::Where(path_, 0, "topic id " + std::to_string(rows.Int(0)) + " has no name"));
        }
        by_id[rows.Int(0)] = topic;
      }
    }
    {
      Statement rows(db_,
                     "SELECT topic_id, COUNT(*), MIN(timestamp), MAX(timestamp) FROM messages "
                     "GROUP BY topic_id",
                     path_);
      while (rows.Step("counting the messages")) {
        const auto it = by_id.find(rows.Int(0));
        if (it == by_id.end()) {
          warnings_.push_back(path_ + ": " + std::to_string(rows.Int(1)) +
                              " messages name topic id " + std::to_string(rows.Int(0)) +
                              ", which the topics table lacks: they are not read");
          continue;
        }
        it->second.count = rows.Int(1);
        it->second.first_s = static_cast<double>(rows.Int(2)) * 1e-9;
        it->second.last_s = static_cast<double>(rows.Int(3)) * 1e-9;
      }
    }
    // Sorted by name; a name used by two topic ids (a topic re-created with other QoS) is one
    // topic for the reader.
    std::map<std::string, std::vector<int64_t>> ids_of_name;
    for (const auto& kv : by_id) ids_of_name[kv.second.name].push_back(kv.first);
    for (const auto& kv : ids_of_name) {
      TopicInfo merged = by_id[kv.second.front()];
      for (size_t i = 1; i < kv.second.size(); ++i) {
        const TopicInfo& other = by_id[kv.second[i]];
        if (other.count == 0) continue;
        merged.first_s =
            merged.count == 0 ? other.first_s : std::min(merged.first_s, other.first_s);
        merged.last_s = merged.count == 0 ? other.last_s : std::max(merged.last_s, other.last_s);
        merged.count += other.count;
      }
      for (int64_t id : kv.second) slot_of_id_[id] = topics_.size();
      topics_.push_back(merged);
    }
  }

  sqlite3* db_ = nullptr;
  std::map<int64_t, size_t> slot_of_id_;  // topics.id -> index in topics_
};

// A rosbag2 folder: its storage files read one after the other.
class SplitRecording : public Recording {
 public:
  SplitRecording(const std::string& folder, std::vector<std::unique_ptr<Recording>> parts)
      : parts_(std::move(parts)) {
    path_ = folder;
    std::map<std::string, TopicInfo> merged;
    double previous_last_s = 0.0;
    for (size_t p = 0; p < parts_.size(); ++p) {
      const Recording& part = *parts_[p];
      for (const std::string& w : part.warnings()) warnings_.push_back(w);
      compressions_.insert(part.compressions().begin(), part.compressions().end());
      double first_s = 0.0, last_s = 0.0;
      bool any = false;
      for (const TopicInfo& t : part.topics()) {
        const auto [it, inserted] = merged.emplace(t.name, t);
        TopicInfo& m = it->second;
        if (!inserted && m.type != t.type) {
          warnings_.push_back(part.path() + ": topic " + t.name + " has type " + t.type +
                              " here, " + m.type + " in an earlier file");
        }
        if (t.count == 0) continue;
        if (!inserted) {
          m.first_s = m.count == 0 ? t.first_s : std::min(m.first_s, t.first_s);
          m.last_s = m.count == 0 ? t.last_s : std::max(m.last_s, t.last_s);
          m.count += t.count;
        }
        first_s = any ? std::min(first_s, t.first_s) : t.first_s;
        last_s = any ? std::max(last_s, t.last_s) : t.last_s;
        any = true;
      }
      if (any && p > 0 && first_s < previous_last_s) {
        warnings_.push_back(part.path() +
                            ": starts before the previous file ends: messages at "
                            "the seam are passed on in file order, not time order");
      }
      if (any) previous_last_s = std::max(previous_last_s, last_s);
    }
    for (auto& kv : merged) topics_.push_back(kv.second);
  }

  RecordingFormat format() const override { return parts_.front()->format(); }
  void AddWarning(std::string warning) { warnings_.push_back(std::move(warning)); }

  void ForEach(const std::set<std::string>& topic_names,
               const std::function<void(const RecordedMessage&)>& fn) override {
    for (const std::string& name : topic_names) {
      if (FindTopic(topics_, name) == nullptr) {
        throw io::InputError(path_ + ": no topic " + name +
                             " in the recording (topics: " + TopicList(topics_) + ")");
      }
    }
    std::map<const TopicInfo*, int64_t> emitted;
    for (const auto& part : parts_) {
      std::set<std::string> here;
      for (const std::string& name : topic_names) {
        if (FindTopic(part->topics(), name) != nullptr) here.insert(name);
      }
      if (here.empty()) continue;
      part->ForEach(here, [&](const RecordedMessage& m) {
        RecordedMessage out = m;
        out.topic = FindTopic(topics_, m.topic->name);
        out.index = emitted[out.topic]++;
        fn(out);
      });
    }
  }

 private:
  std::vector<std::unique_ptr<Recording>> parts_;
};

bool HasMcapMagic(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[8] = {};
  in.read(magic, sizeof magic);
  return in && std::memcmp(magic, "\x89MCAP0\r\n", 8) == 0;
}

std::unique_ptr<Recording> OpenStorageFile(const std::string& path) {
  if (HasMcapMagic(path)) return OpenMcap(path);
  return std::make_unique<Db3Recording>(path);
}

std::unique_ptr<Recording> OpenFolder(const std::string& folder) {
  const Rosbag2Files found = FindRosbag2Files(folder);
  const std::vector<std::string>& files = found.paths;
  const std::string meta_path = (fs::path(folder) / "metadata.yaml").string();
  const io::Rosbag2Metadata& meta = found.metadata;
  std::vector<std::string> notes;
  if (!found.has_metadata) {
    if (files.empty()) {
      throw io::InputError(io::Where(folder, 0,
                                     "neither a metadata.yaml nor .db3/.mcap files: not a "
                                     "rosbag2 folder"));
    }
    notes.push_back(folder + ": no metadata.yaml (the recorder did not finish?): read the " +
                    std::to_string(files.size()) + " storage files found, in name order");
  } else if (static_cast<size_t>(found.listed) < files.size()) {
    std::string names;
    for (size_t i = static_cast<size_t>(found.listed); i < files.size(); ++i) {
      names += (names.empty() ? "" : ", ") + fs::path(files[i]).filename().string();
    }
    notes.push_back(meta_path + ": does not list " + names +
                    " (the recorder went on after writing it?): read after the files it lists");
  }
  std::vector<std::unique_ptr<Recording>> parts;
  for (const std::string& f : files) parts.push_back(OpenStorageFile(f));
  auto recording = std::make_unique<SplitRecording>(folder, std::move(parts));
  std::vector<std::string> warnings = notes;
  for (const io::Rosbag2TopicCount& c : meta.topics) {
    const TopicInfo* topic = FindTopic(recording->topics(), c.name);
    const int64_t held = topic != nullptr ? topic->count : 0;
    if (held != c.message_count) {
      warnings.push_back(meta_path + ": counts " + std::to_string(c.message_count) +
                         " messages on " + c.name + ", the storage files hold " +
                         std::to_string(held));
    }
  }
  for (std::string& w : warnings) recording->AddWarning(std::move(w));
  return recording;
}

}  // namespace

std::unique_ptr<Recording> OpenRosbag2(const std::string& path) {
  std::error_code ec;
  if (fs::is_directory(path, ec)) return OpenFolder(path);
  return OpenStorageFile(path);
}

}  // namespace wallcal::recording
