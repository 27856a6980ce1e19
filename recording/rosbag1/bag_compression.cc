// SPDX-License-Identifier: Apache-2.0
#include "recording/rosbag1/internal/bag_compression.h"

#include <bzlib.h>
#include <lz4frame.h>

#include <algorithm>
#include <cassert>
#include <cstring>
#include <limits>
#include <memory>

namespace wallcal::recording {
namespace {

// Output grows geometrically from a guess, up to expected + 1 bytes: one byte beyond the
// declared size is enough to notice a stream that produces more than it should.
size_t GrownCapacity(size_t current, size_t input_size, size_t expected_size) {
  const size_t limit = expected_size + 1;
  size_t next = current == 0 ? std::max<size_t>(input_size * 4, 64 * 1024) : current * 2;
  return std::min(next, limit);
}

// Before each decompression step: room in *out for more output. False, with *outcome saying
// so, when the output already holds more than the declared size.
bool MakeRoom(const char* codec, size_t produced, size_t input_size, size_t expected_size,
              std::vector<uint8_t>* out, DecompressOutcome* outcome) {
  if (produced < out->size()) return true;
  if (out->size() > expected_size) {
    *outcome = {DecompressStatus::kSizeMismatch, std::string(codec) + ": more than the " +
                                                     std::to_string(expected_size) +
                                                     " bytes declared"};
    return false;
  }
  out->resize(GrownCapacity(out->size(), input_size, expected_size));
  return true;
}

std::string SizeText(size_t produced, size_t expected) {
  return std::to_string(produced) + " bytes decompressed, " + std::to_string(expected) +
         " declared";
}

}  // namespace

DecompressOutcome DecompressBz2(const uint8_t* data, size_t size, size_t expected_size,
                                std::vector<uint8_t>* out) {
  out->clear();
  bz_stream stream;
  std::memset(&stream, 0, sizeof(stream));
  if (BZ2_bzDecompressInit(&stream, 0, 0) != BZ_OK) {
    return {DecompressStatus::kCorrupt, "bz2: could not start the decompressor"};
  }
  // bz2 counts in unsigned int: feed at most 1 GiB at a time.
  constexpr size_t kStep = size_t{1} << 30;
  size_t in_pos = 0;
  size_t produced = 0;
  DecompressOutcome outcome;
  while (true) {
    if (!MakeRoom("bz2", produced, size, expected_size, out, &outcome)) break;
    const size_t in_step = std::min(size - in_pos, kStep);
    const size_t out_step = std::min(out->size() - produced, kStep);
    stream.next_in = const_cast<char*>(reinterpret_cast<const char*>(data + in_pos));
    stream.avail_in = static_cast<unsigned int>(in_step);
    stream.next_out = reinterpret_cast<char*>(out->data() + produced);
    stream.avail_out = static_cast<unsigned int>(out_step);
    const int rc = BZ2_bzDecompress(&stream);
    in_pos += in_step - stream.avail_in;
    produced += out_step - stream.avail_out;
    if (rc == BZ_STREAM_END) {
      if (produced != expected_size) {
        outcome = {DecompressStatus::kSizeMismatch, "bz2: " + SizeText(produced, expected_size)};
      }
      break;
    }
    if (rc != BZ_OK) {
      outcome = {DecompressStatus::kCorrupt,
                 "bz2: corrupt data (libbz2 error " + std::to_string(rc) + ")"};
      break;
    }
    // BZ_OK with room left to write and nothing left to read: the stream was cut off.
    if (stream.avail_out > 0 && in_pos == size) {
      outcome = {DecompressStatus::kCutOff, "bz2: input ends before the stream does"};
      break;
    }
  }
  BZ2_bzDecompressEnd(&stream);
  out->resize(std::min(produced, out->size()));
  return outcome;
}

DecompressOutcome DecompressLz4Frame(const uint8_t* data, size_t size, size_t expected_size,
                                     std::vector<uint8_t>* out) {
  out->clear();
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION))) {
    return {DecompressStatus::kCorrupt, "lz4: could not start the decompressor"};
  }
  std::unique_ptr<LZ4F_dctx, decltype(&LZ4F_freeDecompressionContext)> owner(
      context, &LZ4F_freeDecompressionContext);
  size_t in_pos = 0;
  size_t produced = 0;
  DecompressOutcome outcome;
  while (true) {
    if (!MakeRoom("lz4", produced, size, expected_size, out, &outcome)) break;
    size_t out_step = out->size() - produced;
    size_t in_step = size - in_pos;
    const size_t hint = LZ4F_decompress(context, out->data() + produced, &out_step, data + in_pos,
                                        &in_step, nullptr);
    in_pos += in_step;
    produced += out_step;
    if (LZ4F_isError(hint)) {
      outcome = {DecompressStatus::kCorrupt,
                 std::string("lz4: corrupt frame (") + LZ4F_getErrorName(hint) + ")"};
      break;
    }
    if (hint == 0) {  // the frame ended (its content checksum verified)
      if (produced != expected_size) {
        outcome = {DecompressStatus::kSizeMismatch, "lz4: " + SizeText(produced, expected_size)};
      }
      break;
    }
    if (in_pos == size && produced < out->size()) {
      outcome = {DecompressStatus::kCutOff, "lz4: input ends before the frame does"};
      break;
    }
    if (in_step == 0 && out_step == 0 && produced < out->size()) {
      // No progress with input and output room left: cannot happen with a sane library; stop
      // rather than spin.
      outcome = {DecompressStatus::kCorrupt, "lz4: decompressor made no progress"};
      break;
    }
  }
  out->resize(std::min(produced, out->size()));
  return outcome;
}

std::vector<uint8_t> CompressBz2(const uint8_t* data, size_t size) {
  assert(size < std::numeric_limits<unsigned int>::max() / 2);
  // libbz2's documented worst case: 1% larger plus 600 bytes.
  unsigned int capacity = static_cast<unsigned int>(size + size / 100 + 600);
  std::vector<uint8_t> out(capacity);
  const int rc = BZ2_bzBuffToBuffCompress(reinterpret_cast<char*>(out.data()), &capacity,
                                          const_cast<char*>(reinterpret_cast<const char*>(data)),
                                          static_cast<unsigned int>(size), 9, 0, 0);
  assert(rc == BZ_OK);
  (void)rc;
  out.resize(capacity);
  return out;
}

std::vector<uint8_t> CompressLz4Frame(const uint8_t* data, size_t size) {
  // What roslz4 writes and insists on reading: independent 1 MB blocks, a content checksum, no
  // content size, no block checksums.
  LZ4F_preferences_t preferences;
  std::memset(&preferences, 0, sizeof(preferences));
  preferences.frameInfo.blockSizeID = LZ4F_max1MB;
  preferences.frameInfo.blockMode = LZ4F_blockIndependent;
  preferences.frameInfo.contentChecksumFlag = LZ4F_contentChecksumEnabled;
  preferences.frameInfo.contentSize = 0;
  preferences.frameInfo.blockChecksumFlag = LZ4F_noBlockChecksum;
  std::vector<uint8_t> out(LZ4F_compressFrameBound(size, &preferences));
  const size_t written = LZ4F_compressFrame(out.data(), out.size(), data, size, &preferences);
  assert(!LZ4F_isError(written));
  out.resize(written);
  return out;
}

}  // namespace wallcal::recording
