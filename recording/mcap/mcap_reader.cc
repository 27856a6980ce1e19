// SPDX-License-Identifier: Apache-2.0
#include "recording/mcap/internal/mcap_reader.h"

#include <zlib.h>

#include <algorithm>
#include <cstring>
#include <map>

#include "recording/mcap/internal/mcap_compression.h"
#include "recording/mcap/internal/mcap_recording.h"

namespace wallcal::recording {
namespace mcap {

std::string At(const std::string& path, uint64_t offset, const std::string& message) {
  return path + ":" + std::to_string(offset) + ": " + message;
}

namespace {

// Loose messages are grouped in runs of at most this many bytes: ForEach holds a run in memory.
constexpr uint64_t kLooseRunBytes = uint64_t{4} << 20;

std::string Hex(uint32_t v) {
  char text[16];
  std::snprintf(text, sizeof text, "0x%08x", v);
  return text;
}

const char* OpcodeName(uint8_t op) {
  switch (op) {
    case kHeader:
      return "Header";
    case kFooter:
      return "Footer";
    case kSchema:
      return "Schema";
    case kChannel:
      return "Channel";
    case kMessage:
      return "Message";
    case kChunk:
      return "Chunk";
    case kMessageIndex:
      return "Message Index";
    case kChunkIndex:
      return "Chunk Index";
    case kAttachment:
      return "Attachment";
    case kAttachmentIndex:
      return "Attachment Index";
    case kStatistics:
      return "Statistics";
    case kMetadata:
      return "Metadata";
    case kMetadataIndex:
      return "Metadata Index";
    case kSummaryOffset:
      return "Summary Offset";
    case kDataEnd:
      return "Data End";
    default:
      return "unknown";
  }
}

ChunkCompression CompressionFromName(const std::string& name, const std::string& path,
                                     uint64_t offset) {
  if (name.empty()) return ChunkCompression::kNone;
  if (name == "zstd") return ChunkCompression::kZstd;
  if (name == "lz4") return ChunkCompression::kLz4;
  throw io::InputError(
      At(path, offset, "unknown chunk compression '" + name + "' (expected '', 'zstd' or 'lz4')"));
}

}  // namespace

McapRecording::McapRecording(std::string path, std::unique_ptr<ByteSource> source,
                             McapLimits limits)
    : source_(std::move(source)), limits_(limits) {
  path_ = std::move(path);
  ReadHeader();
  std::string why_not;
  if (!ReadSummary(&why_not)) {
    Reset();
    warnings_.push_back(path_ + ": " + why_not + ": the data section was read record by record");
    ScanData();
  }
  BuildTopics();
}

void McapRecording::Reset() {
  schemas_.clear();
  channels_.clear();
  stats_.clear();
  blocks_.clear();
  compressions_.clear();
}

void McapRecording::ReadHeader() {
  const uint64_t size = source_->size();
  uint8_t head[kMagicSize + kRecordHeaderSize];
  if (size < sizeof head) {
    throw io::InputError(At(path_, 0,
                            "not an MCAP file: " + std::to_string(size) +
                                " bytes, too short for the magic and a Header record"));
  }
  source_->Read(0, sizeof head, head);
  if (std::memcmp(head, kMagic, kMagicSize) != 0) {
    throw io::InputError(At(path_, 0, "not an MCAP file: expected the magic \\x89MCAP0\\r\\n"));
  }
  const uint64_t len = GetU64(head + kMagicSize + 1);
  if (head[kMagicSize] != kHeader || len > size - sizeof head) {
    throw io::InputError(At(path_, kMagicSize, "expected a Header record after the magic"));
  }
  const std::vector<uint8_t> content = source_->Bytes(sizeof head, len);
  Cursor c(content.data(), content.size(), path_, kMagicSize, "Header");
  c.Str("profile");  // "ros2" expected; other profiles are read the same way
  c.Str("library");
  header_end_ = sizeof head + len;
}

void McapRecording::AddSchema(Cursor* c) {
  const uint16_t id = c->U16("id");
  SchemaInfo schema;
  schema.name = c->Str("name");
  schema.encoding = c->Str("encoding");
  if (id != 0) schemas_.emplace(id, std::move(schema));  // id 0 is invalid: ignored (spec)
}

void McapRecording::AddChannel(Cursor* c) {
  const uint16_t id = c->U16("id");
  ChannelInfo channel;
  channel.schema_id = c->U16("schema_id");
  channel.topic = c->Str("topic");
  channel.encoding = c->Str("message_encoding");
  channels_.emplace(id, std::move(channel));  // repeats must be identical (spec): first kept
}

UnpackedChunk UnpackChunk(const uint8_t* content, uint64_t size, const std::string& path,
                          uint64_t offset, uint64_t max_chunk_bytes) {
  Cursor c(content, static_cast<size_t>(size), path, offset, "Chunk");
  c.U64("message_start_time");
  c.U64("message_end_time");
  const uint64_t uncompressed_size = c.U64("uncompressed_size");
  const uint32_t crc = c.U32("uncompressed_crc");
  const std::string compression_name = c.Str("compression");
  const uint64_t records_size = c.U64("records length");
  const uint8_t* records = c.Take(records_size, "records");
  const ChunkCompression compression = CompressionFromName(compression_name, path, offset);
  if (uncompressed_size > max_chunk_bytes) {
    throw io::InputError(At(path, offset,
                            "chunk declares " + std::to_string(uncompressed_size) +
                                " bytes uncompressed, more than the " +
                                std::to_string(max_chunk_bytes) + " accepted"));
  }
  std::vector<uint8_t> out;
  if (compression == ChunkCompression::kNone) {
    if (records_size != uncompressed_size) {
      throw io::InputError(At(path, offset,
                              "uncompressed chunk holds " + std::to_string(records_size) +
                                  " bytes but declares " + std::to_string(uncompressed_size)));
    }
    out.assign(records, records + records_size);
  } else {
    const Codec codec = compression == ChunkCompression::kZstd ? Codec::kZstd : Codec::kLz4;
    const InflateStatus status =
        Inflate(codec, records, static_cast<size_t>(records_size), uncompressed_size, &out);
    if (status != InflateStatus::kOk) {
      throw io::InputError(At(path, offset,
                              compression_name + " chunk does not decompress to its " +
                                  std::to_string(uncompressed_size) +
                                  " bytes: " + InflateStatusText(status)));
    }
  }
  if (crc != 0) {
    const uint32_t got = static_cast<uint32_t>(crc32(0, out.data(), static_cast<uInt>(out.size())));
    if (got != crc) {
      throw io::InputError(
          At(path, offset,
             "chunk CRC mismatch: records hash to " + Hex(got) + ", the chunk says " + Hex(crc)));
    }
  }
  return UnpackedChunk{compression, std::move(out)};
}

std::vector<uint8_t> McapRecording::UnpackChunk(const uint8_t* content, uint64_t size,
                                                uint64_t offset) {
  UnpackedChunk chunk = mcap::UnpackChunk(content, size, path_, offset, limits_.max_chunk_bytes);
  compressions_.insert(chunk.compression);
  return std::move(chunk.records);
}

bool McapRecording::ReadSummary(std::string* why_not) {
  const uint64_t size = source_->size();
  constexpr uint64_t kTail = kRecordHeaderSize + kFooterContentSize + kMagicSize;
  if (size < header_end_ + kTail) {
    *why_not = "no footer (the recording was not closed)";
    return false;
  }
  const uint64_t footer_at = size - kTail;
  uint8_t tail[kTail];
  source_->Read(footer_at, kTail, tail);
  if (tail[0] != kFooter || GetU64(tail + 1) != kFooterContentSize ||
      std::memcmp(tail + kTail - kMagicSize, kMagic, kMagicSize) != 0) {
    *why_not = "no footer (the recording was not closed)";
    return false;
  }
  const uint64_t summary_start = GetU64(tail + 9);
  const uint64_t offsets_start = GetU64(tail + 17);
  const uint32_t summary_crc = GetU32(tail + 25);
  if (summary_start == 0) {
    *why_not = "no summary section";
    return false;
  }
  const uint64_t summary_end = offsets_start != 0 ? offsets_start : footer_at;
  if (summary_start < header_end_ || summary_start > summary_end || summary_end > footer_at) {
    *why_not = "the footer points outside the file";
    return false;
  }
  if (summary_crc != 0) {
    const uint64_t covered = footer_at + kRecordHeaderSize + 16 - summary_start;
    const uint32_t got = source_->Crc(summary_start, covered, 0);
    if (got != summary_crc) {
      throw io::InputError(At(path_, summary_start,
                              "summary CRC mismatch: the summary hashes to " + Hex(got) +
                                  ", the footer says " + Hex(summary_crc)));
    }
  }
  const std::vector<uint8_t> summary = source_->Bytes(summary_start, summary_end - summary_start);
  struct ChunkRef {
    Block block;
    uint64_t index_offset = 0, index_length = 0;
    bool indexed = false;
  };
  std::vector<ChunkRef> chunks;
  bool have_statistics = false;
  uint64_t statistics_count = 0;
  for (size_t pos = 0; pos < summary.size();) {
    if (summary.size() - pos < kRecordHeaderSize ||
        GetU64(&summary[pos + 1]) > summary.size() - pos - kRecordHeaderSize) {
      *why_not = "summary record at byte " + std::to_string(summary_start + pos) + " is cut off";
      return false;
    }
    const uint8_t op = summary[pos];
    const size_t len = static_cast<size_t>(GetU64(&summary[pos + 1]));
    const uint64_t at = summary_start + pos;
    Cursor c(&summary[pos + kRecordHeaderSize], len, path_, at, OpcodeName(op));
    if (op == kSchema) {
      AddSchema(&c);
    } else if (op == kChannel) {
      AddChannel(&c);
    } else if (op == kStatistics) {
      have_statistics = true;
      statistics_count = c.U64("message_count");
    } else if (op == kChunkIndex) {
      ChunkRef ref;
      c.U64("message_start_time");
      c.U64("message_end_time");
      ref.block.offset = c.U64("chunk_start_offset");
      ref.block.length = c.U64("chunk_length");
      Cursor offsets = c.Sub32("message_index_offsets");
      ref.indexed = offsets.left() > 0;
      ref.index_length = c.U64("message_index_length");
      compressions_.insert(CompressionFromName(c.Str("compression"), path_, ref.block.offset));
      const uint64_t start = ref.block.offset, length = ref.block.length;
      // start is checked against both ends before any difference is taken (unsigned).
      if (start < header_end_ || start > summary_start || length < kRecordHeaderSize ||
          length > summary_start - start || ref.index_length > summary_start - start - length) {
        *why_not = "chunk index at byte " + std::to_string(at) + " points outside the data section";
        return false;
      }
      ref.index_offset = start + length;
      chunks.push_back(ref);
    }
    pos += kRecordHeaderSize + len;
  }
  uint64_t indexed_messages = 0;
  for (ChunkRef& ref : chunks) {
    if (!ref.indexed) {
      *why_not = "chunk at byte " + std::to_string(ref.block.offset) + " has no message index";
      return false;
    }
    ReadMessageIndexes(&ref.block, ref.index_offset, ref.index_length);
    for (uint16_t id : ref.block.channels) {
      if (channels_.count(id) == 0) {
        *why_not = "channel " + std::to_string(id) + " is indexed but not in the summary";
        return false;
      }
    }
    if (!ref.block.channels.empty()) blocks_.push_back(ref.block);
  }
  for (const auto& kv : stats_) indexed_messages += static_cast<uint64_t>(kv.second.count);
  if (have_statistics && statistics_count != indexed_messages) {
    *why_not = "the statistics count " + std::to_string(statistics_count) +
               " messages, the chunk indexes " + std::to_string(indexed_messages);
    return false;
  }
  // Data End sits just before the summary; its CRC covers every byte before it.
  constexpr uint64_t kDataEndSize = kRecordHeaderSize + 4;
  if (summary_start >= header_end_ + kDataEndSize) {
    const uint64_t at = summary_start - kDataEndSize;
    uint8_t record[kDataEndSize];
    source_->Read(at, kDataEndSize, record);
    const uint32_t crc = GetU32(record + kRecordHeaderSize);
    if (record[0] == kDataEnd && GetU64(record + 1) == 4 && crc != 0) {
      const uint32_t got = source_->Crc(0, at, 0);
      if (got != crc) {
        throw io::InputError(At(path_, at,
                                "data section CRC mismatch: the data hashes to " + Hex(got) +
                                    ", the Data End record says " + Hex(crc)));
      }
    }
  }
  return true;
}

void McapRecording::ReadMessageIndexes(Block* block, uint64_t index_offset, uint64_t index_length) {
  const std::vector<uint8_t> bytes = source_->Bytes(index_offset, index_length);
  for (size_t pos = 0; pos < bytes.size();) {
    const uint64_t at = index_offset + pos;
    if (bytes.size() - pos < kRecordHeaderSize ||
        GetU64(&bytes[pos + 1]) > bytes.size() - pos - kRecordHeaderSize) {
      throw io::InputError(At(path_, at, "message index record cut off"));
    }
    const size_t len = static_cast<size_t>(GetU64(&bytes[pos + 1]));
    if (bytes[pos] == kMessageIndex) {
      Cursor c(&bytes[pos + kRecordHeaderSize], len, path_, at, "Message Index");
      const uint16_t channel = c.U16("channel_id");
      Cursor entries = c.Sub32("records");
      ChannelStats& stats = stats_[channel];
      while (entries.left() > 0) {
        const uint64_t t_ns = entries.U64("log_time");
        entries.U64("offset");
        stats.Add(t_ns);
        block->start_ns = std::min(block->start_ns, t_ns);
        block->end_ns = std::max(block->end_ns, t_ns);
        block->channels.insert(channel);
      }
    }
    pos += kRecordHeaderSize + len;
  }
}

void McapRecording::ScanChunkRecords(const std::vector<uint8_t>& records, Block* block) {
  WalkRecords(records, path_, block->offset,
              [&](uint8_t op, const uint8_t* content, uint64_t len, size_t) {
                Cursor c(content, static_cast<size_t>(len), path_, block->offset, OpcodeName(op));
                if (op == kSchema) {
                  AddSchema(&c);
                } else if (op == kChannel) {
                  AddChannel(&c);
                } else if (op == kMessage) {
                  const uint16_t channel = c.U16("channel_id");
                  c.U32("sequence");
                  const uint64_t t_ns = c.U64("log_time");
                  c.U64("publish_time");
                  if (channels_.count(channel) == 0) {
                    throw io::InputError(At(path_, block->offset,
                                            "message on channel " + std::to_string(channel) +
                                                " before any Channel record defines it"));
                  }
                  stats_[channel].Add(t_ns);
                  block->start_ns = std::min(block->start_ns, t_ns);
                  block->end_ns = std::max(block->end_ns, t_ns);
                  block->channels.insert(channel);
                }
              });
}

void McapRecording::AddLooseMessage(uint64_t offset, uint64_t record_length, const uint8_t* content,
                                    uint64_t content_length, bool* loose_run_open) {
  Cursor c(content, static_cast<size_t>(content_length), path_, offset, "Message");
  const uint16_t channel = c.U16("channel_id");
  c.U32("sequence");
  const uint64_t t_ns = c.U64("log_time");
  c.U64("publish_time");
  if (channels_.count(channel) == 0) {
    throw io::InputError(At(
        path_, offset,
        "message on channel " + std::to_string(channel) + " before any Channel record defines it"));
  }
  stats_[channel].Add(t_ns);
  if (!*loose_run_open || blocks_.empty() || offset - blocks_.back().offset > kLooseRunBytes) {
    Block run;
    run.chunk = false;
    run.offset = offset;
    blocks_.push_back(run);
    *loose_run_open = true;
  }
  Block& run = blocks_.back();
  run.length = offset + record_length - run.offset;
  run.start_ns = std::min(run.start_ns, t_ns);
  run.end_ns = std::max(run.end_ns, t_ns);
  run.channels.insert(channel);
}

void McapRecording::ScanData() {
  const uint64_t size = source_->size();
  uint64_t off = header_end_;
  uint32_t crc = source_->Crc(0, header_end_, 0);
  bool loose_run_open = false;
  while (true) {
    const uint64_t left = size - off;
    if (left == 0) {
      warnings_.push_back(At(path_, off,
                             "the file ends without a Data End record (cut off "
                             "between records): read up to there"));
      return;
    }
    if (left < kRecordHeaderSize) {
      warnings_.push_back(At(path_, off,
                             "the file is cut off inside a record header: the last " +
                                 std::to_string(left) + " bytes lost"));
      return;
    }
    uint8_t head[kRecordHeaderSize];
    source_->Read(off, kRecordHeaderSize, head);
    const uint8_t op = head[0];
    const uint64_t len = GetU64(head + 1);
    if (op == 0) {
      warnings_.push_back(At(path_, off,
                             "zero bytes where a record should start (a damaged "
                             "or unwritten tail): the last " +
                                 std::to_string(left) + " bytes ignored"));
      return;
    }
    if (len > left - kRecordHeaderSize) {
      warnings_.push_back(At(path_, off,
                             std::string("the file is cut off inside a ") + OpcodeName(op) +
                                 " record declaring " + std::to_string(len) + " bytes: the last " +
                                 std::to_string(left) + " bytes lost" +
                                 (op == kChunk ? " with the messages of that chunk" : "")));
      return;
    }
    if (op == kDataEnd || op == kFooter) {
      if (op == kDataEnd && len >= 4) {
        uint8_t field[4];
        source_->Read(off + kRecordHeaderSize, 4, field);
        const uint32_t expected = GetU32(field);
        if (expected != 0 && expected != crc) {
          throw io::InputError(At(path_, off,
                                  "data section CRC mismatch: the data hashes to " + Hex(crc) +
                                      ", the Data End record says " + Hex(expected)));
        }
      }
      return;
    }
    crc = static_cast<uint32_t>(crc32(crc, head, kRecordHeaderSize));
    const uint64_t record_length = kRecordHeaderSize + len;
    if (op == kSchema || op == kChannel || op == kMessage || op == kChunk) {
      const std::vector<uint8_t> content = source_->Bytes(off + kRecordHeaderSize, len);
      crc = static_cast<uint32_t>(crc32(crc, content.data(), static_cast<uInt>(content.size())));
      Cursor c(content.data(), content.size(), path_, off, OpcodeName(op));
      if (op == kSchema) {
        AddSchema(&c);
      } else if (op == kChannel) {
        AddChannel(&c);
      } else if (op == kMessage) {
        AddLooseMessage(off, record_length, content.data(), len, &loose_run_open);
      } else {
        loose_run_open = false;
        Block block;
        block.offset = off;
        block.length = record_length;
        ScanChunkRecords(UnpackChunk(content.data(), len, off), &block);
        if (!block.channels.empty()) blocks_.push_back(block);
      }
    } else {
      crc = source_->Crc(off + kRecordHeaderSize, len, crc);  // skipped, but hashed
    }
    off += record_length;
  }
}

void McapRecording::BuildTopics() {
  std::map<std::string, TopicInfo> by_name;
  for (const auto& kv : channels_) {
    const ChannelInfo& channel = kv.second;
    const auto schema = schemas_.find(channel.schema_id);
    const std::string type = schema != schemas_.end() ? schema->second.name : std::string();
    if (channel.schema_id != 0 && schema == schemas_.end()) {
      warnings_.push_back(path_ + ": channel " + std::to_string(kv.first) + " (" + channel.topic +
                          ") names schema " + std::to_string(channel.schema_id) +
                          ", which the file does not hold: its type is unknown");
    }
    auto it = by_name.find(channel.topic);
    if (it == by_name.end()) {
      TopicInfo topic;
      topic.name = channel.topic;
      topic.type = type;
      topic.encoding = channel.encoding;
      it = by_name.emplace(channel.topic, topic).first;
    } else if (it->second.type != type || it->second.encoding != channel.encoding) {
      warnings_.push_back(path_ + ": topic " + channel.topic +
                          " has channels of different types (" + it->second.type + " " +
                          it->second.encoding + ", " + type + " " + channel.encoding +
                          "): the first is reported");
    }
    const auto stats = stats_.find(kv.first);
    if (stats == stats_.end() || stats->second.count == 0) continue;
    TopicInfo& topic = it->second;
    const double first_s = static_cast<double>(stats->second.first_ns) * 1e-9;
    const double last_s = static_cast<double>(stats->second.last_ns) * 1e-9;
    topic.first_s = topic.count == 0 ? first_s : std::min(topic.first_s, first_s);
    topic.last_s = topic.count == 0 ? last_s : std::max(topic.last_s, last_s);
    topic.count += stats->second.count;
  }
  topics_.clear();
  for (auto& kv : by_name) topics_.push_back(std::move(kv.second));
  for (auto& kv : channels_) {
    const auto it =
        std::lower_bound(topics_.begin(), topics_.end(), kv.second.topic,
                         [](const TopicInfo& t, const std::string& name) { return t.name < name; });
    kv.second.topic_slot = static_cast<size_t>(it - topics_.begin());
  }
}

}  // namespace mcap

std::unique_ptr<Recording> OpenMcap(const std::string& path, const McapLimits& limits) {
  return std::make_unique<mcap::McapRecording>(path, OpenFileSource(path), limits);
}

std::unique_ptr<Recording> OpenMcapBuffer(const std::string& name, std::vector<uint8_t> bytes,
                                          const McapLimits& limits) {
  return std::make_unique<mcap::McapRecording>(name, MemorySource(std::move(bytes)), limits);
}

}  // namespace wallcal::recording
