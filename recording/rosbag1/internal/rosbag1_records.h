// SPDX-License-Identifier: Apache-2.0
#pragma once
// The record layer of the ROS 1 bag format v2.0 (wiki.ros.org/Bags/Format/2.0), shared by the
// reader and the writer. Internal to io/.
//
// A bag is "#ROSBAG V2.0\n" followed by records. Each record: uint32 header_len, header (fields
// of uint32 field_len + "name=value", the value binary), uint32 data_len, data. The header's
// "op" field (one byte) says what the record is. All integers little-endian.

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "recording/internal/byte_source.h"

namespace wallcal::recording::bag1 {

inline constexpr char kMagic[] = "#ROSBAG V2.0\n";
inline constexpr size_t kMagicSize = 13;
// rosbag pads the bag header record to 4096 bytes so it can be rewritten in place at close.
inline constexpr size_t kBagHeaderRecordSize = 4096;
// No real record header is near this; a larger one is damage (bounded before allocating).
inline constexpr uint32_t kMaxHeaderBytes = 1u << 20;

enum Op : uint8_t {
  kOpMessageData = 0x02,
  kOpBagHeader = 0x03,
  kOpIndexData = 0x04,
  kOpChunk = 0x05,
  kOpChunkInfo = 0x06,
  kOpConnection = 0x07,
};

// Bag time: uint32 sec + uint32 nsec, kept as integer nanoseconds for exact ordering.
inline int64_t TimeNs(uint32_t sec, uint32_t nsec) {
  return static_cast<int64_t>(sec) * 1000000000 + static_cast<int64_t>(nsec);
}
// Seconds as a double, from the two parts (keeps the most precision a double can).
inline double TimeSeconds(int64_t time_ns) {
  const int64_t sec = time_ns / 1000000000;
  return static_cast<double>(sec) + 1e-9 * static_cast<double>(time_ns - sec * 1000000000);
}

inline uint32_t LoadU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}
inline uint64_t LoadU64(const uint8_t* p) {
  return static_cast<uint64_t>(LoadU32(p)) | static_cast<uint64_t>(LoadU32(p + 4)) << 32;
}
inline int64_t LoadTimeNs(const uint8_t* p) { return TimeNs(LoadU32(p), LoadU32(p + 4)); }

// The fields of one record header (views into the caller's buffer).
struct Fields {
  std::vector<std::pair<std::string_view, std::string_view>> items;
  // The value of `name`, or nullptr when absent.
  const std::string_view* Find(std::string_view name) const;
  // The bytes of `name` when it holds exactly `size` of them, else nullptr.
  const uint8_t* Sized(std::string_view name, size_t size) const;
  // Fixed-size integer fields; false when absent or of the wrong size.
  bool U8(std::string_view name, uint8_t* value) const;
  bool U32(std::string_view name, uint32_t* value) const;
  bool U64(std::string_view name, uint64_t* value) const;
  bool Time(std::string_view name, int64_t* time_ns) const;
};

// Splits a header into fields. Returns "" on success, else what is wrong (a field length past
// the end, a field without '=').
std::string ParseFields(const uint8_t* data, size_t size, Fields* fields);

// A connection record's data (its own header): the message type and md5sum of connection
// `conn`. Returns "" on success, else what is wrong, ready for a "file:offset: " prefix.
struct ConnectionHeader {
  std::string type;
  std::string md5sum;
};
std::string ParseConnectionHeader(const uint8_t* data, size_t size, uint32_t conn,
                                  ConnectionHeader* header);

// One record located in a byte range: where its parts are, and its header fields. Not
// copyable: `fields` views into `header_bytes`.
struct RecordRef {
  RecordRef() = default;
  RecordRef(const RecordRef&) = delete;
  RecordRef& operator=(const RecordRef&) = delete;
  uint64_t pos = 0;  // offset of header_len
  std::vector<uint8_t> header_bytes;
  Fields fields;  // views into header_bytes
  uint8_t op = 0;
  uint64_t data_pos = 0;  // offset of the data
  uint32_t data_len = 0;  // as declared
  uint64_t end() const { return data_pos + data_len; }
};

enum class RecordStatus {
  kOk,
  kCut,        // the range ends inside the record (header or declared data)
  kMalformed,  // header unparsable, no op field, or a length beyond any sane value
};

// Reads the record at `pos` of a source whose usable bytes end at `limit`. On kCut/kMalformed
// *why says what (for the caller's io::InputError or warning). A record whose data runs past
// `limit` is kCut with the header still filled.
RecordStatus ReadRecord(const ByteSource& source, uint64_t pos, uint64_t limit, RecordRef* record,
                        std::string* why);
// The same over a buffer (a decompressed chunk).
RecordStatus ReadRecord(const uint8_t* data, size_t size, size_t pos, RecordRef* record,
                        std::string* why);

// Builders for the writer.
void AddField(std::string* header, std::string_view name, const void* value, size_t size);
void AddField(std::string* header, std::string_view name, std::string_view value);
void AddU32Field(std::string* header, std::string_view name, uint32_t value);
void AddU64Field(std::string* header, std::string_view name, uint64_t value);
void AddTimeField(std::string* header, std::string_view name, int64_t time_ns);
void AppendU32(std::vector<uint8_t>* out, uint32_t value);
void AppendU64(std::vector<uint8_t>* out, uint64_t value);
void AppendRecord(std::vector<uint8_t>* out, const std::string& header, const uint8_t* data,
                  size_t size);

}  // namespace wallcal::recording::bag1
