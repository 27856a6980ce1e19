// SPDX-License-Identifier: Apache-2.0
#include "recording/mcap/internal/mcap_compression.h"

#include <lz4frame.h>
#include <zstd.h>

#include <algorithm>
#include <stdexcept>

#include "common/enum_text.h"
#include "recording/rosbag1/internal/bag_compression.h"

namespace wallcal::recording {
namespace {

// First allocation: what the input could plausibly hold, so a chunk that lies about its size
// costs memory only in proportion to the data that really decompresses.
size_t InitialCapacity(size_t in_size, uint64_t limit) {
  const uint64_t guess = std::max<uint64_t>(uint64_t{1} << 16, uint64_t{4} * in_size);
  return static_cast<size_t>(std::min(guess, limit));
}

// Output buffer one byte larger than declared: a stream that fills it is too long.
bool Grow(std::vector<uint8_t>* out, uint64_t limit) {
  if (out->size() >= limit) return false;
  out->resize(static_cast<size_t>(std::min<uint64_t>(limit, uint64_t{2} * out->size())));
  return true;
}

InflateStatus InflateZstd(const uint8_t* data, size_t size, uint64_t expected,
                          std::vector<uint8_t>* out) {
  const uint64_t limit = expected + 1;
  ZSTD_DCtx* ctx = ZSTD_createDCtx();
  if (ctx == nullptr) throw std::bad_alloc();
  out->assign(InitialCapacity(size, limit), 0);
  ZSTD_inBuffer in{data, size, 0};
  size_t produced = 0;
  InflateStatus status = InflateStatus::kOk;
  size_t pending = 1;  // nonzero: a frame is open
  while (true) {
    if (produced == out->size() && !Grow(out, limit)) {
      status = InflateStatus::kTooLong;
      break;
    }
    ZSTD_outBuffer ob{out->data(), out->size(), produced};
    const size_t in_before = in.pos;
    pending = ZSTD_decompressStream(ctx, &ob, &in);
    if (ZSTD_isError(pending)) {
      status = InflateStatus::kCorrupt;
      break;
    }
    const bool progressed = ob.pos != produced || in.pos != in_before;
    produced = ob.pos;
    if (pending == 0 && in.pos == in.size) break;  // last frame closed, input used up
    if (!progressed && ob.pos < ob.size) {         // starved: input ended inside a frame
      status = InflateStatus::kCorrupt;
      break;
    }
  }
  ZSTD_freeDCtx(ctx);
  if (status == InflateStatus::kOk && produced > expected) status = InflateStatus::kTooLong;
  if (status == InflateStatus::kOk && produced < expected) status = InflateStatus::kTooShort;
  out->resize(std::min<size_t>(produced, out->size()));
  return status;
}

// The one LZ4 frame decoder (ROS 1 bags' roslz4 chunks are the same frame format); its
// outcome in this container's terms.
InflateStatus InflateLz4(const uint8_t* data, size_t size, uint64_t expected,
                         std::vector<uint8_t>* out) {
  const DecompressOutcome outcome =
      DecompressLz4Frame(data, size, static_cast<size_t>(expected), out);
  switch (outcome.status) {
    case DecompressStatus::kOk:
      return InflateStatus::kOk;
    case DecompressStatus::kSizeMismatch:
      return out->size() > expected ? InflateStatus::kTooLong : InflateStatus::kTooShort;
    case DecompressStatus::kCorrupt:
    case DecompressStatus::kCutOff:
      break;
  }
  return InflateStatus::kCorrupt;
}

}  // namespace

InflateStatus Inflate(Codec codec, const uint8_t* data, size_t size, uint64_t expected_size,
                      std::vector<uint8_t>* out) {
  if (size == 0) {  // nothing to decode: right only when nothing was declared
    out->clear();
    return expected_size == 0 ? InflateStatus::kOk : InflateStatus::kTooShort;
  }
  return codec == Codec::kZstd ? InflateZstd(data, size, expected_size, out)
                               : InflateLz4(data, size, expected_size, out);
}

std::vector<uint8_t> Deflate(Codec codec, const uint8_t* data, size_t size) {
  std::vector<uint8_t> out;
  if (codec == Codec::kZstd) {
    out.resize(ZSTD_compressBound(size));
    const size_t n = ZSTD_compress(out.data(), out.size(), data, size, 3);
    if (ZSTD_isError(n)) throw std::runtime_error(ZSTD_getErrorName(n));
    out.resize(n);
  } else {
    out.resize(LZ4F_compressFrameBound(size, nullptr));
    const size_t n = LZ4F_compressFrame(out.data(), out.size(), data, size, nullptr);
    if (LZ4F_isError(n)) throw std::runtime_error(LZ4F_getErrorName(n));
    out.resize(n);
  }
  return out;
}

const char* InflateStatusText(InflateStatus status) {
  static const EnumText<InflateStatus> kTexts[] = {
      {InflateStatus::kOk, "ok"},
      {InflateStatus::kCorrupt, "the compressed data is damaged"},
      {InflateStatus::kTooLong, "it decompresses to more bytes than declared"},
      {InflateStatus::kTooShort, "it decompresses to fewer bytes than declared"}};
  return TextOf(kTexts, status, "?");
}

}  // namespace wallcal::recording
