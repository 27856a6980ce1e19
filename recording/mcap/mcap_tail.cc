// SPDX-License-Identifier: Apache-2.0
// An MCAP file read on as it is written (recording/recording_tail.h): the data section walked
// from where the last read stopped, one whole record at a time. A writer appends each record
// whole (a chunk once it closes), so the file's end is either between records or inside the
// one being written, which is read next time. The data section CRC (in Data End) covers the
// whole section and is not checked here; each chunk's own CRC is.


#include <algorithm>
#include <cstring>
#include <map>
#include <vector>

#include "recording/internal/byte_source.h"
#include "recording/mcap/internal/mcap_reader.h"
#include "recording/internal/file_tail.h"
#include "recording/mcap/internal/mcap_recording.h"

namespace wallcal::recording {
namespace {

using mcap::Cursor;
using mcap::GetU64;
using mcap::kRecordHeaderSize;

class McapTail : public FileTail {
 public:
  explicit McapTail(std::string path) : FileTail(std::move(path)) {}
  RecordingFormat format() const override { return RecordingFormat::kMcap; }

 protected:
  void Reset() override {
    schemas_.clear();
    channels_.clear();
    ended_ = false;
  }
  uint64_t Walk(uint64_t from_byte, uint64_t file_bytes, const std::set<std::string>& topic_names,
                const MessageFn& fn) override;

 private:
  struct Channel {
    std::string topic;
    uint16_t schema_id = 0;
    std::string encoding;
    TopicInfo* info = nullptr;  // set when its topic's type is known
  };
  // One message on a wanted topic: its bytes stay in the buffer they came from.
  struct Message {
    TopicInfo* topic;
    uint64_t log_time_ns;
    const uint8_t* data;
    size_t size;
  };
  // A schema, channel or message record; a message on `topic_names` is added to *messages.
  void Take(uint8_t op, const uint8_t* content, uint64_t len, uint64_t offset,
            const std::set<std::string>& topic_names, std::vector<Message>* messages);
  std::vector<uint8_t> Unpack(const std::vector<uint8_t>& content, uint64_t offset) const;
  void Emit(std::vector<Message>* messages, uint64_t offset, const MessageFn& fn);

  std::map<uint16_t, std::string> schemas_;  // id -> name ("sensor_msgs/msg/LaserScan")
  std::map<uint16_t, Channel> channels_;
  bool ended_ = false;  // Data End or Footer read: nothing more comes
};

void McapTail::Take(uint8_t op, const uint8_t* content, uint64_t len, uint64_t offset,
                    const std::set<std::string>& topic_names, std::vector<Message>* messages) {
  Cursor c(content, static_cast<size_t>(len), path_, offset,
           op == mcap::kSchema ? "Schema" : op == mcap::kChannel ? "Channel" : "Message");
  if (op == mcap::kSchema) {
    const uint16_t id = c.U16("id");
    const std::string name = c.Str("name");
    if (id != 0) schemas_.emplace(id, name);  // id 0 is invalid: ignored (spec)
  } else if (op == mcap::kChannel) {
    const uint16_t id = c.U16("id");
    Channel channel;
    channel.schema_id = c.U16("schema_id");
    channel.topic = c.Str("topic");
    channel.encoding = c.Str("message_encoding");
    channels_.emplace(id, std::move(channel));  // repeats must be identical (spec): first kept
  } else if (op == mcap::kMessage) {
    const uint16_t id = c.U16("channel_id");
    c.U32("sequence");
    const uint64_t log_time_ns = c.U64("log_time");
    c.U64("publish_time");
    const auto it = channels_.find(id);
    if (it == channels_.end()) {
      throw io::InputError(mcap::At(path_, offset,
                                    "message on channel " + std::to_string(id) +
                                        " before any Channel record defines it"));
    }
    Channel& channel = it->second;
    if (channel.info == nullptr) {
      const auto schema = schemas_.find(channel.schema_id);
      channel.info = Topic(channel.topic, schema != schemas_.end() ? schema->second : "", "",
                           channel.encoding);
    }
    if (topic_names.count(channel.topic) > 0 && channel.info->encoding == channel.encoding) {
      const size_t size = c.left();
      messages->push_back({channel.info, log_time_ns, c.Take(size, "data"), size});
    } else {
      ++channel.info->count;
    }
  }
}

std::vector<uint8_t> McapTail::Unpack(const std::vector<uint8_t>& content, uint64_t offset) const {
  return mcap::UnpackChunk(content.data(), content.size(), path_, offset,
                           McapLimits().max_chunk_bytes)
      .records;
}

void McapTail::Emit(std::vector<Message>* messages, uint64_t offset, const MessageFn& fn) {
  std::stable_sort(messages->begin(), messages->end(), [](const Message& a, const Message& b) {
    return a.log_time_ns < b.log_time_ns;
  });
  for (const Message& m : *messages) {
    RecordedMessage message;
    message.topic = m.topic;
    message.wire = WireFormat::kCdr;
    message.receive_s = static_cast<double>(m.log_time_ns) * 1e-9;
    message.data = m.data;
    message.size = m.size;
    message.index = m.topic->count++;
    message.file_offset = offset;
    fn(message);
  }
  messages->clear();
}

uint64_t McapTail::Walk(uint64_t from_byte, uint64_t file_bytes,
                        const std::set<std::string>& topic_names, const MessageFn& fn) {
  if (ended_) return from_byte;
  const std::unique_ptr<ByteSource> source = OpenFileSource(path_);
  file_bytes = std::min(file_bytes, source->size());
  uint64_t off = from_byte;
  uint8_t head[mcap::kMagicSize + kRecordHeaderSize];
  if (off == 0) {
    if (file_bytes < sizeof head) return 0;
    source->Read(0, sizeof head, head);
    if (std::memcmp(head, mcap::kMagic, mcap::kMagicSize) != 0 ||
        head[mcap::kMagicSize] != mcap::kHeader) {
      throw io::InputError(
          mcap::At(path_, 0, "not an MCAP file: expected the magic and a Header record"));
    }
    const uint64_t len = GetU64(head + mcap::kMagicSize + 1);
    if (len > file_bytes - sizeof head) return 0;
    off = sizeof head + len;
  }
  std::vector<Message> messages;
  while (file_bytes - off >= kRecordHeaderSize) {
    source->Read(off, kRecordHeaderSize, head);
    const uint8_t op = head[0];
    const uint64_t len = GetU64(head + 1);
    // Zeros: space the writer has not filled yet; a record past the end: still being written.
    if (op == 0 || len > file_bytes - off - kRecordHeaderSize) break;
    if (op == mcap::kDataEnd || op == mcap::kFooter) {
      ended_ = true;
      break;
    }
    if (op == mcap::kSchema || op == mcap::kChannel || op == mcap::kMessage ||
        op == mcap::kChunk) {
      const std::vector<uint8_t> content = source->Bytes(off + kRecordHeaderSize, len);
      if (op == mcap::kChunk) {
        const std::vector<uint8_t> records = Unpack(content, off);
        mcap::WalkRecords(records, path_, off,
                          [&](uint8_t inner, const uint8_t* data, uint64_t n, size_t) {
                            Take(inner, data, n, off, topic_names, &messages);
                          });
        Emit(&messages, off, fn);
      } else {
        Take(op, content.data(), len, off, topic_names, &messages);
        Emit(&messages, off, fn);
      }
    }
    off += kRecordHeaderSize + len;
  }
  return off;
}

}  // namespace

std::unique_ptr<RecordingTail> OpenMcapTail(const std::string& path) {
  return std::make_unique<McapTail>(path);
}

}  // namespace wallcal::recording
