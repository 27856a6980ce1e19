// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes ROS 1 bags, format v2.0, as rosbag does: the bag header (padded to 4096 bytes, with the
// index position filled in at Close), chunks of about `chunk_bytes` uncompressed bytes
// (compression none, bz2, or lz4 frames readable by roslz4), each followed by its index-data
// records, then the connection and chunk-info records the bag header points to.
//
// The bag is written to "<path>.part" and renamed to `path` by Close(): a writer destroyed
// without Close() (an exception on the way) removes the partial file and leaves no bag behind.
// Errors writing the file throw io::InputError naming it.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "recording/recording.h"
#include "recording/ros/ros_messages.h"

namespace wallcal::recording {

class Ros1BagWriter {
 public:
  // rosbag's default chunk threshold.
  static constexpr size_t kDefaultChunkBytes = 768 * 1024;

  // compression: kNone, kBz2 or kLz4 (ROS 1 bags have no zstd: io::InputError).
  Ros1BagWriter(const std::string& path, ChunkCompression compression,
                size_t chunk_bytes = kDefaultChunkBytes);
  ~Ros1BagWriter();
  Ros1BagWriter(const Ros1BagWriter&) = delete;
  Ros1BagWriter& operator=(const Ros1BagWriter&) = delete;

  // A connection for one of the supported types (type name, md5sum and definition from
  // io/ros_messages.h). Returns its id for Write.
  int AddConnection(const std::string& topic, RosType type);
  // Any type, described by the caller.
  int AddConnection(const std::string& topic, const std::string& type_name,
                    const std::string& md5sum, const std::string& definition);

  // One message: `payload` serialized for ROS 1, received at `receive_s` (s since the epoch,
  // >= 0; rounded to the nanosecond). Messages may come in any time order.
  void Write(int connection, double receive_s, const uint8_t* payload, size_t size);
  void Write(int connection, double receive_s, const std::vector<uint8_t>& payload) {
    Write(connection, receive_s, payload.data(), payload.size());
  }

  // Writes the last chunk and the index, fills in the bag header and renames the file into
  // place. Further Writes are errors.
  void Close();

 private:
  struct ConnectionInfo {
    std::string topic;
    std::string type;
    std::string md5sum;
    std::string definition;
    bool written = false;  // its connection record has gone into a chunk
  };
  struct ChunkInfo {
    uint64_t pos = 0;
    int64_t start_ns = 0, end_ns = 0;
    std::map<uint32_t, uint32_t> counts;  // messages per connection
  };

  void WriteBytes(const void* data, size_t size);
  void WriteBagHeader(uint64_t index_pos);
  void AppendConnectionRecord(std::vector<uint8_t>* out, uint32_t id) const;
  void FlushChunk();

  std::string path_;
  std::string part_path_;
  ChunkCompression compression_;
  size_t chunk_bytes_;
  std::FILE* file_ = nullptr;
  uint64_t position_ = 0;  // bytes written so far
  std::vector<ConnectionInfo> connections_;
  std::vector<ChunkInfo> chunk_infos_;
  // The open chunk: its records, and per connection (time, offset) of each message.
  std::vector<uint8_t> chunk_;
  std::map<uint32_t, std::vector<std::pair<int64_t, uint32_t>>> chunk_index_;
  int64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
};

}  // namespace wallcal::recording
