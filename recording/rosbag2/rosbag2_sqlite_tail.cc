// SPDX-License-Identifier: Apache-2.0
// A rosbag2 sqlite3 storage file (.db3) read on as it is written (recording/recording_tail.h):
// each read takes the rows of `messages` after the last id read, ordered by timestamp (ties:
// id) within the read (read in id order when that is their timestamp order, as a recorder
// writes them; sorted otherwise); the rows on other topics are counted, their data not read.
// The database is opened read-only for each read, so SQLite shows the rows committed by then; a
// transaction still open is read next time. The byte offsets of a TailRead are the file's sizes
// (where the last read stopped: the size it saw).

#include <sqlite3.h>

#include <algorithm>
#include <map>
#include <set>
#include <string>

#include "io/types.h"
#include "recording/internal/file_tail.h"
#include "recording/rosbag2/internal/rosbag2_sqlite_reader.h"

namespace wallcal::recording {
namespace {

// The database, read-only, closed on scope exit.
class Database {
 public:
  explicit Database(const std::string& path) : path_(path) {
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READONLY, nullptr) != SQLITE_OK) {
      const std::string what = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
      sqlite3_close(db_);
      throw io::InputError(io::Where(path, 0, "cannot open the rosbag2 database: " + what));
    }
  }
  ~Database() { sqlite3_close(db_); }
  Database(const Database&) = delete;
  Database& operator=(const Database&) = delete;
  sqlite3* get() const { return db_; }
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  sqlite3* db_ = nullptr;
};

// One prepared statement, finalized on scope exit.
class Query {
 public:
  Query(const Database& db, const char* sql) : db_(db) {
    if (sqlite3_prepare_v2(db.get(), sql, -1, &stmt_, nullptr) != SQLITE_OK) Fail("preparing");
  }
  ~Query() { sqlite3_finalize(stmt_); }
  Query(const Query&) = delete;
  Query& operator=(const Query&) = delete;
  bool Step() {
    const int rc = sqlite3_step(stmt_);
    if (rc == SQLITE_ROW) return true;
    if (rc != SQLITE_DONE) Fail("reading");
    return false;
  }
  sqlite3_stmt* get() const { return stmt_; }
  int64_t Int(int col) const { return sqlite3_column_int64(stmt_, col); }
  std::string Text(int col) const {
    const unsigned char* text = sqlite3_column_text(stmt_, col);
    return text != nullptr ? reinterpret_cast<const char*>(text) : "";
  }

 private:
  [[noreturn]] void Fail(const char* doing) const {
    throw io::InputError(io::Where(db_.path(), 0,
                                   std::string(doing) + " the rosbag2 database: " +
                                       sqlite3_errmsg(db_.get()) +
                                       "; expected the tables topics and messages"));
  }
  const Database& db_;
  sqlite3_stmt* stmt_ = nullptr;
};

class SqliteTail : public FileTail {
 public:
  explicit SqliteTail(std::string path) : FileTail(std::move(path)) {}
  RecordingFormat format() const override { return RecordingFormat::kRosbag2Sqlite; }

 protected:
  void Reset() override {
    last_id_ = 0;
    topic_of_id_.clear();
  }
  uint64_t Walk(uint64_t, uint64_t file_bytes, const std::set<std::string>& topic_names,
                const MessageFn& fn) override {
    const Database db(path_);
    // One read transaction: the topics and the rows as one commit left them (a topic and its
    // first messages committed between two queries would otherwise be passed over).
    Query(db, "BEGIN").Step();
    {
      Query topics(db, "SELECT id, name, type, serialization_format FROM topics");
      while (topics.Step()) {
        const int64_t id = topics.Int(0);
        if (topic_of_id_.count(id) > 0) continue;
        topic_of_id_[id] = Topic(topics.Text(1), topics.Text(2), "", topics.Text(3));
      }
    }
    std::set<int64_t> wanted;
    std::string wanted_list;  // "1,3" for the query
    for (const auto& [id, topic] : topic_of_id_) {
      if (topic_names.count(topic->name) == 0 || topic->encoding != "cdr") continue;
      wanted.insert(id);
      wanted_list += (wanted_list.empty() ? "" : ",") + std::to_string(id);
    }
    // The rows gained, in id order without their data: the other topics' counted, the last id
    // read, and whether the wanted ones are in timestamp order already (a recorder writes them
    // as they come), so that the second query reads their data without sorting it.
    int64_t last_id = last_id_;
    bool any = false, in_order = true;
    int64_t last_stamp = 0;
    {
      Query rows(db, "SELECT id, topic_id, timestamp FROM messages WHERE id > ?1 ORDER BY id");
      sqlite3_bind_int64(rows.get(), 1, last_id_);
      while (rows.Step()) {
        last_id = rows.Int(0);
        const auto topic = topic_of_id_.find(rows.Int(1));
        // Rows naming a topic id the topics table lacks are not read (as OpenRosbag2 does).
        if (topic == topic_of_id_.end()) continue;
        if (wanted.count(topic->first) == 0) {
          ++topic->second->count;
          continue;
        }
        const int64_t stamp = rows.Int(2);
        in_order = in_order && (!any || stamp >= last_stamp);
        last_stamp = stamp;
        any = true;
      }
    }
    if (any) {
      Query rows(db, ("SELECT id, topic_id, timestamp, data FROM messages WHERE id > ?1 AND "
                      "id <= ?2 AND topic_id IN (" + wanted_list + ") ORDER BY " +
                      (in_order ? "id" : "timestamp, id"))
                         .c_str());
      sqlite3_bind_int64(rows.get(), 1, last_id_);
      sqlite3_bind_int64(rows.get(), 2, last_id);
      while (rows.Step()) Emit(rows, fn);
    }
    Query(db, "COMMIT").Step();
    last_id_ = last_id;
    return file_bytes;
  }

 private:
  void Emit(const Query& row, const MessageFn& fn) {
    TopicInfo* topic = topic_of_id_.at(row.Int(1));
    const int data_type = sqlite3_column_type(row.get(), 3);
    if (sqlite3_column_type(row.get(), 2) != SQLITE_INTEGER ||
        (data_type != SQLITE_BLOB && data_type != SQLITE_TEXT)) {
      throw io::InputError(io::Where(path_, 0,
                                     "message id " + std::to_string(row.Int(0)) +
                                         ": expected an integer timestamp (ns) and a data blob"));
    }
    RecordedMessage message;
    message.topic = topic;
    message.wire = WireFormat::kCdr;
    message.receive_s = static_cast<double>(row.Int(2)) * 1e-9;
    message.data = static_cast<const uint8_t*>(sqlite3_column_blob(row.get(), 3));
    message.size = static_cast<size_t>(sqlite3_column_bytes(row.get(), 3));
    message.index = topic->count++;
    message.file_offset = static_cast<uint64_t>(row.Int(0));
    fn(message);
  }

  int64_t last_id_ = 0;  // the largest messages.id read
  std::map<int64_t, TopicInfo*> topic_of_id_;
};

}  // namespace

std::unique_ptr<RecordingTail> OpenRosbag2SqliteTail(const std::string& path) {
  return std::make_unique<SqliteTail>(path);
}

}  // namespace wallcal::recording
