// SPDX-License-Identifier: Apache-2.0
#pragma once
// ROS 1 bag format v2.0 (wiki.ros.org/Bags/Format/2.0) read without ROS: connection records,
// chunks (compression none, bz2, lz4 frames as roslz4 writes them), index data and chunk info.
//
// Opening reads the index (the bag header's index_pos -> connection and chunk-info records,
// then the index-data records after each chunk): no chunk is decompressed until ForEach. When
// the index is missing (index_pos 0: the recorder was killed), points outside the file, or does
// not hold together, every record is walked from the start instead (each chunk decompressed
// once to count its messages) and a warning says so.
//
// Topics merge the connections that share a topic name (a topic may be split over several);
// type and md5sum are the first connection's; a later connection of the same topic with another
// type is left out, with a warning counting its messages. TopicInfo::encoding is "ros1".
//
// Errors (io::InputError, "file:byte N: what"): not a v2.0 bag, an unknown chunk compression
// (named), a chunk that does not decompress to its declared size, a record that does not parse. A
// file cut off inside its last record or chunk (a crashed recorder, a partial copy) is read up to
// the cut: warnings() says where and how many messages were read from the cut chunk.
//
// Memory: one index entry (16 bytes) per message is kept; ForEach holds the decompressed chunks
// it is between (one, unless chunks overlap in time), each bounded by its declared size.

#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "recording/recording.h"

namespace wallcal::recording {

class ByteSource;
class RecordingTail;

// Opens a bag file. Throws io::InputError (see above).
std::unique_ptr<Recording> OpenRos1Bag(const std::string& path);
// The same over bytes in memory (fuzzing, tests); `name` stands for the path in messages.
std::unique_ptr<Recording> OpenRos1BagFromMemory(std::vector<uint8_t> bytes,
                                                 const std::string& name);

// A bag still being recorded, read on record by record (recording/recording_tail.h;
// rosbag1_tail.cc).
std::unique_ptr<RecordingTail> OpenRos1BagTail(const std::string& path);

class Ros1Bag : public Recording {
 public:
  Ros1Bag(std::unique_ptr<ByteSource> source, const std::string& path);
  ~Ros1Bag() override;
  Ros1Bag(const Ros1Bag&) = delete;
  Ros1Bag& operator=(const Ros1Bag&) = delete;

  RecordingFormat format() const override { return RecordingFormat::kRos1Bag; }

  // Messages of the named topics by receive time (the bag's record time), ties in file order.
  // Only chunks holding a requested connection are decompressed. Throws io::InputError on an
  // unknown topic (listing those present) or a damaged chunk (its byte offset).
  void ForEach(const std::set<std::string>& topic_names,
               const std::function<void(const RecordedMessage&)>& fn) override;

  // True when the messages were located through the bag's index; false when records were
  // walked (see warnings()).
  bool index_used() const { return index_used_; }

 private:
  struct Connection {
    std::string topic;
    std::string type;
    std::string md5sum;
    int topic_index = -1;  // into topics_; -1: left out (type differs from the topic's)
  };
  struct Entry {
    int64_t time_ns;  // receive time
    uint32_t offset;  // of the message-data record in the decompressed chunk
    uint32_t conn;
  };
  struct Chunk {
    uint64_t record_pos = 0;  // file offset of the chunk record
    uint64_t data_pos = 0;    // file offset of its (compressed) data
    uint64_t data_len = 0;    // bytes of data read (less than declared when the file is cut)
    uint32_t size = 0;        // declared uncompressed size
    ChunkCompression compression = ChunkCompression::kNone;
    bool cut = false;  // the file ends inside this chunk: read up to the cut
    std::vector<Entry> entries;
  };
  struct Index {
    std::map<uint32_t, Connection> connections;
    std::vector<Chunk> chunks;
    int64_t length_mismatches = 0;  // index-data records whose data_len != 12 * count
    uint64_t first_mismatch_pos = 0;
  };

  [[noreturn]] void Fail(uint64_t offset, const std::string& what) const;
  void ReadBagHeader();
  // Fills *index from the bag's index; "" on success, else why the index cannot be used.
  std::string ReadIndex(uint64_t index_pos, Index* index) const;
  std::string ReadChunkIndex(uint64_t chunk_pos, const std::map<uint32_t, uint32_t>& counts,
                             Index* index) const;
  void WalkRecords(Index* index);
  void WalkChunk(Chunk chunk, Index* index);
  void AddConnection(uint64_t pos, const std::string& record_topic, uint32_t conn,
                     const uint8_t* data, size_t size, Index* index) const;
  ChunkCompression ParseCompression(uint64_t pos, std::string_view name) const;
  // Decompressed bytes of a chunk; throws io::InputError unless the chunk is cut (then partial).
  std::vector<uint8_t> LoadChunk(const Chunk& chunk) const;
  void BuildTopics(Index* index);

  std::unique_ptr<ByteSource> source_;
  uint64_t file_size_ = 0;
  uint64_t first_record_pos_ = 0;  // after the bag header record
  uint64_t index_pos_ = 0;
  uint32_t declared_chunks_ = 0;
  std::map<uint32_t, Connection> connections_;
  std::vector<Chunk> chunks_;  // in file order
  bool index_used_ = false;
};

}  // namespace wallcal::recording
