// SPDX-License-Identifier: Apache-2.0
#pragma once
// Files for tests that read what they write: a named folder inside one scratch folder per test
// program (removed when the process ends), and writing a file's bytes as given.

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include "test/support/scratch_dir.h"

namespace wallcal::testing_support {

// <scratch folder for `prefix`>/<name>, made if missing. One scratch folder per prefix and
// process, removed at exit.
inline std::string ScratchFolder(const std::string& prefix, const std::string& name) {
  static std::map<std::string, std::unique_ptr<ScratchDir>> scratch;
  std::unique_ptr<ScratchDir>& dir = scratch[prefix];
  if (!dir) dir = std::make_unique<ScratchDir>(prefix);
  const std::filesystem::path path = dir->path() / name;
  std::filesystem::create_directories(path);
  return path.string();
}

// Writes `content` to `path` byte for byte; returns the path.
inline std::string WriteFile(const std::string& path, const std::string& content) {
  std::ofstream(path, std::ios::binary) << content;
  return path;
}

}  // namespace wallcal::testing_support
