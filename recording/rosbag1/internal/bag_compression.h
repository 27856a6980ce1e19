// SPDX-License-Identifier: Apache-2.0
#pragma once
// Chunk (de)compression for ROS 1 bags: bz2 (libbz2, one stream per chunk) and lz4 in the LZ4
// *frame* format as ROS's roslz4 writes it (magic 0x184D2204, independent blocks, content
// checksum, no content size, no block checksums; liblz4's LZ4F API reads and writes that).
// Internal to io/.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace wallcal::recording {

// What became of a decompression, typed.
enum class DecompressStatus {
  kOk,            // the stream ended and produced exactly the expected size
  kCorrupt,       // the library rejected the data (bad magic, checksum, block)
  kSizeMismatch,  // the stream ended with more or fewer bytes than expected
  kCutOff,        // the input ended before the stream did (a truncated file)
};

struct DecompressOutcome {
  DecompressStatus status = DecompressStatus::kOk;
  std::string detail;  // for people: the library's error, the sizes
};

// Decompresses `size` bytes into *out. `expected_size` (the chunk's declared uncompressed size)
// bounds the output: memory grows with what the stream really produces, never beyond
// expected_size + 1 bytes, so a hostile declared size costs nothing until data backs it. On
// kCutOff and kCorrupt, *out holds what was decompressed before the problem (for reading a
// recording up to its damage).
DecompressOutcome DecompressBz2(const uint8_t* data, size_t size, size_t expected_size,
                                std::vector<uint8_t>* out);
DecompressOutcome DecompressLz4Frame(const uint8_t* data, size_t size, size_t expected_size,
                                     std::vector<uint8_t>* out);

// Compressors for the bag writer. Both abort-free: they return the compressed bytes.
std::vector<uint8_t> CompressBz2(const uint8_t* data, size_t size);
std::vector<uint8_t> CompressLz4Frame(const uint8_t* data, size_t size);

}  // namespace wallcal::recording
