// SPDX-License-Identifier: Apache-2.0
#include "recording/internal/byte_source.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "io/types.h"

namespace wallcal::recording {

std::vector<uint8_t> ByteSource::Bytes(uint64_t offset, uint64_t n) const {
  if (offset > size() || n > size() - offset) {
    throw std::logic_error("recording reader: bytes [" + std::to_string(offset) + ", +" +
                           std::to_string(n) + ") asked of a " + std::to_string(size()) +
                           "-byte source");
  }
  std::vector<uint8_t> out(static_cast<size_t>(n));
  if (n > 0) Read(offset, static_cast<size_t>(n), out.data());
  return out;
}

uint32_t ByteSource::Crc(uint64_t offset, uint64_t n, uint32_t crc) const {
  std::vector<uint8_t> piece(static_cast<size_t>(std::min<uint64_t>(n, uint64_t{1} << 20)));
  while (n > 0) {
    const size_t take = static_cast<size_t>(std::min<uint64_t>(n, piece.size()));
    Read(offset, take, piece.data());
    crc = static_cast<uint32_t>(crc32(crc, piece.data(), static_cast<uInt>(take)));
    offset += take;
    n -= take;
  }
  return crc;
}

namespace {

class FileSource : public ByteSource {
 public:
  FileSource(std::string path, int fd, uint64_t size)
      : path_(std::move(path)), fd_(fd), size_(size) {}
  ~FileSource() override { ::close(fd_); }
  FileSource(const FileSource&) = delete;
  FileSource& operator=(const FileSource&) = delete;
  uint64_t size() const override { return size_; }
  void Read(uint64_t offset, size_t n, uint8_t* out) const override {
    while (n > 0) {
      const ssize_t got = ::pread(fd_, out, n, static_cast<off_t>(offset));
      if (got < 0 && errno == EINTR) continue;
      if (got <= 0) {
        throw io::InputError(io::Where(
            path_, 0,
            "byte " + std::to_string(offset) + ": " +
                (got == 0 ? "file shorter than when it was opened"
                          : std::string("read failed: ") + std::strerror(errno))));
      }
      out += got;
      offset += static_cast<uint64_t>(got);
      n -= static_cast<size_t>(got);
    }
  }

 private:
  std::string path_;
  int fd_;
  uint64_t size_;
};

class BufferSource : public ByteSource {
 public:
  explicit BufferSource(std::vector<uint8_t> bytes) : bytes_(std::move(bytes)) {}
  uint64_t size() const override { return bytes_.size(); }
  void Read(uint64_t offset, size_t n, uint8_t* out) const override {
    if (n > 0) std::memcpy(out, bytes_.data() + offset, n);
  }

 private:
  std::vector<uint8_t> bytes_;
};

}  // namespace

std::unique_ptr<ByteSource> OpenFileSource(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0)
    throw io::InputError(io::Where(path, 0, std::string("cannot open: ") + std::strerror(errno)));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw io::InputError(io::Where(path, 0, "not a regular file"));
  }
  return std::make_unique<FileSource>(path, fd, static_cast<uint64_t>(st.st_size));
}

std::unique_ptr<ByteSource> MemorySource(std::vector<uint8_t> bytes) {
  return std::make_unique<BufferSource>(std::move(bytes));
}

}  // namespace wallcal::recording
