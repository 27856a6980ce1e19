// SPDX-License-Identifier: Apache-2.0
// The time-ordered pass over an MCAP file's messages. Blocks (chunks, runs of loose messages)
// are loaded in order of their first log time; their messages wait in a min-heap keyed by
// (log time, block offset, position in block) and leave it once no unloaded block can hold an
// earlier one. So chunks that overlap in time still come out in log-time order, ties in file
// order, each chunk decompressed once, and memory holds only the chunks that overlap.

#include <algorithm>
#include <queue>

#include "recording/mcap/internal/mcap_recording.h"

namespace wallcal::recording::mcap {
namespace {

struct Pending {
  uint64_t log_ns = 0;
  uint64_t block_offset = 0;
  size_t position = 0;  // of the record within its block's bytes
  uint16_t channel = 0;
  uint64_t record_offset = 0;  // reported as RecordedMessage::file_offset
  std::shared_ptr<const std::vector<uint8_t>> bytes;
  size_t data_at = 0, data_size = 0;
};

struct Later {
  bool operator()(const Pending& a, const Pending& b) const {
    if (a.log_ns != b.log_ns) return a.log_ns > b.log_ns;
    if (a.block_offset != b.block_offset) return a.block_offset > b.block_offset;
    return a.position > b.position;
  }
};

std::string TopicList(const std::vector<TopicInfo>& topics) {
  std::string list;
  for (const TopicInfo& t : topics) list += (list.empty() ? "" : ", ") + t.name;
  return list.empty() ? "none" : list;
}

}  // namespace

void McapRecording::ForEach(const std::set<std::string>& topic_names,
                            const std::function<void(const RecordedMessage&)>& fn) {
  for (const std::string& name : topic_names) {
    const auto it = std::find_if(topics_.begin(), topics_.end(),
                                 [&](const TopicInfo& t) { return t.name == name; });
    if (it == topics_.end()) {
      throw io::InputError(path_ + ": no topic " + name +
                           " in the recording (topics: " + TopicList(topics_) + ")");
    }
    if (it->encoding != "cdr") {
      throw io::InputError(path_ + ": topic " + name + " is encoded as '" + it->encoding +
                           "'; only 'cdr' (ROS 2) messages are read from MCAP");
    }
  }
  std::set<uint16_t> wanted;
  for (const auto& kv : channels_) {
    if (topic_names.count(kv.second.topic) != 0) wanted.insert(kv.first);
  }
  std::vector<const Block*> order;
  for (const Block& block : blocks_) {
    for (uint16_t id : block.channels) {
      if (wanted.count(id) != 0) {
        order.push_back(&block);
        break;
      }
    }
  }
  std::stable_sort(order.begin(), order.end(), [](const Block* a, const Block* b) {
    return a->start_ns != b->start_ns ? a->start_ns < b->start_ns : a->offset < b->offset;
  });

  std::priority_queue<Pending, std::vector<Pending>, Later> heap;
  auto take_messages = [&](const Block& block, std::shared_ptr<const std::vector<uint8_t>> bytes,
                           bool chunk) {
    WalkRecords(*bytes, path_, block.offset,
                [&](uint8_t op, const uint8_t* content, uint64_t len, size_t pos) {
                  if (op != kMessage) return;
                  const uint64_t record_offset = chunk ? block.offset : block.offset + pos;
                  Cursor c(content, static_cast<size_t>(len), path_, record_offset, "Message");
                  Pending p;
                  p.channel = c.U16("channel_id");
                  c.U32("sequence");
                  p.log_ns = c.U64("log_time");
                  c.U64("publish_time");
                  if (wanted.count(p.channel) == 0) return;
                  p.block_offset = block.offset;
                  p.position = pos;
                  p.record_offset = record_offset;
                  p.bytes = bytes;
                  p.data_at = static_cast<size_t>(content - bytes->data()) + c.pos();
                  p.data_size = c.left();
                  heap.push(std::move(p));
                });
  };
  auto load = [&](const Block& block) {
    std::vector<uint8_t> raw = source_->Bytes(block.offset, block.length);
    if (!block.chunk) {
      take_messages(block, std::make_shared<const std::vector<uint8_t>>(std::move(raw)), false);
      return;
    }
    if (raw[0] != kChunk || GetU64(&raw[1]) != block.length - kRecordHeaderSize) {
      throw io::InputError(At(path_, block.offset,
                              "the chunk index points at no Chunk record of " +
                                  std::to_string(block.length) + " bytes"));
    }
    auto records = std::make_shared<const std::vector<uint8_t>>(UnpackChunk(
        raw.data() + kRecordHeaderSize, block.length - kRecordHeaderSize, block.offset));
    take_messages(block, records, true);
  };

  std::vector<int64_t> emitted(topics_.size(), 0);
  uint64_t last_ns = 0;
  bool disorder_noted = false;
  size_t next = 0;
  while (next < order.size() || !heap.empty()) {
    if (next < order.size() && (heap.empty() || order[next]->start_ns <= heap.top().log_ns)) {
      load(*order[next++]);
      continue;
    }
    const Pending& p = heap.top();
    const auto channel = channels_.find(p.channel);
    if (channel == channels_.end()) {
      throw io::InputError(At(
          path_, p.record_offset,
          "message on channel " + std::to_string(p.channel) + ", which no Channel record defines"));
    }
    if (p.log_ns < last_ns && !disorder_noted) {
      disorder_noted = true;  // an index that misstates a chunk's times
      warnings_.push_back(At(path_, p.block_offset,
                             "a chunk holds messages earlier than its index says: some "
                             "messages were passed on out of log-time order"));
    }
    last_ns = std::max(last_ns, p.log_ns);
    RecordedMessage message;
    const size_t slot = channel->second.topic_slot;
    message.topic = &topics_[slot];
    message.wire = WireFormat::kCdr;
    message.receive_s = static_cast<double>(p.log_ns) * 1e-9;
    message.data = p.bytes->data() + p.data_at;
    message.size = p.data_size;
    message.index = emitted[slot]++;
    message.file_offset = p.record_offset;
    fn(message);
    heap.pop();
  }
}

}  // namespace wallcal::recording::mcap
