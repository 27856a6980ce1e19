// SPDX-License-Identifier: Apache-2.0
#include "recording/rosbag1/internal/rosbag1_records.h"

#include <cerrno>
#include <cstring>

#include "io/types.h"

namespace wallcal::recording::bag1 {
namespace {

RecordStatus FinishRecord(uint64_t pos, uint64_t header_end, uint32_t data_len, uint64_t limit,
                          RecordRef* record, std::string* why) {
  record->pos = pos;
  record->data_pos = header_end + 4;
  record->data_len = data_len;
  const std::string problem =
      ParseFields(record->header_bytes.data(), record->header_bytes.size(), &record->fields);
  if (!problem.empty()) {
    *why = "record header: " + problem;
    return RecordStatus::kMalformed;
  }
  if (!record->fields.U8("op", &record->op)) {
    *why = "record header has no one-byte 'op' field";
    return RecordStatus::kMalformed;
  }
  if (record->end() > limit) {
    *why = "record declares " + std::to_string(data_len) + " data bytes, " +
           std::to_string(limit - record->data_pos) + " present";
    return RecordStatus::kCut;
  }
  return RecordStatus::kOk;
}

}  // namespace

const std::string_view* Fields::Find(std::string_view name) const {
  for (const auto& item : items) {
    if (item.first == name) return &item.second;
  }
  return nullptr;
}

const uint8_t* Fields::Sized(std::string_view name, size_t size) const {
  const std::string_view* v = Find(name);
  return v != nullptr && v->size() == size ? reinterpret_cast<const uint8_t*>(v->data()) : nullptr;
}

bool Fields::U8(std::string_view name, uint8_t* value) const {
  const uint8_t* bytes = Sized(name, 1);
  if (bytes != nullptr) *value = bytes[0];
  return bytes != nullptr;
}

bool Fields::U32(std::string_view name, uint32_t* value) const {
  const uint8_t* bytes = Sized(name, 4);
  if (bytes != nullptr) *value = LoadU32(bytes);
  return bytes != nullptr;
}

bool Fields::U64(std::string_view name, uint64_t* value) const {
  const uint8_t* bytes = Sized(name, 8);
  if (bytes != nullptr) *value = LoadU64(bytes);
  return bytes != nullptr;
}

bool Fields::Time(std::string_view name, int64_t* time_ns) const {
  const uint8_t* bytes = Sized(name, 8);
  if (bytes != nullptr) *time_ns = LoadTimeNs(bytes);
  return bytes != nullptr;
}

std::string ParseFields(const uint8_t* data, size_t size, Fields* fields) {
  fields->items.clear();
  size_t pos = 0;
  while (pos < size) {
    if (size - pos < 4) return "field length cut off at header byte " + std::to_string(pos);
    const uint32_t length = LoadU32(data + pos);
    pos += 4;
    if (length > size - pos) {
      return "field of " + std::to_string(length) + " bytes at header byte " +
             std::to_string(pos - 4) + " runs past the header's end";
    }
    const std::string_view field(reinterpret_cast<const char*>(data + pos), length);
    const size_t equals = field.find('=');
    if (equals == std::string_view::npos) {
      return "field at header byte " + std::to_string(pos - 4) + " has no '='";
    }
    fields->items.emplace_back(field.substr(0, equals), field.substr(equals + 1));
    pos += length;
  }
  return "";
}

std::string ParseConnectionHeader(const uint8_t* data, size_t size, uint32_t conn,
                                  ConnectionHeader* header) {
  Fields fields;
  const std::string problem = ParseFields(data, size, &fields);
  if (!problem.empty()) return "connection header: " + problem;
  const std::string_view* type = fields.Find("type");
  const std::string_view* md5sum = fields.Find("md5sum");
  if (type == nullptr || md5sum == nullptr) {
    return "connection " + std::to_string(conn) + " lacks its type or md5sum";
  }
  header->type = std::string(*type);
  header->md5sum = std::string(*md5sum);
  return "";
}

RecordStatus ReadRecord(const ByteSource& source, uint64_t pos, uint64_t limit, RecordRef* record,
                        std::string* why) {
  record->pos = pos;
  record->op = 0;
  if (pos > limit || limit - pos < 4) {
    *why = "record header length cut off";
    return RecordStatus::kCut;
  }
  uint8_t word[4];
  source.Read(pos, 4, word);
  const uint32_t header_len = LoadU32(word);
  if (header_len > kMaxHeaderBytes) {
    *why = "record header of " + std::to_string(header_len) + " bytes (no real one is near " +
           std::to_string(kMaxHeaderBytes) + ")";
    return RecordStatus::kMalformed;
  }
  // header + the data length after it
  if (limit - pos - 4 < static_cast<uint64_t>(header_len) + 4) {
    *why = "record header of " + std::to_string(header_len) + " bytes cut off";
    return RecordStatus::kCut;
  }
  record->header_bytes = source.Bytes(pos + 4, header_len);
  source.Read(pos + 4 + header_len, 4, word);
  return FinishRecord(pos, pos + 4 + header_len, LoadU32(word), limit, record, why);
}

RecordStatus ReadRecord(const uint8_t* data, size_t size, size_t pos, RecordRef* record,
                        std::string* why) {
  record->pos = pos;
  record->op = 0;
  if (pos > size || size - pos < 4) {
    *why = "record header length cut off";
    return RecordStatus::kCut;
  }
  const uint32_t header_len = LoadU32(data + pos);
  if (header_len > kMaxHeaderBytes) {
    *why = "record header of " + std::to_string(header_len) + " bytes";
    return RecordStatus::kMalformed;
  }
  if (size - pos - 4 < static_cast<uint64_t>(header_len) + 4) {
    *why = "record header of " + std::to_string(header_len) + " bytes cut off";
    return RecordStatus::kCut;
  }
  record->header_bytes.assign(data + pos + 4, data + pos + 4 + header_len);
  return FinishRecord(pos, pos + 4 + header_len, LoadU32(data + pos + 4 + header_len), size, record,
                      why);
}

void AddField(std::string* header, std::string_view name, const void* value, size_t size) {
  const uint32_t length = static_cast<uint32_t>(name.size() + 1 + size);
  for (int i = 0; i < 4; ++i) header->push_back(static_cast<char>(length >> (8 * i)));
  header->append(name);
  header->push_back('=');
  header->append(static_cast<const char*>(value), size);
}

void AddField(std::string* header, std::string_view name, std::string_view value) {
  AddField(header, name, value.data(), value.size());
}

void AddU32Field(std::string* header, std::string_view name, uint32_t value) {
  char bytes[4];
  for (int i = 0; i < 4; ++i) bytes[i] = static_cast<char>(value >> (8 * i));
  AddField(header, name, bytes, 4);
}

void AddU64Field(std::string* header, std::string_view name, uint64_t value) {
  char bytes[8];
  for (int i = 0; i < 8; ++i) bytes[i] = static_cast<char>(value >> (8 * i));
  AddField(header, name, bytes, 8);
}

void AddTimeField(std::string* header, std::string_view name, int64_t time_ns) {
  const uint64_t sec = static_cast<uint64_t>(time_ns / 1000000000);
  const uint64_t nsec = static_cast<uint64_t>(time_ns % 1000000000);
  AddU64Field(header, name, (sec & 0xffffffffu) | nsec << 32);
}

void AppendU32(std::vector<uint8_t>* out, uint32_t value) {
  for (int i = 0; i < 4; ++i) out->push_back(static_cast<uint8_t>(value >> (8 * i)));
}

void AppendU64(std::vector<uint8_t>* out, uint64_t value) {
  for (int i = 0; i < 8; ++i) out->push_back(static_cast<uint8_t>(value >> (8 * i)));
}

void AppendRecord(std::vector<uint8_t>* out, const std::string& header, const uint8_t* data,
                  size_t size) {
  AppendU32(out, static_cast<uint32_t>(header.size()));
  out->insert(out->end(), header.begin(), header.end());
  AppendU32(out, static_cast<uint32_t>(size));
  if (size > 0) out->insert(out->end(), data, data + size);
}

}  // namespace wallcal::recording::bag1
