// SPDX-License-Identifier: Apache-2.0
#pragma once
// SHA-256 (FIPS 180-4) of bytes and of files, for the provenance of offsets.yaml: which input
// files a calibration was computed from. Computed by OpenSSL's libcrypto (Debian libssl-dev),
// which uses the CPU's SHA extensions where it has them: an hour-long scan log (350 MB) is
// hashed in a fraction of a second instead of 1.7 s (docs/results.md, "Speed").

#include <atomic>
#include <cstddef>
#include <memory>
#include <string>

namespace wallcal {

// Incremental SHA-256: Update() any number of times, then Hex() once.
class Sha256 {
 public:
  Sha256();
  ~Sha256();
  Sha256(const Sha256&) = delete;
  Sha256& operator=(const Sha256&) = delete;
  void Update(const void* data, size_t size);
  // The digest as 64 lowercase hex digits. Finishes the hash: call once.
  std::string Hex();

 private:
  struct Context;
  std::unique_ptr<Context> context_;
};

// The SHA-256 of a string's bytes, 64 lowercase hex digits.
std::string Sha256Hex(const std::string& bytes);

// The SHA-256 of a file's bytes (read in 1 MiB blocks), or an empty string when the path is not
// a regular file (never opened then) or cannot be read.
std::string Sha256OfFile(const std::string& path);
// The same, giving up (empty string) as soon as *cancel is true (checked between blocks).
std::string Sha256OfFile(const std::string& path, const std::atomic<bool>* cancel);

}  // namespace wallcal
