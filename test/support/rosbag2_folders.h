// SPDX-License-Identifier: Apache-2.0
#pragma once
// rosbag2 folders as `ros2 bag record` leaves them while it records, made from a recording
// (a simulated session's session.db3 or session.mcap): its messages split into storage files
// NAME_0, NAME_1, ... of a number of messages each (.db3 or .mcap), then shown as the folder
// stands when a share of them is written. The files before the one being written are whole;
// that one is cut (a .db3 at a row, grown in place as a recorder commits rows; an .mcap at a
// byte, anywhere, appended to); the later ones are not there yet. With metadata, metadata.yaml
// lists the files closed so far (as rosbag2 writes it at a split), all of them at the end.
// Shared by test/recording, test/guide and bench/guide_bench (no GoogleTest here: a failure to
// write throws std::runtime_error). Needs SQLite and wallcal_recording_writers,
// wallcal_io_writers.

#include <sqlite3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/config/session_reader.h"
#include "io/output_file.h"
#include "io/writers/writers.h"
#include "recording/recording.h"
#include "recording/ros/ros_messages.h"
#include "recording/writers/mcap_writer.h"
#include "recording/writers/rosbag2_sqlite_writer.h"

namespace wallcal::testing_support {

enum class Rosbag2Storage { kSqlite3, kMcap };

// A rosbag2 folder written whole.
struct SplitFolder {
  std::filesystem::path folder;
  Rosbag2Storage storage = Rosbag2Storage::kSqlite3;
  std::vector<std::string> files;      // names in split order
  std::vector<int64_t> messages;       // each file's messages
  std::vector<recording::TopicInfo> topics;  // every topic with its count (for metadata.yaml)
  const char* storage_identifier() const {
    return storage == Rosbag2Storage::kMcap ? "mcap" : "sqlite3";
  }
};

// Writes every message of the recording at `source` into folder/<folder name>_<k>.db3 or .mcap
// (zstd chunks of `chunk_bytes`), `per_file` messages each (every file registers every topic,
// as rosbag2 does at a split), and no metadata.yaml.
inline SplitFolder SplitIntoRosbag2Folder(const std::string& source,
                                          const std::filesystem::path& folder,
                                          Rosbag2Storage storage, int64_t per_file,
                                          size_t chunk_bytes = size_t{1} << 20) {
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  SplitFolder split;
  split.folder = folder;
  split.storage = storage;
  std::unique_ptr<recording::Recording> in = recording::OpenRecording(source);
  split.topics = in->topics();
  std::set<std::string> names;
  for (const recording::TopicInfo& t : split.topics) names.insert(t.name);
  std::unique_ptr<recording::Rosbag2SqliteWriter> db3;
  std::unique_ptr<recording::McapWriter> mcap;
  std::vector<int64_t> ids;  // by the topic's place in split.topics
  const auto close = [&] {
    if (db3) db3->Close();
    if (mcap) mcap->Close();
    db3.reset();
    mcap.reset();
  };
  const auto open = [&] {
    const std::string name = folder.filename().string() + "_" +
                             std::to_string(split.files.size()) +
                             (storage == Rosbag2Storage::kMcap ? ".mcap" : ".db3");
    const std::string path = (folder / name).string();
    split.files.push_back(name);
    split.messages.push_back(0);
    ids.clear();
    if (storage == Rosbag2Storage::kMcap) {
      mcap = std::make_unique<recording::McapWriter>(path, recording::ChunkCompression::kZstd,
                                                     chunk_bytes);
    } else {
      db3 = std::make_unique<recording::Rosbag2SqliteWriter>(path, recording::Rosbag2Layout::kIron);
    }
    for (const recording::TopicInfo& t : split.topics) {
      const char* definition = recording::RosTypeDefinition(recording::RosTypeFromName(t.type),
                                                            recording::WireFormat::kCdr);
      ids.push_back(mcap ? mcap->AddChannel(t.name, t.type, definition)
                         : db3->AddTopic(t.name, t.type, definition));
    }
  };
  in->ForEach(names, [&](const recording::RecordedMessage& m) {
    if (split.files.empty() || split.messages.back() == per_file) {
      close();
      open();
    }
    const size_t topic = static_cast<size_t>(
        std::find_if(split.topics.begin(), split.topics.end(),
                     [&](const recording::TopicInfo& t) { return t.name == m.topic->name; }) -
        split.topics.begin());
    const int64_t ns = static_cast<int64_t>(std::llround(m.receive_s * 1e9));
    if (mcap) {
      mcap->WriteNs(static_cast<uint16_t>(ids[topic]), static_cast<uint64_t>(ns),
                    static_cast<uint64_t>(ns), m.data, m.size);
    } else {
      db3->WriteNs(ids[topic], ns, m.data, m.size);
    }
    ++split.messages.back();
  });
  close();
  return split;
}

// The recording at `source` (a simulated session.db3 or session.mcap) split into `files`
// storage files of its own kind: .mcap from an MCAP file, .db3 otherwise.
inline SplitFolder SplitIntoFiles(const std::string& source, const std::filesystem::path& folder,
                                  int files, size_t chunk_bytes = size_t{1} << 20) {
  const std::unique_ptr<recording::Recording> whole = recording::OpenRecording(source);
  int64_t messages = 0;
  for (const recording::TopicInfo& t : whole->topics()) messages += t.count;
  const Rosbag2Storage storage = whole->format() == recording::RecordingFormat::kMcap
                                     ? Rosbag2Storage::kMcap
                                     : Rosbag2Storage::kSqlite3;
  return SplitIntoRosbag2Folder(source, folder, storage, messages / files + 1, chunk_bytes);
}

// Points session.yaml in `session_dir` at `log` for the scans, the GNSS and the heading (their
// topics kept).
inline void PointSessionAt(const std::filesystem::path& session_dir, const std::string& log) {
  io::SessionSpec session = io::ReadSession(session_dir.string());
  session.scanner_log = session.gnss_log = session.heading_log = log;
  io::WriteFileAtomically(session.file, io::FormatSessionYaml(session));
}

// A folder growing into a copy of a SplitFolder, as a recorder writes it.
class GrowingRosbag2Folder {
 public:
  // `growing`: the folder shown (made empty now); `metadata`: metadata.yaml written at each
  // split and at the end.
  GrowingRosbag2Folder(SplitFolder complete, std::filesystem::path growing, bool metadata)
      : complete_(std::move(complete)), growing_(std::move(growing)), metadata_(metadata) {
    for (size_t k = 0; k < complete_.files.size(); ++k) {
      const uint64_t bytes =
          complete_.storage == Rosbag2Storage::kMcap
              ? static_cast<uint64_t>(std::filesystem::file_size(complete_.folder /
                                                                 complete_.files[k]))
              : static_cast<uint64_t>(complete_.messages[k]);
      units_.push_back(bytes);
      total_ += bytes;
    }
    Restart();
  }

  const std::filesystem::path& path() const { return growing_; }

  // The folder removed and made again, empty (a new recording under the same name).
  void Restart() {
    std::filesystem::remove_all(growing_);
    std::filesystem::create_directories(growing_);
    written_.assign(complete_.files.size(), 0);
    listed_ = 0;
  }

  // The folder with `share` (0 to 1) of the messages (.db3) or bytes (.mcap) written. Shares
  // only grow between two Restart()s.
  void WriteUpTo(double share) {
    uint64_t left = static_cast<uint64_t>(std::clamp(share, 0.0, 1.0) * static_cast<double>(total_));
    if (share >= 1.0) left = total_;
    size_t closed = 0;  // files written whole, with a later one begun
    for (size_t k = 0; k < units_.size() && left > 0; ++k) {
      const uint64_t upto = std::min(left, units_[k]);
      Grow(k, upto);
      left -= upto;
      if (upto == units_[k] && (left > 0 || k + 1 == units_.size())) closed = k + 1;
    }
    if (!metadata_) return;
    if (share >= 1.0) closed = units_.size();
    if (closed > listed_) {
      std::vector<std::string> files(complete_.files.begin(),
                                     complete_.files.begin() + static_cast<long>(closed));
      recording::WriteRosbag2Metadata(growing_.string(), complete_.storage_identifier(), files,
                                      complete_.topics);
      listed_ = closed;
    }
  }

 private:
  // File k grown to `upto` units (rows or bytes).
  void Grow(size_t k, uint64_t upto) {
    if (upto <= written_[k]) return;
    const std::filesystem::path from = complete_.folder / complete_.files[k];
    const std::filesystem::path to = growing_ / complete_.files[k];
    if (complete_.storage == Rosbag2Storage::kMcap) {
      std::ifstream in(from, std::ios::binary);
      in.seekg(static_cast<std::streamoff>(written_[k]));
      std::string bytes(upto - written_[k], '\0');
      in.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
      std::ofstream(to, std::ios::binary | std::ios::app)
          .write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    } else {
      CopyRows(from.string(), to.string(), written_[k], upto);
    }
    written_[k] = upto;
  }

  // Rows (first, last] of the complete .db3 into the growing one, in place and in one
  // transaction, as a recorder commits them; the tables and the other rows the first time.
  static void CopyRows(const std::string& from, const std::string& to, uint64_t first,
                       uint64_t last) {
    sqlite3* db = nullptr;
    const auto run = [&db, &to](const std::string& sql) {
      char* error = nullptr;
      if (sqlite3_exec(db, sql.c_str(), nullptr, nullptr, &error) == SQLITE_OK) return;
      const std::string what = error != nullptr ? error : "unknown error";
      sqlite3_free(error);
      sqlite3_close(db);
      throw std::runtime_error(to + ": " + what);
    };
    if (sqlite3_open(to.c_str(), &db) != SQLITE_OK) {
      sqlite3_close(db);
      throw std::runtime_error(to + ": cannot open");
    }
    run("ATTACH DATABASE '" + from + "' AS src");
    std::string sql = "BEGIN;";
    if (first == 0) {
      sqlite3_stmt* schema = nullptr;
      sqlite3_prepare_v2(db, "SELECT type, name, sql FROM src.sqlite_master WHERE sql NOT NULL",
                         -1, &schema, nullptr);
      std::string tables;
      while (sqlite3_step(schema) == SQLITE_ROW) {
        const auto text = [schema](int col) {
          return std::string(reinterpret_cast<const char*>(sqlite3_column_text(schema, col)));
        };
        sql += text(2) + ";";
        if (text(0) == "table" && text(1) != "messages") {
          tables += "INSERT INTO main." + text(1) + " SELECT * FROM src." + text(1) + ";";
        }
      }
      sqlite3_finalize(schema);
      sql += tables;
    }
    sql += "INSERT INTO main.messages SELECT * FROM src.messages WHERE id > " +
           std::to_string(first) + " AND id <= " + std::to_string(last) + "; COMMIT;";
    run(sql);
    sqlite3_close(db);
  }

  SplitFolder complete_;
  std::filesystem::path growing_;
  bool metadata_;
  std::vector<uint64_t> units_;    // each file's rows or bytes
  uint64_t total_ = 0;
  std::vector<uint64_t> written_;  // of each file in the growing folder
  size_t listed_ = 0;              // files metadata.yaml lists
};

}  // namespace wallcal::testing_support
