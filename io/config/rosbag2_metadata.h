// SPDX-License-Identifier: Apache-2.0
#pragma once
// rosbag2's metadata.yaml (a bag folder's index), read and written: which storage files hold
// the recording, in order, and what rosbag2 counted. recording/ opens the folder with it. Keys read
// (versions 4 to 9; other keys are ignored):
//   rosbag2_bagfile_information:
//     version, storage_identifier ("sqlite3" | "mcap"), relative_file_paths: [names],
//     duration: {nanoseconds}, starting_time: {nanoseconds_since_epoch}, message_count,
//     topics_with_message_count: [{topic_metadata: {name, type, serialization_format},
//                                  message_count}],
//     compression_format, compression_mode

#include <cstdint>
#include <string>
#include <vector>

namespace wallcal::io {

struct Rosbag2TopicCount {
  std::string name, type, serialization_format;
  int64_t message_count = 0;
};

struct Rosbag2Metadata {
  int version = 0;
  std::string storage_identifier;                // "sqlite3", "mcap"
  std::vector<std::string> relative_file_paths;  // in recording order
  int64_t starting_time_ns = 0;                  // since the epoch
  int64_t duration_ns = 0;
  int64_t message_count = 0;
  std::vector<Rosbag2TopicCount> topics;
  std::string compression_format, compression_mode;  // "" when not compressed
};

// Parses metadata.yaml text; `name` stands for the file in messages. Throws io::InputError
// "name:line: ..." on YAML errors, a missing rosbag2_bagfile_information map, a missing or empty
// relative_file_paths, a missing storage_identifier, or a value of the wrong kind.
Rosbag2Metadata ParseRosbag2Metadata(const std::string& text, const std::string& name);
Rosbag2Metadata ReadRosbag2Metadata(const std::string& path);

// metadata.yaml as rosbag2 writes it (version 5 keys) from `meta` (its version is written as 5;
// each topic's offered_qos_profiles empty).
std::string FormatRosbag2Metadata(const Rosbag2Metadata& meta);

}  // namespace wallcal::io
