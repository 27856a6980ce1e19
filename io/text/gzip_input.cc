// SPDX-License-Identifier: Apache-2.0
#include "io/text/internal/gzip_input.h"

#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>

#include "io/types.h"

namespace wallcal::io {
namespace {

constexpr int kBufferBytes = 1 << 16;

}  // namespace

bool IsGzipFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[2] = {0, 0};
  if (!in.read(magic, 2)) return false;
  return static_cast<unsigned char>(magic[0]) == 0x1f && static_cast<unsigned char>(magic[1]) == 0x8b;
}

void* OpenGzip(const std::string& path, const std::string& what, unsigned buffer_bytes) {
  errno = 0;
  gzFile file = gzopen(path.c_str(), "rb");
  if (file == nullptr) {
    throw InputError(Where(path, 0, "cannot open " + what + ": " +
                                        (errno != 0 ? std::strerror(errno) : "out of memory")));
  }
  gzbuffer(file, buffer_bytes);
  return file;
}

GzipStreamBuf::GzipStreamBuf(const std::string& path, int64_t max_bytes)
    : max_bytes_(max_bytes), buffer_(new char[kBufferBytes]) {
  gz_ = OpenGzip(path, "the gzip file", 1 << 17);
  setg(buffer_.get(), buffer_.get(), buffer_.get());
}

GzipStreamBuf::~GzipStreamBuf() {
  if (gz_ != nullptr) gzclose(static_cast<gzFile>(gz_));
}

GzipStreamBuf::int_type GzipStreamBuf::underflow() {
  if (gptr() < egptr()) return traits_type::to_int_type(*gptr());
  if (state_ != GzipState::kOk) return traits_type::eof();
  const int64_t room = max_bytes_ - bytes_read_;
  if (room <= 0) {
    // One byte more than allowed tells a file of exactly max_bytes from a larger one.
    char probe = 0;
    if (gzread(static_cast<gzFile>(gz_), &probe, 1) == 1) state_ = GzipState::kTooLarge;
    return traits_type::eof();
  }
  const unsigned want = static_cast<unsigned>(std::min<int64_t>(kBufferBytes, room));
  const int got = gzread(static_cast<gzFile>(gz_), buffer_.get(), want);
  if (got <= 0) {
    int error = Z_OK;
    gzerror(static_cast<gzFile>(gz_), &error);
    // zlib reports a stream that ends early as Z_BUF_ERROR ("unexpected end of file").
    if (error == Z_BUF_ERROR) {
      state_ = GzipState::kCutOff;
    } else if (got < 0 || error != Z_OK) {
      state_ = GzipState::kCorrupt;
    }
    return traits_type::eof();
  }
  bytes_read_ += got;
  setg(buffer_.get(), buffer_.get(), buffer_.get() + got);
  return traits_type::to_int_type(*gptr());
}

GzipStreamBuf::pos_type GzipStreamBuf::seekoff(off_type offset, std::ios_base::seekdir dir,
                                               std::ios_base::openmode which) {
  if (offset == 0 && dir == std::ios_base::beg) return seekpos(pos_type(0), which);
  return pos_type(off_type(-1));  // only a rewind is supported
}

GzipStreamBuf::pos_type GzipStreamBuf::seekpos(pos_type position, std::ios_base::openmode which) {
  if (position != pos_type(0) || (which & std::ios_base::in) == 0) return pos_type(off_type(-1));
  // Corrupt data stay reported (zlib refuses to rewind past a data error). A cut-off or
  // oversized stream is read again from the start and meets the same end at the same place.
  if (state_ == GzipState::kCorrupt || gzrewind(static_cast<gzFile>(gz_)) != 0) {
    state_ = GzipState::kCorrupt;
    return pos_type(off_type(-1));
  }
  state_ = GzipState::kOk;
  bytes_read_ = 0;
  setg(buffer_.get(), buffer_.get(), buffer_.get());
  return pos_type(0);
}

std::string GzipStreamBuf::Problem() const {
  const std::string after = std::to_string(bytes_read_) + " uncompressed bytes";
  switch (state_) {
    case GzipState::kOk:
      return "";
    case GzipState::kCutOff:
      return "the gzip stream is cut off after " + after + "; expected a complete gzip file";
    case GzipState::kCorrupt:
      return "the gzip data are corrupt after " + after + "; expected a valid gzip file";
    case GzipState::kTooLarge:
      return "more than " + std::to_string(max_bytes_) +
             " bytes uncompressed; expected at most that (a larger file must be read uncompressed)";
  }
  return "";
}

}  // namespace wallcal::io
