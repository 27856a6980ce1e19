// SPDX-License-Identifier: Apache-2.0
#include "recording/writers/mcap_writer.h"

#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include "common/enum_text.h"
#include "recording/mcap/internal/mcap_compression.h"
#include "recording/mcap/internal/mcap_records.h"

namespace wallcal::recording {
namespace {

uint64_t ToNs(double t_s) {
  if (!(t_s >= 0.0) || t_s > 1.8e10) throw std::invalid_argument("MCAP time out of range");
  return static_cast<uint64_t>(std::llround(t_s * 1e9));
}

uint32_t Crc(uint32_t crc, const std::vector<uint8_t>& bytes) {
  return static_cast<uint32_t>(crc32(crc, bytes.data(), static_cast<uInt>(bytes.size())));
}

const char* CompressionName(ChunkCompression c) {
  static const EnumText<ChunkCompression> kTexts[] = {{ChunkCompression::kZstd, "zstd"},
                                                      {ChunkCompression::kLz4, "lz4"}};
  return TextOf(kTexts, c, "");
}

}  // namespace

McapWriter::McapWriter(const std::string& path, ChunkCompression compression, size_t chunk_bytes)
    : path_(path), compression_(compression), chunk_bytes_(chunk_bytes) {
  if (compression == ChunkCompression::kBz2) {
    throw std::invalid_argument("MCAP chunks are uncompressed, zstd or lz4; not bz2");
  }
  std::string pattern = path + ".tmp-XXXXXX";
  const int fd = ::mkstemp(pattern.data());
  if (fd < 0) Fail(std::string("cannot create a temporary file: ") + std::strerror(errno));
  temp_path_ = pattern;
  ::fchmod(fd, 0644);  // mkstemp makes it 0600; a recording is meant to be read by others
  file_ = ::fdopen(fd, "wb");
  if (file_ == nullptr) {
    ::close(fd);
    Fail("cannot open the temporary file");
  }
  mcap::Out out;
  out.Raw(mcap::kMagic, mcap::kMagicSize);
  const size_t at = out.Begin(mcap::kHeader);
  out.Str("ros2");
  out.Str("wallcal");
  out.End(at);
  Emit(out.bytes);
}

McapWriter::~McapWriter() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::remove(temp_path_.c_str());
  }
}

void McapWriter::Fail(const std::string& what) {
  if (file_ != nullptr) {
    std::fclose(file_);
    file_ = nullptr;
  }
  if (!temp_path_.empty()) std::remove(temp_path_.c_str());
  throw io::InputError(io::Where(path_, 0, what));
}

void McapWriter::Emit(const std::vector<uint8_t>& bytes) {
  if (bytes.empty()) return;
  if (std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) {
    Fail(std::string("write failed: ") + std::strerror(errno));
  }
  crc_ = Crc(crc_, bytes);
  position_ += bytes.size();
}

uint16_t McapWriter::AddChannel(const std::string& topic, const std::string& type_name,
                                const std::string& definition) {
  if (channel_count_ == UINT16_MAX) throw std::length_error("too many MCAP channels");
  auto schema = schema_ids_.find(type_name);
  if (schema == schema_ids_.end()) {
    const uint16_t id = static_cast<uint16_t>(schema_ids_.size() + 1);  // 0 means "no schema"
    mcap::Out out;
    const size_t at = out.Begin(mcap::kSchema);
    out.U16(id);
    out.Str(type_name);
    out.Str("ros2msg");
    out.Str(definition);  // uint32 length-prefixed bytes: the same layout as a string
    out.End(at);
    schema_records_.push_back(out.bytes);
    chunk_.insert(chunk_.end(), out.bytes.begin(), out.bytes.end());
    schema = schema_ids_.emplace(type_name, id).first;
  }
  const uint16_t id = ++channel_count_;  // ids from 1, as rosbag2 numbers them
  mcap::Out out;
  const size_t at = out.Begin(mcap::kChannel);
  out.U16(id);
  out.U16(schema->second);
  out.Str(topic);
  out.Str("cdr");
  mcap::Out metadata;  // rosbag2 stores the QoS here; an empty value is accepted by readers
  metadata.Str("offered_qos_profiles");
  metadata.Str("");
  out.U32(static_cast<uint32_t>(metadata.bytes.size()));
  out.Raw(metadata.bytes.data(), metadata.bytes.size());
  out.End(at);
  channel_records_.push_back(out.bytes);
  chunk_.insert(chunk_.end(), out.bytes.begin(), out.bytes.end());
  message_counts_[id] = 0;
  return id;
}

void McapWriter::Write(uint16_t channel, double log_time_s, double publish_time_s,
                       const uint8_t* data, size_t size) {
  WriteNs(channel, ToNs(log_time_s), ToNs(publish_time_s), data, size);
}

void McapWriter::WriteNs(uint16_t channel, uint64_t log_time_ns, uint64_t publish_time_ns,
                         const uint8_t* data, size_t size) {
  if (channel == 0 || channel > channel_count_)
    throw std::invalid_argument("MCAP channel not added");
  const uint64_t sequence = message_counts_[channel]++;
  chunk_index_[channel].emplace_back(log_time_ns, chunk_.size());
  mcap::Out out;
  out.bytes.swap(chunk_);
  const size_t at = out.Begin(mcap::kMessage);
  out.U16(channel);
  out.U32(static_cast<uint32_t>(sequence));
  out.U64(log_time_ns);
  out.U64(publish_time_ns);
  out.Raw(data, size);
  out.End(at);
  out.bytes.swap(chunk_);
  chunk_start_ns_ = std::min(chunk_start_ns_, log_time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, log_time_ns);
  first_ns_ = std::min(first_ns_, log_time_ns);
  last_ns_ = std::max(last_ns_, log_time_ns);
  ++messages_;
  if (chunk_.size() >= chunk_bytes_) FlushChunk();
}

void McapWriter::FlushChunk() {
  if (chunk_.empty()) return;
  const bool has_messages = chunk_start_ns_ != UINT64_MAX;
  ChunkIndexEntry entry;
  entry.start_ns = has_messages ? chunk_start_ns_ : 0;
  entry.end_ns = has_messages ? chunk_end_ns_ : 0;
  entry.uncompressed_size = chunk_.size();
  std::vector<uint8_t> packed;
  if (compression_ != ChunkCompression::kNone) {
    packed = Deflate(compression_ == ChunkCompression::kZstd ? Codec::kZstd : Codec::kLz4,
                     chunk_.data(), chunk_.size());
  }
  const std::vector<uint8_t>& records = compression_ == ChunkCompression::kNone ? chunk_ : packed;
  entry.compressed_size = records.size();
  mcap::Out out;
  const size_t at = out.Begin(mcap::kChunk);
  out.U64(entry.start_ns);
  out.U64(entry.end_ns);
  out.U64(chunk_.size());
  out.U32(Crc(0, chunk_));
  out.Str(CompressionName(compression_));
  out.U64(records.size());
  out.Raw(records.data(), records.size());
  out.End(at);
  entry.offset = position_;
  entry.length = out.bytes.size();
  Emit(out.bytes);

  mcap::Out index;
  for (const auto& kv : chunk_index_) {
    entry.index_offsets[kv.first] = position_ + index.bytes.size();
    const size_t index_at = index.Begin(mcap::kMessageIndex);
    index.U16(kv.first);
    index.U32(static_cast<uint32_t>(kv.second.size() * 16));
    for (const auto& e : kv.second) {
      index.U64(e.first);
      index.U64(e.second);
    }
    index.End(index_at);
  }
  entry.index_length = index.bytes.size();
  Emit(index.bytes);
  chunks_.push_back(entry);
  chunk_.clear();
  chunk_index_.clear();
  chunk_start_ns_ = UINT64_MAX;
  chunk_end_ns_ = 0;
}

void McapWriter::Close() {
  if (file_ == nullptr) throw std::logic_error("McapWriter::Close called twice");
  FlushChunk();
  mcap::Out data_end;
  const size_t at = data_end.Begin(mcap::kDataEnd);
  data_end.U32(crc_);
  data_end.End(at);
  Emit(data_end.bytes);

  // Summary: records grouped by opcode, each group listed by a Summary Offset record.
  const uint64_t summary_start = position_;
  crc_ = 0;
  struct Group {
    uint8_t opcode;
    uint64_t start, length;
  };
  std::vector<Group> groups;
  auto emit_group = [&](uint8_t opcode, const std::vector<std::vector<uint8_t>>& records) {
    if (records.empty()) return;
    const uint64_t start = position_;
    for (const auto& r : records) Emit(r);
    groups.push_back({opcode, start, position_ - start});
  };
  emit_group(mcap::kSchema, schema_records_);
  emit_group(mcap::kChannel, channel_records_);
  mcap::Out stats;
  const size_t stats_at = stats.Begin(mcap::kStatistics);
  stats.U64(messages_);
  stats.U16(static_cast<uint16_t>(schema_ids_.size()));
  stats.U32(channel_count_);
  stats.U32(0);  // attachments
  stats.U32(0);  // metadata
  stats.U32(static_cast<uint32_t>(chunks_.size()));
  stats.U64(messages_ > 0 ? first_ns_ : 0);
  stats.U64(messages_ > 0 ? last_ns_ : 0);
  stats.U32(static_cast<uint32_t>(message_counts_.size() * 10));
  for (const auto& kv : message_counts_) {
    stats.U16(kv.first);
    stats.U64(kv.second);
  }
  stats.End(stats_at);
  emit_group(mcap::kStatistics, {stats.bytes});
  std::vector<std::vector<uint8_t>> indexes;
  for (const ChunkIndexEntry& e : chunks_) {
    mcap::Out out;
    const size_t index_at = out.Begin(mcap::kChunkIndex);
    out.U64(e.start_ns);
    out.U64(e.end_ns);
    out.U64(e.offset);
    out.U64(e.length);
    out.U32(static_cast<uint32_t>(e.index_offsets.size() * 10));
    for (const auto& kv : e.index_offsets) {
      out.U16(kv.first);
      out.U64(kv.second);
    }
    out.U64(e.index_length);
    out.Str(CompressionName(compression_));
    out.U64(e.compressed_size);
    out.U64(e.uncompressed_size);
    out.End(index_at);
    indexes.push_back(out.bytes);
  }
  emit_group(mcap::kChunkIndex, indexes);
  const uint64_t offsets_start = position_;
  for (const Group& g : groups) {
    mcap::Out out;
    const size_t offset_at = out.Begin(mcap::kSummaryOffset);
    out.U8(g.opcode);
    out.U64(g.start);
    out.U64(g.length);
    out.End(offset_at);
    Emit(out.bytes);
  }
  mcap::Out footer;
  footer.U8(mcap::kFooter);
  footer.U64(mcap::kFooterContentSize);
  footer.U64(summary_start);
  footer.U64(offsets_start);
  footer.U32(Crc(crc_, footer.bytes));  // the CRC runs through summary_offset_start
  footer.Raw(mcap::kMagic, mcap::kMagicSize);
  Emit(footer.bytes);

  if (std::fflush(file_) != 0 || ::fsync(::fileno(file_)) != 0) {
    Fail(std::string("cannot flush: ") + std::strerror(errno));
  }
  std::FILE* f = file_;
  file_ = nullptr;
  if (std::fclose(f) != 0) Fail("cannot close the temporary file");
  if (std::rename(temp_path_.c_str(), path_.c_str()) != 0) {
    Fail(std::string("cannot rename the temporary file over it: ") + std::strerror(errno));
  }
}

}  // namespace wallcal::recording
