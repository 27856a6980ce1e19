// SPDX-License-Identifier: Apache-2.0
#pragma once
// A robot recording (ROS 1 bag v2.0, MCAP with the ros2 profile, rosbag2 sqlite3 storage) seen as
// topics and time-ordered messages, whatever the container. No ROS installation is used: each
// container is read from its specification (io/rosbag1_reader.cc, io/mcap_reader.cc,
// io/rosbag2_sqlite_reader.cc).
//
// Errors: a file that is not a recording, a damaged container (bad CRC, a chunk that does not
// decompress, a record cut off) throws io::InputError naming the file, the byte offset (or message
// index for sqlite) and what was expected. A recording cut off after usable data (a crashed
// recorder: no index, no summary, a truncated last chunk) is read as far as it goes, with
// warnings() saying so and counting what was lost.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "recording/ros/ros_messages.h"

namespace wallcal::recording {

enum class RecordingFormat { kRos1Bag, kMcap, kRosbag2Sqlite };
const char* RecordingFormatName(RecordingFormat format);  // "ROS 1 bag", "MCAP", "rosbag2 sqlite3"

enum class ChunkCompression { kNone, kBz2, kLz4, kZstd };

struct TopicInfo {
  std::string name;      // "/scan"
  std::string type;      // as stored: "sensor_msgs/LaserScan" or "sensor_msgs/msg/LaserScan"
  std::string md5sum;    // ROS 1 bags only ("" elsewhere)
  std::string encoding;  // "ros1", "cdr"
  int64_t count = 0;     // messages
  double first_s = 0.0, last_s = 0.0;  // receive (log) time of the first / last message, s
};

struct RecordedMessage {
  const TopicInfo* topic = nullptr;
  WireFormat wire = WireFormat::kCdr;
  double receive_s = 0.0;         // the recorder's receive time, s since the epoch
  const uint8_t* data = nullptr;  // the serialized payload; valid only during the callback
  size_t size = 0;
  int64_t index = 0;         // 0-based index of this message on its topic
  uint64_t file_offset = 0;  // where its record (or chunk) starts in the file; 0 if unknown;
                             // rosbag2 sqlite3: the row's messages.id
};

class Recording {
 public:
  virtual ~Recording() = default;
  virtual RecordingFormat format() const = 0;
  const std::string& path() const { return path_; }
  // Every topic of the recording, sorted by name.
  const std::vector<TopicInfo>& topics() const { return topics_; }
  // Compressions met in the chunks (for inspect).
  const std::set<ChunkCompression>& compressions() const { return compressions_; }
  // What was lost or worked around (no index: records walked; damaged tail: N messages lost).
  const std::vector<std::string>& warnings() const { return warnings_; }

  // Calls `fn` for every message on the named topics, in receive-time order (ties: file order),
  // in one pass over the file. Unknown topic names throw io::InputError listing the topics present.
  virtual void ForEach(const std::set<std::string>& topic_names,
                       const std::function<void(const RecordedMessage&)>& fn) = 0;

 protected:
  std::string path_;
  std::vector<TopicInfo> topics_;
  std::set<ChunkCompression> compressions_;
  std::vector<std::string> warnings_;
};

// True when the file's first bytes are a recording's magic ("#ROSBAG V2.0\n", MCAP's
// "\x89MCAP0\r\n", SQLite's "SQLite format 3\0") or `path` is a rosbag2 folder (a folder
// holding a metadata.yaml or a .db3 or .mcap storage file: one still being recorded has no
// metadata.yaml yet).
bool IsRecording(const std::string& path);

// Opens a recording by content. A rosbag2 folder is read through its metadata.yaml (every
// storage file it lists, in order, then those it does not list) or, without one, from the
// storage files it holds (rosbag2/internal/rosbag2_sqlite_reader.h). Throws io::InputError when
// the file is none of the formats.
std::unique_ptr<Recording> OpenRecording(const std::string& path);

}  // namespace wallcal::recording
