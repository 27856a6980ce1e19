// SPDX-License-Identifier: Apache-2.0
#pragma once
// Chunk codecs for MCAP (and rosbag2 files that store MCAP): zstd (libzstd) and lz4 in its frame
// format (liblz4's LZ4F, as MCAP's registry names it). Decompression never writes more than the
// container declared: the output grows only as real data arrives, up to `expected_size`.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace wallcal::recording {

enum class Codec { kZstd, kLz4 };

enum class InflateStatus {
  kOk,
  kCorrupt,   // the codec rejected the stream (or it ended mid-frame)
  kTooLong,   // more bytes than declared
  kTooShort,  // the stream ended before the declared size
};

// Decompresses `size` bytes into `out` (replaced), expecting exactly `expected_size` bytes.
InflateStatus Inflate(Codec codec, const uint8_t* data, size_t size, uint64_t expected_size,
                      std::vector<uint8_t>* out);

// Compresses into one frame (zstd level 3 / lz4 default preferences).
std::vector<uint8_t> Deflate(Codec codec, const uint8_t* data, size_t size);

const char* InflateStatusText(InflateStatus status);

}  // namespace wallcal::recording
