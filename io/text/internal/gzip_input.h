// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading gzip-compressed text files through a std::istream, for the readers that take a stream
// (NMEA, survey). Memory stays bounded: the file is inflated in small pieces as it is read, not
// held whole. The stream can be rewound to its start (seekg(0)), which re-inflates from the
// beginning: the NMEA reader reads its log twice.

#include <cstdint>
#include <istream>
#include <memory>
#include <streambuf>
#include <string>

namespace wallcal::io {

// True when the file begins with the gzip magic bytes 1f 8b. False for a missing or short file.
bool IsGzipFile(const std::string& path);

// Opens a plain or gzip file through zlib for reading, with an input buffer of buffer_bytes.
// Returns the gzFile (opaque here: zlib stays out of this header). Throws InputError
// "path: cannot open <what>: <reason>" when it cannot.
void* OpenGzip(const std::string& path, const std::string& what, unsigned buffer_bytes);

// How reading a gzip file ended so far.
enum class GzipState {
  kOk,        // no problem met (yet)
  kCutOff,    // the compressed stream ends early: everything before the cut was delivered
  kCorrupt,   // the compressed data are invalid (or the file could not be read)
  kTooLarge,  // more than max_bytes uncompressed: reading stopped there
};

// A std::streambuf inflating a gzip file. Reading ends (end of file) at the end of the data, at a
// cut-off stream, at corrupt data, or after max_bytes uncompressed bytes; state() says which.
class GzipStreamBuf : public std::streambuf {
 public:
  // Throws InputError (file: message) when the file cannot be opened.
  GzipStreamBuf(const std::string& path, int64_t max_bytes);
  ~GzipStreamBuf() override;
  GzipStreamBuf(const GzipStreamBuf&) = delete;
  GzipStreamBuf& operator=(const GzipStreamBuf&) = delete;

  GzipState state() const { return state_; }
  // Uncompressed bytes delivered since the last rewind.
  int64_t bytes_read() const { return bytes_read_; }
  // A sentence for an InputError about state(): "gzip data are corrupt after N uncompressed
  // bytes; expected a valid gzip file", and the like. Empty for kOk.
  std::string Problem() const;

 protected:
  int_type underflow() override;
  pos_type seekoff(off_type offset, std::ios_base::seekdir dir,
                   std::ios_base::openmode which) override;
  pos_type seekpos(pos_type position, std::ios_base::openmode which) override;

 private:
  void* gz_ = nullptr;  // gzFile, kept opaque so this header does not include zlib.h
  int64_t max_bytes_;
  int64_t bytes_read_ = 0;
  GzipState state_ = GzipState::kOk;
  std::unique_ptr<char[]> buffer_;
};

}  // namespace wallcal::io
