// SPDX-License-Identifier: Apache-2.0
// A ROS 1 bag read on as it is recorded (recording/recording_tail.h). rosbag writes a chunk's
// record header with zero lengths, appends its records, and fills the lengths in when the chunk
// closes; a recorder killed or copied mid-write leaves a chunk cut off. Such an open chunk is
// read as far as its whole records go (a compressed one: as far as its stream decompresses)
// and the next read starts at the chunk again, passing over the records already read in it.
// The connection records a chunk holds come before that chunk's messages of them.

#include <algorithm>
#include <cstring>
#include <map>
#include <vector>

#include "io/types.h"
#include "recording/internal/byte_source.h"
#include "recording/internal/file_tail.h"
#include "recording/rosbag1/internal/bag_compression.h"
#include "recording/rosbag1/internal/rosbag1_reader.h"
#include "recording/rosbag1/internal/rosbag1_records.h"

namespace wallcal::recording {
namespace {

using bag1::RecordRef;
using bag1::RecordStatus;

// The largest open chunk decompressed (its declared size not yet filled in): rosbag's chunks
// are 768 kB; one large message makes a chunk of its own size, tens of MB at most.
constexpr size_t kMaxOpenChunkBytes = size_t{256} << 20;

class Ros1BagTail : public FileTail {
 public:
  explicit Ros1BagTail(std::string path) : FileTail(std::move(path)) {}
  RecordingFormat format() const override { return RecordingFormat::kRos1Bag; }

 protected:
  void Reset() override {
    connections_.clear();
    open_chunk_pos_ = 0;
    open_chunk_read_ = 0;
  }
  uint64_t Walk(uint64_t from_byte, uint64_t file_bytes, const std::set<std::string>& topic_names,
                const MessageFn& fn) override;

 private:
  [[noreturn]] void Fail(uint64_t offset, const std::string& what) const {
    throw io::InputError(path_ + ":byte " + std::to_string(offset) + ": " + what);
  }
  // After the bag header record, or `from_byte` when it is not whole yet.
  uint64_t ReadBagHeader(const ByteSource& source, uint64_t file_bytes) const;
  void AddConnection(uint64_t pos, const RecordRef& record, const uint8_t* data, size_t size);
  // The chunk's decompressed records; a chunk that is `open` (cut off, or its lengths not yet
  // filled in) gives what its bytes in the file hold so far.
  std::vector<uint8_t> ChunkData(const ByteSource& source, const RecordRef& record, bool open,
                                 uint64_t file_bytes) const;
  // Passes the chunk's messages on `topic_names` from record offset `from` on to `fn`, by
  // receive time (ties: chunk order); an open chunk's walk stops at its first record not whole.
  // Returns the offset after the last whole record.
  size_t WalkChunk(const std::vector<uint8_t>& data, size_t from, bool open, uint64_t pos,
                   const std::set<std::string>& topic_names, const MessageFn& fn);

  std::map<uint32_t, TopicInfo*> connections_;
  uint64_t open_chunk_pos_ = 0;  // the open chunk the last read stopped in (0: none)
  size_t open_chunk_read_ = 0;   // the offset in its records the last read reached
};

uint64_t Ros1BagTail::ReadBagHeader(const ByteSource& source, uint64_t file_bytes) const {
  if (file_bytes < bag1::kMagicSize) return 0;
  char magic[bag1::kMagicSize];
  source.Read(0, bag1::kMagicSize, reinterpret_cast<uint8_t*>(magic));
  if (std::memcmp(magic, bag1::kMagic, bag1::kMagicSize) != 0) {
    Fail(0, "not a ROS 1 bag: expected '#ROSBAG V2.0' at the start");
  }
  RecordRef record;
  std::string why;
  const RecordStatus status =
      bag1::ReadRecord(source, bag1::kMagicSize, file_bytes, &record, &why);
  if (status == RecordStatus::kMalformed) Fail(bag1::kMagicSize, "bag header record: " + why);
  if (status == RecordStatus::kCut) return 0;  // its padding is still being written
  if (record.op != bag1::kOpBagHeader) {
    Fail(bag1::kMagicSize, "expected the bag header record (op 3)");
  }
  return record.end();
}

void Ros1BagTail::AddConnection(uint64_t pos, const RecordRef& record, const uint8_t* data,
                                size_t size) {
  uint32_t conn = 0;
  const std::string_view* topic = record.fields.Find("topic");
  if (!record.fields.U32("conn", &conn) || topic == nullptr) {
    Fail(pos, "connection record lacks conn or topic");
  }
  if (connections_.count(conn) > 0) return;  // written again in the index: same content
  bag1::ConnectionHeader header;
  const std::string problem = bag1::ParseConnectionHeader(data, size, conn, &header);
  if (!problem.empty()) Fail(pos, problem);
  TopicInfo* info = Topic(std::string(*topic), header.type, header.md5sum, "ros1");
  // A later connection of the topic with another type is left out, as the bag reader does.
  connections_[conn] = info->type == header.type ? info : nullptr;
}

std::vector<uint8_t> Ros1BagTail::ChunkData(const ByteSource& source, const RecordRef& record,
                                            bool open, uint64_t file_bytes) const {
  const uint64_t pos = record.pos;
  uint32_t size = 0;
  const std::string_view* compression = record.fields.Find("compression");
  if (!record.fields.U32("size", &size) || compression == nullptr) {
    Fail(pos, "chunk record lacks its compression or size");
  }
  const uint64_t stored_bytes = open ? file_bytes - record.data_pos : record.data_len;
  const std::vector<uint8_t> stored = source.Bytes(record.data_pos, stored_bytes);
  if (*compression == "none") return stored;
  if (*compression != "bz2" && *compression != "lz4") {
    Fail(pos, "chunk compression '" + std::string(*compression) +
                  "' is not known; expected none, bz2 or lz4");
  }
  // An open chunk's size may not be filled in yet: bounded by the largest chunk accepted.
  const size_t expected = open && size == 0 ? kMaxOpenChunkBytes : size;
  std::vector<uint8_t> data;
  const DecompressOutcome outcome =
      *compression == "bz2" ? DecompressBz2(stored.data(), stored.size(), expected, &data)
                            : DecompressLz4Frame(stored.data(), stored.size(), expected, &data);
  if (!open && outcome.status != DecompressStatus::kOk) {
    Fail(pos, "chunk does not decompress: " + outcome.detail);
  }
  if (!open && data.size() != size) {
    Fail(pos, "chunk holds " + std::to_string(data.size()) + " bytes, declares " +
                  std::to_string(size));
  }
  return data;  // open: what decompressed before the cut
}

size_t Ros1BagTail::WalkChunk(const std::vector<uint8_t>& data, size_t from, bool open,
                              uint64_t pos, const std::set<std::string>& topic_names,
                              const MessageFn& fn) {
  struct Message {
    TopicInfo* topic;
    int64_t time_ns;
    size_t data_pos;
    uint32_t data_len;
  };
  std::vector<Message> messages;
  size_t at = from;
  std::string why;
  while (at < data.size()) {
    RecordRef inner;
    const RecordStatus status = bag1::ReadRecord(data.data(), data.size(), at, &inner, &why);
    if (status == RecordStatus::kCut && open) break;  // the rest comes later
    if (status != RecordStatus::kOk) {
      Fail(pos, "record at offset " + std::to_string(at) + " of the chunk: " + why);
    }
    if (inner.op == bag1::kOpConnection) {
      AddConnection(pos, inner, data.data() + inner.data_pos, inner.data_len);
    } else if (inner.op == bag1::kOpMessageData) {
      uint32_t conn = 0;
      int64_t time_ns = 0;
      if (!inner.fields.U32("conn", &conn) || !inner.fields.Time("time", &time_ns)) {
        Fail(pos, "message record at offset " + std::to_string(at) +
                      " of the chunk lacks conn or time");
      }
      const auto it = connections_.find(conn);
      if (it != connections_.end() && it->second != nullptr &&
          topic_names.count(it->second->name) > 0) {
        messages.push_back(
            {it->second, time_ns, static_cast<size_t>(inner.data_pos), inner.data_len});
      } else if (it != connections_.end() && it->second != nullptr) {
        ++it->second->count;
      }
    }
    at = static_cast<size_t>(inner.end());
  }
  std::stable_sort(messages.begin(), messages.end(),
                   [](const Message& a, const Message& b) { return a.time_ns < b.time_ns; });
  for (const Message& m : messages) {
    RecordedMessage message;
    message.topic = m.topic;
    message.wire = WireFormat::kRos1;
    message.receive_s = bag1::TimeSeconds(m.time_ns);
    message.data = data.data() + m.data_pos;
    message.size = m.data_len;
    message.index = m.topic->count++;
    message.file_offset = pos;
    fn(message);
  }
  return at;
}

uint64_t Ros1BagTail::Walk(uint64_t from_byte, uint64_t file_bytes,
                           const std::set<std::string>& topic_names, const MessageFn& fn) {
  const std::unique_ptr<ByteSource> source = OpenFileSource(path_);
  file_bytes = std::min(file_bytes, source->size());
  uint64_t pos = from_byte;
  if (pos == 0) {
    pos = ReadBagHeader(*source, file_bytes);
    if (pos == 0) return 0;
  }
  while (pos < file_bytes) {
    RecordRef record;
    std::string why;
    const RecordStatus status = bag1::ReadRecord(*source, pos, file_bytes, &record, &why);
    if (status == RecordStatus::kMalformed) Fail(pos, why);
    uint32_t size = 0;
    // Zero lengths with bytes after them: the chunk is open (its lengths are filled in when it
    // closes); a chunk cut off by the file's end is still being written.
    const bool open = record.op == bag1::kOpChunk &&
                      (status == RecordStatus::kCut ||
                       (record.data_len == 0 && record.fields.U32("size", &size) && size == 0 &&
                        record.data_pos < file_bytes));
    if (status == RecordStatus::kCut && !open) break;  // still being written: read next time
    if (record.op == bag1::kOpChunk) {
      const size_t from = pos == open_chunk_pos_ ? open_chunk_read_ : 0;
      const size_t read = WalkChunk(ChunkData(*source, record, open, file_bytes), from, open,
                                    pos, topic_names, fn);
      open_chunk_pos_ = open ? pos : 0;
      open_chunk_read_ = open ? read : 0;
      if (open) break;  // read from the chunk's start next time
    } else if (record.op == bag1::kOpConnection) {
      const std::vector<uint8_t> data = source->Bytes(record.data_pos, record.data_len);
      AddConnection(pos, record, data.data(), data.size());
    }
    pos = record.end();
  }
  return pos;
}

}  // namespace

std::unique_ptr<RecordingTail> OpenRos1BagTail(const std::string& path) {
  return std::make_unique<Ros1BagTail>(path);
}

}  // namespace wallcal::recording
