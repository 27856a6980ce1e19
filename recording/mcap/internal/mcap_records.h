// SPDX-License-Identifier: Apache-2.0
#pragma once
// MCAP building blocks shared by io/mcap_reader.cc and io/mcap_writer.cc: opcodes, the magic,
// little-endian encoding, and a bounds-checked cursor over one record's bytes. Format: the MCAP
// specification (mcap.dev/spec, records and serialization sections). Internal to io/.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::recording::mcap {

inline constexpr uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};
inline constexpr size_t kMagicSize = 8;
inline constexpr size_t kRecordHeaderSize = 9;    // opcode (1) + content length (uint64)
inline constexpr size_t kFooterContentSize = 20;  // summary_start, summary_offset_start, crc

enum Opcode : uint8_t {
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

// "path:offset: message": the byte offset is from the start of the file.
std::string At(const std::string& path, uint64_t offset, const std::string& message);

inline uint16_t GetU16(const uint8_t* p) { return static_cast<uint16_t>(p[0] | (p[1] << 8)); }
inline uint32_t GetU32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}
inline uint64_t GetU64(const uint8_t* p) {
  return static_cast<uint64_t>(GetU32(p)) | (static_cast<uint64_t>(GetU32(p + 4)) << 32);
}

// Appends little-endian values to a byte vector (the writer's serialization).
struct Out {
  std::vector<uint8_t> bytes;
  void U8(uint8_t v) { bytes.push_back(v); }
  void U16(uint16_t v) {
    for (int i = 0; i < 2; ++i) bytes.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void U32(uint32_t v) {
    for (int i = 0; i < 4; ++i) bytes.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void U64(uint64_t v) {
    for (int i = 0; i < 8; ++i) bytes.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void Raw(const uint8_t* p, size_t n) { bytes.insert(bytes.end(), p, p + n); }
  void Str(const std::string& s) {
    U32(static_cast<uint32_t>(s.size()));
    Raw(reinterpret_cast<const uint8_t*>(s.data()), s.size());
  }
  // Opens a record: writes the opcode and a length placeholder; returns where the length sits.
  size_t Begin(uint8_t opcode) {
    U8(opcode);
    const size_t at = bytes.size();
    U64(0);
    return at;
  }
  void End(size_t length_at) {
    const uint64_t n = bytes.size() - length_at - 8;
    for (int i = 0; i < 8; ++i) bytes[length_at + i] = static_cast<uint8_t>(n >> (8 * i));
  }
};

// Reads fields of one record's content. Every read is checked against what is left; a short
// record throws io::InputError "path:offset: <record> record cut short reading <field> ...", with
// `offset` the record's start in the file (for records inside a chunk: the chunk's start).
class Cursor {
 public:
  Cursor(const uint8_t* data, size_t size, const std::string& path, uint64_t offset,
         const char* record)
      : data_(data), size_(size), path_(path), offset_(offset), record_(record) {}

  uint8_t U8(const char* field) { return *Take(1, field); }
  uint16_t U16(const char* field) { return GetU16(Take(2, field)); }
  uint32_t U32(const char* field) { return GetU32(Take(4, field)); }
  uint64_t U64(const char* field) { return GetU64(Take(8, field)); }
  std::string Str(const char* field) {
    const uint32_t n = U32(field);
    const uint8_t* p = Take(n, field);
    return std::string(reinterpret_cast<const char*>(p), n);
  }
  // A uint32 byte length followed by that many bytes (Schema data, arrays, maps): a sub-cursor.
  Cursor Sub32(const char* field) {
    const uint32_t n = U32(field);
    return Cursor(Take(n, field), n, path_, offset_, record_);
  }
  const uint8_t* Take(uint64_t n, const char* field) {
    if (n > size_ - pos_) {
      throw io::InputError(At(path_, offset_,
                              std::string(record_) + " record cut short reading " + field +
                                  ": needs " + std::to_string(n) + " bytes, " +
                                  std::to_string(size_ - pos_) + " left"));
    }
    const uint8_t* p = data_ + pos_;
    pos_ += static_cast<size_t>(n);
    return p;
  }
  size_t left() const { return size_ - pos_; }
  size_t pos() const { return pos_; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
  const std::string& path_;
  uint64_t offset_;
  const char* record_;
};

}  // namespace wallcal::recording::mcap
