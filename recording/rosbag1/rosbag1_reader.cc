// SPDX-License-Identifier: Apache-2.0
#include "recording/rosbag1/internal/rosbag1_reader.h"

#include <algorithm>
#include <cstring>
#include <set>
#include <tuple>

#include "io/types.h"
#include "recording/rosbag1/internal/bag_compression.h"
#include "recording/rosbag1/internal/rosbag1_records.h"

namespace wallcal::recording {
namespace {

using bag1::RecordRef;
using bag1::RecordStatus;

// Index-data records (version 1) hold one 12-byte entry per message: time (8) + offset (4).
constexpr uint64_t kIndexEntryBytes = 12;
// A chunk's declared uncompressed size beyond this is damage, not data (rosbag's chunks are
// 768 kB by default; one big message, a point cloud or an image, makes a chunk of its own size,
// tens of MB at most).
constexpr uint32_t kMaxChunkBytes = 256u << 20;

std::string Quoted(std::string_view text) {
  std::string out = "'";
  for (char c : text.substr(0, 40)) out += (c >= 32 && c < 127) ? c : '?';
  return out + (text.size() > 40 ? "...'" : "'");
}

}  // namespace

std::unique_ptr<Recording> OpenRos1Bag(const std::string& path) {
  return std::make_unique<Ros1Bag>(OpenFileSource(path), path);
}

std::unique_ptr<Recording> OpenRos1BagFromMemory(std::vector<uint8_t> bytes,
                                                 const std::string& name) {
  return std::make_unique<Ros1Bag>(MemorySource(std::move(bytes)), name);
}

Ros1Bag::~Ros1Bag() = default;

Ros1Bag::Ros1Bag(std::unique_ptr<ByteSource> source, const std::string& path)
    : source_(std::move(source)) {
  path_ = path;
  file_size_ = source_->size();
  ReadBagHeader();

  Index index;
  std::string problem;
  if (index_pos_ == 0) {
    problem = "no index (index_pos 0: the recording was not closed)";
  } else if (index_pos_ < first_record_pos_ || index_pos_ > file_size_) {
    problem = "index_pos " + std::to_string(index_pos_) + " is outside the file's " +
              std::to_string(file_size_) + " bytes (file cut off?)";
  } else {
    problem = ReadIndex(index_pos_, &index);
  }
  if (problem.empty()) {
    index_used_ = true;
  } else {
    warnings_.push_back(problem + ": records walked from the start instead");
    index = Index();
    WalkRecords(&index);
  }
  if (index.length_mismatches > 0) {
    warnings_.push_back(std::to_string(index.length_mismatches) +
                        " index-data record(s) declare a data length other than 12 bytes per "
                        "entry (first at byte " +
                        std::to_string(index.first_mismatch_pos) + "): read by their entry count");
  }
  BuildTopics(&index);
}

void Ros1Bag::Fail(uint64_t offset, const std::string& what) const {
  throw io::InputError(path_ + ":byte " + std::to_string(offset) + ": " + what);
}

void Ros1Bag::ReadBagHeader() {
  uint8_t magic[bag1::kMagicSize] = {0};
  const size_t have = static_cast<size_t>(std::min<uint64_t>(file_size_, bag1::kMagicSize));
  source_->Read(0, have, magic);
  const std::string_view start(reinterpret_cast<const char*>(magic), have);
  if (start != std::string_view(bag1::kMagic, bag1::kMagicSize)) {
    if (start.substr(0, 9) == "#ROSBAG V") {
      Fail(0, "ROS bag version " + Quoted(start.substr(9, 3)) + " is not read; expected V2.0");
    }
    Fail(0, "not a ROS 1 bag: expected '#ROSBAG V2.0' at the start");
  }
  RecordRef record;
  std::string why;
  const RecordStatus status =
      bag1::ReadRecord(*source_, bag1::kMagicSize, file_size_, &record, &why);
  if (status == RecordStatus::kMalformed || (status == RecordStatus::kCut && record.op == 0)) {
    Fail(bag1::kMagicSize, "bag header record: " + why);
  }
  uint32_t conn_count = 0;
  if (record.op != bag1::kOpBagHeader || !record.fields.U64("index_pos", &index_pos_) ||
      !record.fields.U32("conn_count", &conn_count) ||
      !record.fields.U32("chunk_count", &declared_chunks_)) {
    Fail(bag1::kMagicSize,
         "expected the bag header record (op 3 with index_pos, conn_count, "
         "chunk_count)");
  }
  // Its data is padding; a file cut inside it has no records to read.
  first_record_pos_ = std::min<uint64_t>(record.end(), file_size_);
}

std::string Ros1Bag::ReadIndex(uint64_t index_pos, Index* index) const {
  std::vector<std::pair<uint64_t, std::map<uint32_t, uint32_t>>> chunk_infos;
  uint64_t pos = index_pos;
  while (pos < file_size_) {
    RecordRef record;
    std::string why;
    if (bag1::ReadRecord(*source_, pos, file_size_, &record, &why) != RecordStatus::kOk) {
      return "index record at byte " + std::to_string(pos) + ": " + why;
    }
    const std::vector<uint8_t> data = source_->Bytes(record.data_pos, record.data_len);
    if (record.op == bag1::kOpConnection) {
      uint32_t conn = 0;
      const std::string_view* topic = record.fields.Find("topic");
      if (!record.fields.U32("conn", &conn) || topic == nullptr) {
        return "connection record at byte " + std::to_string(pos) + " lacks conn or topic";
      }
      try {
        AddConnection(pos, std::string(*topic), conn, data.data(), data.size(), index);
      } catch (const io::InputError& error) {
        return error.what();
      }
    } else if (record.op == bag1::kOpChunkInfo) {
      uint32_t version = 0, count = 0;
      uint64_t chunk_pos = 0;
      if (!record.fields.U32("ver", &version) || version != 1 ||
          !record.fields.U64("chunk_pos", &chunk_pos) || !record.fields.U32("count", &count) ||
          static_cast<uint64_t>(count) * 8 > data.size()) {
        return "chunk info record at byte " + std::to_string(pos) + " does not parse";
      }
      std::map<uint32_t, uint32_t> counts;
      for (uint32_t i = 0; i < count; ++i) {
        counts[bag1::LoadU32(&data[8 * i])] += bag1::LoadU32(&data[8 * i + 4]);
      }
      chunk_infos.emplace_back(chunk_pos, std::move(counts));
    } else {
      return "record op " + std::to_string(record.op) + " at byte " + std::to_string(pos) +
             " inside the index (expected connections and chunk infos)";
    }
    pos = record.end();
  }
  if (chunk_infos.size() != declared_chunks_) {
    return "the index lists " + std::to_string(chunk_infos.size()) + " chunks, the bag header " +
           std::to_string(declared_chunks_);
  }
  std::set<uint64_t> listed;
  for (const auto& [chunk_pos, counts] : chunk_infos) {
    // Listed twice, a chunk's entries would be counted (and held) twice.
    if (!listed.insert(chunk_pos).second) {
      return "the index lists the chunk at byte " + std::to_string(chunk_pos) + " twice";
    }
    const std::string problem = ReadChunkIndex(chunk_pos, counts, index);
    if (!problem.empty()) return problem;
  }
  std::sort(index->chunks.begin(), index->chunks.end(),
            [](const Chunk& a, const Chunk& b) { return a.record_pos < b.record_pos; });
  return "";
}

std::string Ros1Bag::ReadChunkIndex(uint64_t chunk_pos, const std::map<uint32_t, uint32_t>& counts,
                                    Index* index) const {
  const std::string at = "chunk at byte " + std::to_string(chunk_pos);
  RecordRef record;
  std::string why;
  if (chunk_pos < first_record_pos_ ||
      bag1::ReadRecord(*source_, chunk_pos, file_size_, &record, &why) != RecordStatus::kOk ||
      record.op != bag1::kOpChunk) {
    return at + " (from the index) is not a whole chunk record" + (why.empty() ? "" : ": " + why);
  }
  Chunk chunk;
  chunk.record_pos = chunk_pos;
  chunk.data_pos = record.data_pos;
  chunk.data_len = record.data_len;
  const std::string_view* compression = record.fields.Find("compression");
  if (!record.fields.U32("size", &chunk.size) || compression == nullptr) {
    return at + " lacks its compression or size";
  }
  chunk.compression = ParseCompression(chunk_pos, *compression);  // unknown: io::InputError
  // One index-data record per connection of the chunk follows it.
  uint64_t pos = record.end();
  std::map<uint32_t, uint32_t> found;
  for (size_t k = 0; k < counts.size(); ++k) {
    RecordRef entry_record;
    const RecordStatus status = bag1::ReadRecord(*source_, pos, file_size_, &entry_record, &why);
    uint32_t version = 0, conn = 0, count = 0;
    if (status == RecordStatus::kMalformed || entry_record.op != bag1::kOpIndexData ||
        !entry_record.fields.U32("ver", &version) || version != 1 ||
        !entry_record.fields.U32("conn", &conn) || !entry_record.fields.U32("count", &count)) {
      return "index data record " + std::to_string(k + 1) + " of the " + at +
             " missing or malformed (byte " + std::to_string(pos) + ")";
    }
    // Entries are read by count: some bags (rosbag of 2010) declare 20 bytes per entry.
    const uint64_t entry_bytes = kIndexEntryBytes * count;
    if (entry_bytes > file_size_ - entry_record.data_pos) {
      return "index data record at byte " + std::to_string(pos) + " runs past the file's end";
    }
    if (entry_bytes != entry_record.data_len) {
      if (index->length_mismatches++ == 0) index->first_mismatch_pos = pos;
    }
    const std::vector<uint8_t> bytes =
        source_->Bytes(entry_record.data_pos, static_cast<size_t>(entry_bytes));
    for (uint32_t i = 0; i < count; ++i) {
      const uint8_t* e = &bytes[kIndexEntryBytes * i];
      chunk.entries.push_back({bag1::LoadTimeNs(e), bag1::LoadU32(e + 8), conn});
    }
    found[conn] += count;
    pos = entry_record.data_pos + entry_bytes;
  }
  if (found != counts) {
    return "the index data after the " + at + " disagrees with its chunk info";
  }
  for (const Entry& entry : chunk.entries) {
    if (index->connections.count(entry.conn) == 0) {
      return "the " + at + " holds messages of connection " + std::to_string(entry.conn) +
             ", which has no connection record";
    }
  }
  index->chunks.push_back(std::move(chunk));
  return "";
}

ChunkCompression Ros1Bag::ParseCompression(uint64_t pos, std::string_view name) const {
  if (name == "none") return ChunkCompression::kNone;
  if (name == "bz2") return ChunkCompression::kBz2;
  if (name == "lz4") return ChunkCompression::kLz4;
  Fail(pos, "chunk compression " + Quoted(name) + " is not known; expected none, bz2 or lz4");
}

void Ros1Bag::AddConnection(uint64_t pos, const std::string& record_topic, uint32_t conn,
                            const uint8_t* data, size_t size, Index* index) const {
  if (index->connections.count(conn) > 0) return;  // written again in the index: same content
  bag1::ConnectionHeader header;
  const std::string problem = bag1::ParseConnectionHeader(data, size, conn, &header);
  if (!problem.empty()) Fail(pos, problem);
  Connection connection;
  connection.topic = record_topic;
  connection.type = std::move(header.type);
  connection.md5sum = std::move(header.md5sum);
  index->connections.emplace(conn, std::move(connection));
}

std::vector<uint8_t> Ros1Bag::LoadChunk(const Chunk& chunk) const {
  const std::vector<uint8_t> stored =
      source_->Bytes(chunk.data_pos, static_cast<size_t>(chunk.data_len));
  if (chunk.compression == ChunkCompression::kNone) {
    if (!chunk.cut && stored.size() != chunk.size) {
      Fail(chunk.record_pos, "uncompressed chunk holds " + std::to_string(stored.size()) +
                                 " bytes, declares " + std::to_string(chunk.size));
    }
    return stored;
  }
  if (chunk.size > kMaxChunkBytes) {
    Fail(chunk.record_pos, "chunk declares " + std::to_string(chunk.size) +
                               " uncompressed bytes (more than the " +
                               std::to_string(kMaxChunkBytes) + " accepted)");
  }
  std::vector<uint8_t> data;
  const DecompressOutcome outcome =
      chunk.compression == ChunkCompression::kBz2
          ? DecompressBz2(stored.data(), stored.size(), chunk.size, &data)
          : DecompressLz4Frame(stored.data(), stored.size(), chunk.size, &data);
  if (outcome.status != DecompressStatus::kOk && !chunk.cut) {
    Fail(chunk.record_pos, "chunk does not decompress: " + outcome.detail);
  }
  return data;
}

void Ros1Bag::WalkRecords(Index* index) {
  uint64_t pos = first_record_pos_;
  int64_t outside_chunks = 0;
  while (pos < file_size_) {
    RecordRef record;
    std::string why;
    const RecordStatus status = bag1::ReadRecord(*source_, pos, file_size_, &record, &why);
    if (status == RecordStatus::kMalformed) Fail(pos, why);
    uint64_t next = record.end();
    if (record.op == bag1::kOpChunk) {
      Chunk chunk;
      chunk.record_pos = pos;
      chunk.data_pos = record.data_pos;
      const std::string_view* compression = record.fields.Find("compression");
      if (!record.fields.U32("size", &chunk.size) || compression == nullptr) {
        Fail(pos, "chunk record lacks its compression or size");
      }
      chunk.compression = ParseCompression(pos, *compression);
      // rosbag writes a chunk's header with zero lengths and fixes them when the chunk closes:
      // zeros with bytes after them are a chunk that never closed, running to the file's end.
      const bool never_closed =
          record.data_len == 0 && chunk.size == 0 && record.data_pos < file_size_;
      chunk.cut = status == RecordStatus::kCut || never_closed;
      chunk.data_len = chunk.cut ? file_size_ - record.data_pos : record.data_len;
      const bool last = chunk.cut;
      WalkChunk(std::move(chunk), index);
      if (last) break;
      pos = next;
      continue;
    }
    if (status == RecordStatus::kCut) {
      warnings_.push_back("file ends inside a record at byte " + std::to_string(pos) + " (" + why +
                          "): nothing after it read");
      break;
    }
    if (record.op == bag1::kOpConnection) {
      uint32_t conn = 0;
      const std::string_view* topic = record.fields.Find("topic");
      if (!record.fields.U32("conn", &conn) || topic == nullptr) {
        Fail(pos, "connection record lacks conn or topic");
      }
      const std::vector<uint8_t> data = source_->Bytes(record.data_pos, record.data_len);
      AddConnection(pos, std::string(*topic), conn, data.data(), data.size(), index);
    } else if (record.op == bag1::kOpIndexData) {
      uint32_t version = 0, count = 0;
      if (record.fields.U32("ver", &version) && version == 1 &&
          record.fields.U32("count", &count) && kIndexEntryBytes * count != record.data_len) {
        // Read by count, as the index reading does (see ReadChunkIndex).
        if (index->length_mismatches++ == 0) index->first_mismatch_pos = pos;
        next = record.data_pos + kIndexEntryBytes * count;
        if (next > file_size_) {
          warnings_.push_back("file ends inside the index-data record at byte " +
                              std::to_string(pos) + ": nothing after it read");
          break;
        }
      }
    } else if (record.op == bag1::kOpMessageData) {
      ++outside_chunks;
    }
    pos = next;
  }
  if (outside_chunks > 0) {
    warnings_.push_back(std::to_string(outside_chunks) +
                        " message records outside any chunk left out");
  }
  // Walked chunks are already in file order.
}

void Ros1Bag::WalkChunk(Chunk chunk, Index* index) {
  const std::vector<uint8_t> data = LoadChunk(chunk);
  size_t pos = 0;
  std::string why;
  while (pos < data.size()) {
    RecordRef record;
    const RecordStatus status = bag1::ReadRecord(data.data(), data.size(), pos, &record, &why);
    if (status != RecordStatus::kOk) {
      if (chunk.cut) break;  // the damage is the cut: keep the whole records before it
      Fail(chunk.record_pos, "record at offset " + std::to_string(pos) + " of the chunk: " + why);
    }
    if (record.op == bag1::kOpMessageData) {
      uint32_t conn = 0;
      int64_t time_ns = 0;
      if (!record.fields.U32("conn", &conn) || !record.fields.Time("time", &time_ns)) {
        if (chunk.cut) break;
        Fail(chunk.record_pos, "message record at offset " + std::to_string(pos) +
                                   " of the chunk lacks conn or time");
      }
      chunk.entries.push_back({time_ns, static_cast<uint32_t>(pos), conn});
    } else if (record.op == bag1::kOpConnection) {
      uint32_t conn = 0;
      const std::string_view* topic = record.fields.Find("topic");
      if (record.fields.U32("conn", &conn) && topic != nullptr) {
        AddConnection(chunk.record_pos, std::string(*topic), conn, data.data() + record.data_pos,
                      record.data_len, index);
      }
    }
    pos = static_cast<size_t>(record.end());
  }
  if (chunk.cut) {
    warnings_.push_back("file ends inside the chunk at byte " + std::to_string(chunk.record_pos) +
                        " (" + std::to_string(chunk.data_len) +
                        " bytes of it present): " + std::to_string(chunk.entries.size()) +
                        " messages read from it, any after them lost");
  }
  index->chunks.push_back(std::move(chunk));
}

void Ros1Bag::BuildTopics(Index* index) {
  connections_ = std::move(index->connections);
  chunks_ = std::move(index->chunks);
  // One topic per name; its type is its first connection's.
  std::map<std::string, TopicInfo> by_name;
  for (auto& [id, connection] : connections_) {
    auto [it, added] = by_name.try_emplace(connection.topic);
    if (added) {
      it->second.name = connection.topic;
      it->second.type = connection.type;
      it->second.md5sum = connection.md5sum;
      it->second.encoding = "ros1";
    }
  }
  for (auto& [name, topic] : by_name) topics_.push_back(topic);
  for (auto& [id, connection] : connections_) {
    const auto it = std::lower_bound(
        topics_.begin(), topics_.end(), connection.topic,
        [](const TopicInfo& topic, const std::string& name) { return topic.name < name; });
    if (it->type == connection.type)
      connection.topic_index = static_cast<int>(it - topics_.begin());
  }
  std::map<uint32_t, int64_t> left_out;  // messages by connection
  for (Chunk& chunk : chunks_) {
    compressions_.insert(chunk.compression);
    // Messages of connections never declared (walked, damaged bag) cannot be typed: dropped.
    const auto known_end =
        std::partition(chunk.entries.begin(), chunk.entries.end(),
                       [&](const Entry& e) { return connections_.count(e.conn) > 0; });
    for (auto it = known_end; it != chunk.entries.end(); ++it) ++left_out[it->conn];
    chunk.entries.erase(known_end, chunk.entries.end());
    for (const Entry& entry : chunk.entries) {
      const Connection& connection = connections_.at(entry.conn);
      if (connection.topic_index < 0) {
        ++left_out[entry.conn];
        continue;
      }
      TopicInfo& topic = topics_[static_cast<size_t>(connection.topic_index)];
      const double t = bag1::TimeSeconds(entry.time_ns);
      if (topic.count == 0 || t < topic.first_s) topic.first_s = t;
      if (topic.count == 0 || t > topic.last_s) topic.last_s = t;
      ++topic.count;
    }
  }
  for (const auto& [conn, count] : left_out) {
    const auto it = connections_.find(conn);
    if (it == connections_.end()) {
      warnings_.push_back(std::to_string(count) + " messages of connection " +
                          std::to_string(conn) + ", which has no connection record, left out");
    } else {
      warnings_.push_back(std::to_string(count) + " messages of connection " +
                          std::to_string(conn) + " on " + it->second.topic + " left out: type " +
                          it->second.type + " differs from the topic's first connection");
    }
  }
}

void Ros1Bag::ForEach(const std::set<std::string>& topic_names,
                      const std::function<void(const RecordedMessage&)>& fn) {
  std::vector<bool> wanted(topics_.size(), false);
  for (const std::string& name : topic_names) {
    const auto it = std::find_if(topics_.begin(), topics_.end(),
                                 [&](const TopicInfo& topic) { return topic.name == name; });
    if (it == topics_.end()) {
      std::string present;
      for (const TopicInfo& topic : topics_) present += (present.empty() ? "" : ", ") + topic.name;
      throw io::InputError(io::Where(
          path_, 0,
          "no topic " + name + " in the bag; topics: " + (present.empty() ? "(none)" : present)));
    }
    wanted[static_cast<size_t>(it - topics_.begin())] = true;
  }
  struct Pending {
    int64_t time_ns;
    uint32_t chunk;
    uint32_t offset;
    uint32_t conn;
    int topic;
  };
  std::vector<Pending> pending;
  std::vector<int64_t> remaining(chunks_.size(), 0);
  for (size_t c = 0; c < chunks_.size(); ++c) {
    for (const Entry& entry : chunks_[c].entries) {
      const int topic = connections_.at(entry.conn).topic_index;
      if (topic < 0 || !wanted[static_cast<size_t>(topic)]) continue;
      pending.push_back({entry.time_ns, static_cast<uint32_t>(c), entry.offset, entry.conn, topic});
      ++remaining[c];
    }
  }
  // Receive time; ties in file order (chunks are in file order, then offset in the chunk).
  std::sort(pending.begin(), pending.end(), [](const Pending& a, const Pending& b) {
    return std::tie(a.time_ns, a.chunk, a.offset) < std::tie(b.time_ns, b.chunk, b.offset);
  });
  std::map<uint32_t, std::vector<uint8_t>> loaded;
  std::vector<int64_t> topic_index(topics_.size(), 0);
  for (const Pending& p : pending) {
    const Chunk& chunk = chunks_[p.chunk];
    auto it = loaded.find(p.chunk);
    if (it == loaded.end()) it = loaded.emplace(p.chunk, LoadChunk(chunk)).first;
    const std::vector<uint8_t>& data = it->second;
    RecordRef record;
    std::string why;
    const RecordStatus status = bag1::ReadRecord(data.data(), data.size(), p.offset, &record, &why);
    uint32_t conn = 0;
    if (status != RecordStatus::kOk || record.op != bag1::kOpMessageData ||
        !record.fields.U32("conn", &conn) || conn != p.conn) {
      Fail(
          chunk.record_pos,
          "message record at offset " + std::to_string(p.offset) +
              " of the chunk (from the index): " +
              (why.empty() ? "not a message record of connection " + std::to_string(p.conn) : why));
    }
    RecordedMessage message;
    message.topic = &topics_[static_cast<size_t>(p.topic)];
    message.wire = WireFormat::kRos1;
    message.receive_s = bag1::TimeSeconds(p.time_ns);
    message.data = data.data() + record.data_pos;
    message.size = record.data_len;
    message.index = topic_index[static_cast<size_t>(p.topic)]++;
    message.file_offset = chunk.record_pos;
    fn(message);
    if (--remaining[p.chunk] == 0) loaded.erase(p.chunk);
  }
}

}  // namespace wallcal::recording
