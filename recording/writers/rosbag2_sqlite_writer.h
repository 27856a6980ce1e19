// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes rosbag2 sqlite3 storage files (.db3) for tests and the simulator, in the layout of a
// ROS 2 release: Humble (tables topics and messages only) or Iron and later (topics with
// type_description_hash, messages, message_definitions with the ros2msg text, schema, metadata).
// The file is built under a temporary name in the same folder and renamed by Close().

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "recording/recording.h"

struct sqlite3;
struct sqlite3_stmt;

namespace wallcal::recording {

enum class Rosbag2Layout { kHumble, kIron };

class Rosbag2SqliteWriter {
 public:
  // Throws io::InputError naming `path` when the file cannot be created.
  Rosbag2SqliteWriter(const std::string& path, Rosbag2Layout layout);
  // Without Close(), the temporary file is removed and `path` is left untouched.
  ~Rosbag2SqliteWriter();
  Rosbag2SqliteWriter(const Rosbag2SqliteWriter&) = delete;
  Rosbag2SqliteWriter& operator=(const Rosbag2SqliteWriter&) = delete;

  // A topic ("/scan", "sensor_msgs/msg/LaserScan", its ros2msg definition: stored in
  // message_definitions by the Iron layout). Returns topics.id (from 1).
  int64_t AddTopic(const std::string& name, const std::string& type, const std::string& definition,
                   const std::string& serialization_format = "cdr");
  // One serialized message; stamp in s since the epoch, stored as ns.
  void Write(int64_t topic_id, double stamp_s, const uint8_t* data, size_t size);
  void Write(int64_t topic_id, double stamp_s, const std::vector<uint8_t>& payload) {
    Write(topic_id, stamp_s, payload.data(), payload.size());
  }
  void WriteNs(int64_t topic_id, int64_t stamp_ns, const uint8_t* data, size_t size);
  // Commits and renames the file to `path`. Throws io::InputError naming `path` on failure.
  void Close();

  // The topics written so far with their counts and first/last stamps (for metadata.yaml).
  const std::vector<TopicInfo>& topics() const { return topics_; }

 private:
  void Exec(const std::string& sql);
  [[noreturn]] void Fail(const std::string& what);

  std::string path_, temp_path_;
  Rosbag2Layout layout_;
  sqlite3* db_ = nullptr;
  sqlite3_stmt* insert_ = nullptr;
  std::vector<TopicInfo> topics_;
};

// Writes <folder>/metadata.yaml (atomically) naming the storage files, relative to the folder
// and in order, and the topics with their counts (e.g. the writers' topics(), merged).
void WriteRosbag2Metadata(const std::string& folder, const std::string& storage_identifier,
                          const std::vector<std::string>& relative_files,
                          const std::vector<TopicInfo>& topics);

}  // namespace wallcal::recording
