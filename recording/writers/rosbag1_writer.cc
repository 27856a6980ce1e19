// SPDX-License-Identifier: Apache-2.0
#include "recording/writers/rosbag1_writer.h"

#include <cerrno>
#include <cmath>
#include <cstring>

#include "common/enum_text.h"
#include "io/types.h"
#include "recording/rosbag1/internal/bag_compression.h"
#include "recording/rosbag1/internal/rosbag1_records.h"

namespace wallcal::recording {
namespace {

int64_t SecondsToNs(double seconds) {
  if (!(seconds > 0.0)) return 0;  // negative and NaN: the epoch (bag time is unsigned)
  double whole = std::floor(seconds);
  int64_t nsec = std::llround((seconds - whole) * 1e9);
  if (nsec >= 1000000000) {
    whole += 1.0;
    nsec -= 1000000000;
  }
  if (whole > 4294967295.0) return int64_t{4294967295} * 1000000000 + 999999999;
  return static_cast<int64_t>(whole) * 1000000000 + nsec;
}

const char* CompressionName(ChunkCompression compression) {
  static const EnumText<ChunkCompression> kTexts[] = {{ChunkCompression::kBz2, "bz2"},
                                                      {ChunkCompression::kLz4, "lz4"}};
  return TextOf(kTexts, compression, "none");
}

}  // namespace

Ros1BagWriter::Ros1BagWriter(const std::string& path, ChunkCompression compression,
                             size_t chunk_bytes)
    : path_(path),
      part_path_(path + ".part"),
      compression_(compression),
      chunk_bytes_(chunk_bytes) {
  if (compression == ChunkCompression::kZstd) {
    throw io::InputError(io::Where(path, 0, "ROS 1 bags have no zstd chunks (none, bz2 or lz4)"));
  }
  file_ = std::fopen(part_path_.c_str(), "wb");
  if (file_ == nullptr) {
    throw io::InputError(
        io::Where(part_path_, 0, std::string("cannot write: ") + std::strerror(errno)));
  }
  WriteBytes(bag1::kMagic, bag1::kMagicSize);
  WriteBagHeader(0);  // rewritten by Close()
}

Ros1BagWriter::~Ros1BagWriter() {
  if (file_ != nullptr) {
    std::fclose(file_);
    std::remove(part_path_.c_str());
  }
}

int Ros1BagWriter::AddConnection(const std::string& topic, RosType type) {
  return AddConnection(topic, RosTypeName(type), RosTypeMd5(type),
                       RosTypeDefinition(type, WireFormat::kRos1));
}

int Ros1BagWriter::AddConnection(const std::string& topic, const std::string& type_name,
                                 const std::string& md5sum, const std::string& definition) {
  connections_.push_back({topic, type_name, md5sum, definition, false});
  return static_cast<int>(connections_.size() - 1);
}

void Ros1BagWriter::WriteBytes(const void* data, size_t size) {
  if (file_ == nullptr) throw io::InputError(io::Where(path_, 0, "bag already closed"));
  if (size > 0 && std::fwrite(data, 1, size, file_) != size) {
    throw io::InputError(
        io::Where(part_path_, 0, std::string("write failed: ") + std::strerror(errno)));
  }
  position_ += size;
}

void Ros1BagWriter::WriteBagHeader(uint64_t index_pos) {
  // Fields in rosbag's (alphabetical) order, here and in every record.
  std::string header;
  const uint8_t op = bag1::kOpBagHeader;
  bag1::AddU32Field(&header, "chunk_count", static_cast<uint32_t>(chunk_infos_.size()));
  bag1::AddU32Field(&header, "conn_count", static_cast<uint32_t>(connections_.size()));
  bag1::AddU64Field(&header, "index_pos", index_pos);
  bag1::AddField(&header, "op", &op, 1);
  // Padded with spaces to a fixed size so that Close() can rewrite it in place.
  const std::vector<uint8_t> padding(bag1::kBagHeaderRecordSize - 8 - header.size(), ' ');
  std::vector<uint8_t> record;
  bag1::AppendRecord(&record, header, padding.data(), padding.size());
  WriteBytes(record.data(), record.size());
}

void Ros1BagWriter::AppendConnectionRecord(std::vector<uint8_t>* out, uint32_t id) const {
  const ConnectionInfo& c = connections_[id];
  std::string header;
  const uint8_t op = bag1::kOpConnection;
  bag1::AddU32Field(&header, "conn", id);
  bag1::AddField(&header, "op", &op, 1);
  bag1::AddField(&header, "topic", c.topic);
  std::string data;
  bag1::AddField(&data, "topic", c.topic);
  bag1::AddField(&data, "type", c.type);
  bag1::AddField(&data, "md5sum", c.md5sum);
  bag1::AddField(&data, "message_definition", c.definition);
  bag1::AppendRecord(out, header, reinterpret_cast<const uint8_t*>(data.data()), data.size());
}

void Ros1BagWriter::Write(int connection, double receive_s, const uint8_t* payload, size_t size) {
  if (file_ == nullptr) throw io::InputError(io::Where(path_, 0, "bag already closed"));
  if (connection < 0 || static_cast<size_t>(connection) >= connections_.size()) {
    throw io::InputError(io::Where(path_, 0, "no connection " + std::to_string(connection)));
  }
  const uint32_t id = static_cast<uint32_t>(connection);
  // rosbag puts a connection's record into the chunk of its first message as well, so that a
  // bag that was never closed (no index) still says what its messages are.
  if (!connections_[id].written) {
    AppendConnectionRecord(&chunk_, id);
    connections_[id].written = true;
  }
  const int64_t time_ns = SecondsToNs(receive_s);
  std::string header;
  const uint8_t op = bag1::kOpMessageData;
  bag1::AddU32Field(&header, "conn", id);
  bag1::AddField(&header, "op", &op, 1);
  bag1::AddTimeField(&header, "time", time_ns);
  if (chunk_index_.empty()) {
    chunk_start_ns_ = chunk_end_ns_ = time_ns;
  }
  chunk_start_ns_ = std::min(chunk_start_ns_, time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, time_ns);
  chunk_index_[id].emplace_back(time_ns, static_cast<uint32_t>(chunk_.size()));
  bag1::AppendRecord(&chunk_, header, payload, size);
  if (chunk_.size() >= chunk_bytes_) FlushChunk();
}

void Ros1BagWriter::FlushChunk() {
  if (chunk_index_.empty()) return;
  std::vector<uint8_t> stored;
  if (compression_ == ChunkCompression::kBz2) {
    stored = CompressBz2(chunk_.data(), chunk_.size());
  } else if (compression_ == ChunkCompression::kLz4) {
    stored = CompressLz4Frame(chunk_.data(), chunk_.size());
  } else {
    stored.swap(chunk_);
  }
  ChunkInfo info;
  info.pos = position_;
  info.start_ns = chunk_start_ns_;
  info.end_ns = chunk_end_ns_;
  std::string header;
  const uint8_t op = bag1::kOpChunk;
  bag1::AddField(&header, "compression", CompressionName(compression_));
  bag1::AddField(&header, "op", &op, 1);
  const size_t uncompressed =
      compression_ == ChunkCompression::kNone ? stored.size() : chunk_.size();
  bag1::AddU32Field(&header, "size", static_cast<uint32_t>(uncompressed));
  std::vector<uint8_t> out;
  bag1::AppendRecord(&out, header, stored.data(), stored.size());
  // One index-data record per connection: (time, offset in the uncompressed chunk) per message.
  for (const auto& [id, entries] : chunk_index_) {
    std::string index_header;
    const uint8_t index_op = bag1::kOpIndexData;
    bag1::AddU32Field(&index_header, "conn", id);
    bag1::AddU32Field(&index_header, "count", static_cast<uint32_t>(entries.size()));
    bag1::AddField(&index_header, "op", &index_op, 1);
    bag1::AddU32Field(&index_header, "ver", 1);
    std::vector<uint8_t> data;
    for (const auto& [time_ns, offset] : entries) {
      bag1::AppendU32(&data, static_cast<uint32_t>(time_ns / 1000000000));
      bag1::AppendU32(&data, static_cast<uint32_t>(time_ns % 1000000000));
      bag1::AppendU32(&data, offset);
    }
    bag1::AppendRecord(&out, index_header, data.data(), data.size());
    info.counts[id] = static_cast<uint32_t>(entries.size());
  }
  WriteBytes(out.data(), out.size());
  chunk_infos_.push_back(std::move(info));
  chunk_.clear();
  chunk_index_.clear();
}

void Ros1BagWriter::Close() {
  if (file_ == nullptr) throw io::InputError(io::Where(path_, 0, "bag already closed"));
  FlushChunk();
  const uint64_t index_pos = position_;
  std::vector<uint8_t> out;
  for (uint32_t id = 0; id < connections_.size(); ++id) AppendConnectionRecord(&out, id);
  for (const ChunkInfo& info : chunk_infos_) {
    std::string header;
    const uint8_t op = bag1::kOpChunkInfo;
    bag1::AddU64Field(&header, "chunk_pos", info.pos);
    bag1::AddU32Field(&header, "count", static_cast<uint32_t>(info.counts.size()));
    bag1::AddTimeField(&header, "end_time", info.end_ns);
    bag1::AddField(&header, "op", &op, 1);
    bag1::AddTimeField(&header, "start_time", info.start_ns);
    bag1::AddU32Field(&header, "ver", 1);
    std::vector<uint8_t> data;
    for (const auto& [id, count] : info.counts) {
      bag1::AppendU32(&data, id);
      bag1::AppendU32(&data, count);
    }
    bag1::AppendRecord(&out, header, data.data(), data.size());
  }
  WriteBytes(out.data(), out.size());
  if (std::fseek(file_, static_cast<long>(bag1::kMagicSize), SEEK_SET) != 0) {
    throw io::InputError(io::Where(part_path_, 0, "cannot seek back to the bag header"));
  }
  WriteBagHeader(index_pos);
  const bool closed = std::fclose(file_) == 0;
  file_ = nullptr;
  if (!closed || std::rename(part_path_.c_str(), path_.c_str()) != 0) {
    std::remove(part_path_.c_str());
    throw io::InputError(
        io::Where(path_, 0, std::string("cannot finish the bag: ") + std::strerror(errno)));
  }
}

}  // namespace wallcal::recording
