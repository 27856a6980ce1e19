// SPDX-License-Identifier: Apache-2.0
#pragma once
// Shared by the libFuzzer targets: the readers that take a path get the input through a file
// in a private temporary folder (one per fuzzing process, removed at exit).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace wallcal::fuzz {

class ScratchDir {
 public:
  ScratchDir() {
    char pattern[] = "/tmp/wallcal-fuzz-XXXXXX";
    const char* made = ::mkdtemp(pattern);
    if (made == nullptr) std::abort();  // no scratch space: nothing can be fuzzed
    dir_ = made;
  }
  ~ScratchDir() {
    std::error_code ignored;
    std::filesystem::remove_all(dir_, ignored);
  }
  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;

  // Writes the bytes to <dir>/<name> (replacing it) and returns the path.
  std::string Write(const std::string& name, const uint8_t* data, size_t size) const {
    const std::string path = dir_ + "/" + name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
    out.close();
    if (!out) std::abort();
    return path;
  }
  const std::string& path() const { return dir_; }

 private:
  std::string dir_;
};

// One per process; destroyed at normal exit (libFuzzer exits through exit()).
inline ScratchDir& Scratch() {
  static ScratchDir dir;
  return dir;
}

}  // namespace wallcal::fuzz
