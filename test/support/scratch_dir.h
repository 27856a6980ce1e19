// SPDX-License-Identifier: Apache-2.0
#pragma once
// A scratch folder for tests: made empty under ::testing::TempDir() and removed with everything
// in it when the object goes out of scope, so a test run leaves nothing behind in /tmp. A test
// keeps one as a local; a test file whose helpers hand out paths keeps one per process (a
// function-local static, removed at exit: ctest runs each test in a process of its own).

#include <gtest/gtest.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <string>
#include <system_error>
#include <utility>

namespace wallcal::testing_support {

class ScratchDir {
 public:
  // Makes <TempDir>/<prefix><pid>_<n>, n counting the folders this process has made, so two
  // in one process never share one. A folder of that name left by an earlier process with the
  // same pid is emptied first.
  explicit ScratchDir(const std::string& prefix) {
    static std::atomic<int> made{0};
    path_ = std::filesystem::path(::testing::TempDir()) /
            (prefix + std::to_string(::getpid()) + "_" + std::to_string(made++));
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~ScratchDir() { Remove(); }

  ScratchDir(const ScratchDir&) = delete;
  ScratchDir& operator=(const ScratchDir&) = delete;
  ScratchDir(ScratchDir&& other) noexcept : path_(std::move(other.path_)) { other.path_.clear(); }
  ScratchDir& operator=(ScratchDir&& other) noexcept {
    if (this != &other) {
      Remove();
      path_ = std::move(other.path_);
      other.path_.clear();
    }
    return *this;
  }

  const std::filesystem::path& path() const { return path_; }

 private:
  // Never throws: a folder that cannot be removed is left, not an abort in a destructor.
  void Remove() noexcept {
    if (path_.empty()) return;
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }

  std::filesystem::path path_;
};

}  // namespace wallcal::testing_support
