// SPDX-License-Identifier: Apache-2.0
#pragma once
// The MCAP Recording (internal to io/): opening lives in mcap_reader.cc, the time-ordered
// message pass in mcap_foreach.cc.

#include <algorithm>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "recording/mcap/internal/mcap_reader.h"
#include "recording/mcap/internal/mcap_records.h"
#include "recording/internal/byte_source.h"

namespace wallcal::recording::mcap {

// A Chunk record's content (`size` bytes at file offset `offset` of `path`) unpacked: its
// compression and its decompressed records, with the declared size held to max_chunk_bytes and
// the CRC checked. Throws io::InputError "path:offset: ..." otherwise.
struct UnpackedChunk {
  ChunkCompression compression = ChunkCompression::kNone;
  std::vector<uint8_t> records;
};
UnpackedChunk UnpackChunk(const uint8_t* content, uint64_t size, const std::string& path,
                          uint64_t offset, uint64_t max_chunk_bytes);

struct SchemaInfo {
  std::string name;      // "sensor_msgs/msg/LaserScan"
  std::string encoding;  // "ros2msg", "ros2idl"
};

struct ChannelInfo {
  std::string topic;
  std::string encoding;  // message_encoding: "cdr"
  uint16_t schema_id = 0;
  size_t topic_slot = 0;  // index into topics_
};

struct ChannelStats {
  int64_t count = 0;
  uint64_t first_ns = UINT64_MAX, last_ns = 0;
  void Add(uint64_t t_ns) {
    ++count;
    first_ns = std::min(first_ns, t_ns);
    last_ns = std::max(last_ns, t_ns);
  }
};

// A stretch of the data section ForEach reads as a whole: one chunk record, or a run of loose
// (unchunked) records.
struct Block {
  uint64_t offset = 0;  // chunk record start (its opcode), or the first loose record
  uint64_t length = 0;  // bytes from offset: the whole chunk record, or the loose run
  bool chunk = true;
  uint64_t start_ns = UINT64_MAX, end_ns = 0;  // log times of its messages
  std::set<uint16_t> channels;                 // channels with messages in it
};

class McapRecording : public Recording {
 public:
  McapRecording(std::string path, std::unique_ptr<ByteSource> source, McapLimits limits);
  RecordingFormat format() const override { return RecordingFormat::kMcap; }
  void ForEach(const std::set<std::string>& topic_names,
               const std::function<void(const RecordedMessage&)>& fn) override;

 private:
  void ReadHeader();
  bool ReadSummary(std::string* why_not);
  void ReadMessageIndexes(Block* block, uint64_t index_offset, uint64_t index_length);
  void ScanData();
  void ScanChunkRecords(const std::vector<uint8_t>& records, Block* block);
  void AddLooseMessage(uint64_t offset, uint64_t record_length, const uint8_t* content,
                       uint64_t content_length, bool* loose_run_open);
  void BuildTopics();
  void Reset();

  // Parses a Chunk record's content at file offset `offset`, checks its CRC and returns the
  // decompressed records.
  std::vector<uint8_t> UnpackChunk(const uint8_t* content, uint64_t size, uint64_t offset);
  void AddSchema(Cursor* c);
  void AddChannel(Cursor* c);

  std::unique_ptr<ByteSource> source_;
  McapLimits limits_;
  uint64_t header_end_ = 0;  // first byte after the Header record
  std::map<uint16_t, SchemaInfo> schemas_;
  std::map<uint16_t, ChannelInfo> channels_;
  std::map<uint16_t, ChannelStats> stats_;
  std::vector<Block> blocks_;
};

// Calls fn(opcode, content, content_length, record_offset_in_buffer) for each record of a
// chunk's decompressed records; a record running past the end throws io::InputError at `offset`.
template <typename Fn>
void WalkRecords(const std::vector<uint8_t>& records, const std::string& path, uint64_t offset,
                 Fn&& fn) {
  size_t pos = 0;
  while (pos < records.size()) {
    if (records.size() - pos < kRecordHeaderSize) {
      throw io::InputError(At(path, offset,
                              "chunk ends inside a record header (at byte " + std::to_string(pos) +
                                  " of its records)"));
    }
    const uint8_t op = records[pos];
    const uint64_t len = GetU64(&records[pos + 1]);
    if (len > records.size() - pos - kRecordHeaderSize) {
      throw io::InputError(At(path, offset,
                              "record (opcode " + std::to_string(op) + ") at byte " +
                                  std::to_string(pos) + " of the chunk's records declares " +
                                  std::to_string(len) + " bytes, more than the chunk holds"));
    }
    fn(op, &records[pos + kRecordHeaderSize], len, pos);
    pos += kRecordHeaderSize + static_cast<size_t>(len);
  }
}

}  // namespace wallcal::recording::mcap
