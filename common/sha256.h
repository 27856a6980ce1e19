#pragma once
// SHA-256 (FIPS 180-4) of bytes and of files, for the provenance of offsets.yaml: which input
// files a calibration was computed from. Written here from the standard; no external library.

#include <array>
#include <cstddef>
#include <cstdint>
#include <atomic>
#include <string>

namespace wallcal {

// Incremental SHA-256: Update() any number of times, then Hex() once.
class Sha256 {
 public:
  Sha256();
  void Update(const void* data, size_t size);
  // The digest as 64 lowercase hex digits. Finishes the hash: call once.
  std::string Hex();

 private:
  void Block(const uint8_t* block);
  std::array<uint32_t, 8> state_;
  std::array<uint8_t, 64> buffer_{};
  size_t buffered_ = 0;
  uint64_t total_bytes_ = 0;
};

// The SHA-256 of a string's bytes, 64 lowercase hex digits.
std::string Sha256Hex(const std::string& bytes);

// The SHA-256 of a file's bytes (read in 1 MiB blocks), or an empty string when the path is not
// a regular file (never opened then) or cannot be read.
std::string Sha256OfFile(const std::string& path);
// The same, giving up (empty string) as soon as *cancel is true (checked between blocks).
std::string Sha256OfFile(const std::string& path, const std::atomic<bool>* cancel);

}  // namespace wallcal
