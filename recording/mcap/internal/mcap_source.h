// SPDX-License-Identifier: Apache-2.0
#pragma once
// Random-access bytes for the MCAP reader: a file read with pread, or a buffer in memory (tests,
// fuzzing). Internal to io/. Reads past the end are the caller's bug: callers bound every
// offset and length by size() first.

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace wallcal::recording::mcap {

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  virtual uint64_t size() const = 0;
  // Copies [offset, offset + n) into out; throws io::InputError when the system read fails.
  virtual void Read(uint64_t offset, size_t n, uint8_t* out) const = 0;

  // A range past the end is a caller's bug: std::logic_error (exit 3), never a huge allocation.
  std::vector<uint8_t> Bytes(uint64_t offset, uint64_t n) const {
    if (offset > size() || n > size() - offset) {
      throw std::logic_error("MCAP reader: bytes [" + std::to_string(offset) + ", +" +
                             std::to_string(n) + ") asked of a " + std::to_string(size()) +
                             "-byte source");
    }
    std::vector<uint8_t> out(static_cast<size_t>(n));
    if (n > 0) Read(offset, static_cast<size_t>(n), out.data());
    return out;
  }
  // zlib crc32 of [offset, offset + n), continuing from `crc`; streamed in 1 MiB pieces.
  uint32_t Crc(uint64_t offset, uint64_t n, uint32_t crc) const;
};

// Throws io::InputError naming `path` when it cannot be opened.
std::unique_ptr<ByteSource> OpenFileSource(const std::string& path);
std::unique_ptr<ByteSource> MemorySource(std::vector<uint8_t> bytes);

}  // namespace wallcal::recording::mcap
