// SPDX-License-Identifier: Apache-2.0
#include "recording/writers/rosbag2_sqlite_writer.h"

#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <stdexcept>

#include "io/config/rosbag2_metadata.h"
#include "io/output_file.h"
#include "io/writers/writers.h"

namespace wallcal::recording {

Rosbag2SqliteWriter::Rosbag2SqliteWriter(const std::string& path, Rosbag2Layout layout)
    : path_(path), layout_(layout) {
  std::string pattern = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) Fail(std::string("cannot create a temporary file: ") + std::strerror(errno));
  ::fchmod(fd, 0644);  // mkstemp makes it 0600; a recording is meant to be read by others
  ::close(fd);         // sqlite opens it again; an empty file is an empty database
  temp_path_ = pattern;
  if (sqlite3_open_v2(temp_path_.c_str(), &db_, SQLITE_OPEN_READWRITE, nullptr) != SQLITE_OK) {
    Fail("cannot open the temporary database");
  }
  // The journal in memory: the file is private until Close() renames it.
  Exec("PRAGMA journal_mode=MEMORY; PRAGMA synchronous=OFF;");
  const bool iron = layout == Rosbag2Layout::kIron;
  Exec(std::string("CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT "
                   "NOT NULL, serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT "
                   "NULL") +
       (iron ? ", type_description_hash TEXT NOT NULL);" : ");"));
  Exec(
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, timestamp "
      "INTEGER NOT NULL, data BLOB NOT NULL);"
      "CREATE INDEX timestamp_idx ON messages (timestamp ASC);");
  if (iron) {
    Exec(
        "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
        "INSERT INTO schema VALUES (4, 'iron');"
        "CREATE TABLE metadata(id INTEGER PRIMARY KEY, metadata_version INTEGER NOT NULL, "
        "metadata TEXT NOT NULL);"
        "CREATE TABLE message_definitions(id INTEGER PRIMARY KEY, topic_type TEXT NOT NULL, "
        "encoding TEXT NOT NULL, encoded_message_definition TEXT NOT NULL, "
        "type_description_hash TEXT NOT NULL);");
  }
  Exec("BEGIN;");
  if (sqlite3_prepare_v2(db_, "INSERT INTO messages(topic_id, timestamp, data) VALUES (?, ?, ?)",
                         -1, &insert_, nullptr) != SQLITE_OK) {
    Fail(std::string("cannot prepare: ") + sqlite3_errmsg(db_));
  }
}

Rosbag2SqliteWriter::~Rosbag2SqliteWriter() {
  sqlite3_finalize(insert_);
  if (db_ != nullptr) {
    sqlite3_close(db_);
    std::remove(temp_path_.c_str());
  }
}

void Rosbag2SqliteWriter::Fail(const std::string& what) {
  sqlite3_finalize(insert_);
  insert_ = nullptr;
  sqlite3_close(db_);
  db_ = nullptr;
  if (!temp_path_.empty()) std::remove(temp_path_.c_str());
  throw io::InputError(io::Where(path_, 0, what));
}

void Rosbag2SqliteWriter::Exec(const std::string& sql) {
  char* error = nullptr;
  if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &error) != SQLITE_OK) {
    const std::string what = error != nullptr ? error : "unknown error";
    sqlite3_free(error);
    Fail("sqlite: " + what);
  }
}

int64_t Rosbag2SqliteWriter::AddTopic(const std::string& name, const std::string& type,
                                      const std::string& definition,
                                      const std::string& serialization_format) {
  const bool iron = layout_ == Rosbag2Layout::kIron;
  const char* sql = iron ? "INSERT INTO topics VALUES (?, ?, ?, ?, '', '')"
                         : "INSERT INTO topics VALUES (?, ?, ?, ?, '')";
  const int64_t id = static_cast<int64_t>(topics_.size()) + 1;
  sqlite3_stmt* stmt = nullptr;
  sqlite3_prepare_v2(db_, sql, -1, &stmt, nullptr);
  sqlite3_bind_int64(stmt, 1, id);
  sqlite3_bind_text(stmt, 2, name.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 3, type.c_str(), -1, SQLITE_TRANSIENT);
  sqlite3_bind_text(stmt, 4, serialization_format.c_str(), -1, SQLITE_TRANSIENT);
  const int rc = sqlite3_step(stmt);
  sqlite3_finalize(stmt);
  if (rc != SQLITE_DONE) Fail(std::string("cannot add topic ") + name + ": " + sqlite3_errmsg(db_));
  if (iron) {
    bool known = false;
    for (const TopicInfo& t : topics_) known = known || t.type == type;
    if (!known) {
      stmt = nullptr;
      sqlite3_prepare_v2(db_,
                         "INSERT INTO message_definitions(topic_type, encoding, "
                         "encoded_message_definition, type_description_hash) VALUES (?, "
                         "'ros2msg', ?, '')",
                         -1, &stmt, nullptr);
      sqlite3_bind_text(stmt, 1, type.c_str(), -1, SQLITE_TRANSIENT);
      sqlite3_bind_text(stmt, 2, definition.c_str(), -1, SQLITE_TRANSIENT);
      const int rc2 = sqlite3_step(stmt);
      sqlite3_finalize(stmt);
      if (rc2 != SQLITE_DONE) Fail(std::string("cannot add a definition: ") + sqlite3_errmsg(db_));
    }
  }
  TopicInfo topic;
  topic.name = name;
  topic.type = type;
  topic.encoding = serialization_format;
  topics_.push_back(topic);
  return id;
}

void Rosbag2SqliteWriter::Write(int64_t topic_id, double stamp_s, const uint8_t* data,
                                size_t size) {
  if (!std::isfinite(stamp_s) || std::fabs(stamp_s) > 9.2e9) {
    throw std::invalid_argument("rosbag2 stamp out of range");
  }
  WriteNs(topic_id, std::llround(stamp_s * 1e9), data, size);
}

void Rosbag2SqliteWriter::WriteNs(int64_t topic_id, int64_t stamp_ns, const uint8_t* data,
                                  size_t size) {
  if (topic_id < 1 || topic_id > static_cast<int64_t>(topics_.size())) {
    throw std::invalid_argument("rosbag2 topic id not added");
  }
  sqlite3_reset(insert_);
  sqlite3_bind_int64(insert_, 1, topic_id);
  sqlite3_bind_int64(insert_, 2, stamp_ns);
  // A zero-length blob must stay a blob (NOT NULL): bind a non-null pointer.
  static const uint8_t kEmpty = 0;
  sqlite3_bind_blob64(insert_, 3, size > 0 ? data : &kEmpty, size, SQLITE_STATIC);
  if (sqlite3_step(insert_) != SQLITE_DONE) {
    Fail(std::string("cannot write a message: ") + sqlite3_errmsg(db_));
  }
  TopicInfo& topic = topics_[static_cast<size_t>(topic_id - 1)];
  const double t_s = static_cast<double>(stamp_ns) * 1e-9;
  topic.first_s = topic.count == 0 ? t_s : std::min(topic.first_s, t_s);
  topic.last_s = topic.count == 0 ? t_s : std::max(topic.last_s, t_s);
  ++topic.count;
}

void Rosbag2SqliteWriter::Close() {
  if (db_ == nullptr) throw std::logic_error("Rosbag2SqliteWriter::Close called twice");
  sqlite3_finalize(insert_);
  insert_ = nullptr;
  Exec("COMMIT;");
  if (sqlite3_close(db_) != SQLITE_OK) Fail("cannot close the database");
  db_ = nullptr;
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    const int error = errno;
    std::remove(temp_path_.c_str());
    throw io::InputError(io::Where(
        path_, 0,
        std::string("cannot rename the temporary file over it: ") + std::strerror(error)));
  }
}

void WriteRosbag2Metadata(const std::string& folder, const std::string& storage_identifier,
                          const std::vector<std::string>& relative_files,
                          const std::vector<TopicInfo>& topics) {
  // The topics' counts and first/last times give message_count, starting_time and duration.
  io::Rosbag2Metadata meta;
  meta.version = 5;
  meta.storage_identifier = storage_identifier;
  meta.relative_file_paths = relative_files;
  int64_t first_ns = 0, last_ns = 0;
  bool any = false;
  for (const TopicInfo& t : topics) {
    meta.topics.push_back({t.name, t.type, t.encoding, t.count});
    if (t.count == 0) continue;
    const int64_t a = std::llround(t.first_s * 1e9), b = std::llround(t.last_s * 1e9);
    first_ns = any ? std::min(first_ns, a) : a;
    last_ns = any ? std::max(last_ns, b) : b;
    any = true;
    meta.message_count += t.count;
  }
  meta.starting_time_ns = first_ns;
  meta.duration_ns = last_ns - first_ns;
  io::WriteFileAtomically(folder + "/metadata.yaml", io::FormatRosbag2Metadata(meta));
}

}  // namespace wallcal::recording
