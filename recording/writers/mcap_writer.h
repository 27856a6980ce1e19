// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writes MCAP files with the ros2 profile (mcap.dev/spec): Header (profile "ros2"), Schema
// records (encoding "ros2msg", the definition text the caller passes, e.g.
// recording::RosTypeDefinition(type)), Channel records (message_encoding "cdr"), messages in chunks
// (uncompressed, zstd or lz4) each followed by its Message Index records, Data End with the data
// section CRC, a summary (Schemas, Channels, Statistics, Chunk Indexes), Summary Offsets and the
// Footer with the summary CRC. The file is written under a temporary name in the same folder and
// renamed to `path` by Close(), so a reader never sees a half-written file.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include "recording/recording.h"

namespace wallcal::recording {

class McapWriter {
 public:
  // compression: kNone, kZstd or kLz4 (kBz2 is not an MCAP compression: std::invalid_argument).
  // chunk_bytes: a chunk is closed once its uncompressed records reach this size.
  // Throws io::InputError naming `path` when the temporary file cannot be created.
  McapWriter(const std::string& path, ChunkCompression compression,
             size_t chunk_bytes = size_t{1} << 20);
  // Without Close(), the temporary file is removed and `path` is left untouched.
  ~McapWriter();
  McapWriter(const McapWriter&) = delete;
  McapWriter& operator=(const McapWriter&) = delete;

  // A channel on `topic` with type "sensor_msgs/msg/LaserScan" (the schema name) and its
  // ros2msg definition text; channels of one type share a schema. Returns the channel id.
  uint16_t AddChannel(const std::string& topic, const std::string& type_name,
                      const std::string& definition);
  // One CDR payload; times in s since the epoch (>= 0), stored as ns.
  void Write(uint16_t channel, double log_time_s, double publish_time_s, const uint8_t* data,
             size_t size);
  void Write(uint16_t channel, double log_time_s, double publish_time_s,
             const std::vector<uint8_t>& payload) {
    Write(channel, log_time_s, publish_time_s, payload.data(), payload.size());
  }
  void WriteNs(uint16_t channel, uint64_t log_time_ns, uint64_t publish_time_ns,
               const uint8_t* data, size_t size);
  // Flushes the last chunk, writes the summary and footer, and renames the file to `path`.
  // Throws io::InputError naming `path` on a write failure.
  void Close();

 private:
  struct ChunkIndexEntry {
    uint64_t start_ns = 0, end_ns = 0, offset = 0, length = 0;
    std::map<uint16_t, uint64_t> index_offsets;
    uint64_t index_length = 0, compressed_size = 0, uncompressed_size = 0;
  };
  void FlushChunk();
  void Emit(const std::vector<uint8_t>& bytes);
  [[noreturn]] void Fail(const std::string& what);

  std::string path_, temp_path_;
  std::FILE* file_ = nullptr;
  ChunkCompression compression_;
  size_t chunk_bytes_;
  uint64_t position_ = 0;  // bytes written so far
  uint32_t crc_ = 0;       // of every byte written so far (data section, then summary)
  std::vector<std::vector<uint8_t>> schema_records_, channel_records_;  // for the summary
  std::map<std::string, uint16_t> schema_ids_;
  uint16_t channel_count_ = 0;
  std::vector<uint8_t> chunk_;  // uncompressed records of the open chunk
  uint64_t chunk_start_ns_ = UINT64_MAX, chunk_end_ns_ = 0;
  std::map<uint16_t, std::vector<std::pair<uint64_t, uint64_t>>> chunk_index_;  // (log_ns, pos)
  std::vector<ChunkIndexEntry> chunks_;
  std::map<uint16_t, uint64_t> message_counts_;
  uint64_t messages_ = 0, first_ns_ = UINT64_MAX, last_ns_ = 0;
};

}  // namespace wallcal::recording
