// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random-access bytes of a recording (a ROS 1 bag, an MCAP file): a file read with pread, or a
// buffer in memory (tests, fuzzing). Internal to recording/. Reads past the end are the caller's
// bug: callers bound every offset and length by size() first.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace wallcal::recording {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // The bytes there are (a file: as long as it was when opened).
  virtual uint64_t size() const = 0;
  // Copies [offset, offset + n) into out; throws io::InputError when the system read fails.
  virtual void Read(uint64_t offset, size_t n, uint8_t* out) const = 0;

  // [offset, offset + n) as a vector. A range past the end is a caller's bug: std::logic_error
  // (exit 3), never a huge allocation.
  std::vector<uint8_t> Bytes(uint64_t offset, uint64_t n) const;
  // zlib crc32 of [offset, offset + n), continuing from `crc`; streamed in 1 MiB pieces.
  uint32_t Crc(uint64_t offset, uint64_t n, uint32_t crc) const;
};

// Throws io::InputError naming `path` when it cannot be opened or is not a regular file.
std::unique_ptr<ByteSource> OpenFileSource(const std::string& path);
std::unique_ptr<ByteSource> MemorySource(std::vector<uint8_t> bytes);

}  // namespace wallcal::recording
