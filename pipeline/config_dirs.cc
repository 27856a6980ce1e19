// SPDX-License-Identifier: Apache-2.0
#include "pipeline/config_dirs.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

namespace wallcal::pipeline {
namespace {

namespace fs = std::filesystem;

std::string ExecutableDir() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  return error ? std::string() : exe.parent_path().string();
}

}  // namespace

std::vector<std::string> ConfigDirs() {
  std::vector<std::string> dirs;
  if (const char* env = std::getenv("WALLCAL_CONFIG_DIR"); env != nullptr && *env != '\0') {
    dirs.push_back(env);
  }
  const std::string exe_dir = ExecutableDir();
  if (!exe_dir.empty()) {
    const fs::path exe(exe_dir);
    dirs.push_back((exe / ".." / "share" / "wallcal").lexically_normal().string());
    dirs.push_back((exe / "share" / "wallcal").string());
  }
  return dirs;
}

std::vector<std::string> PresetDirs() {
  std::vector<std::string> dirs;
  for (const std::string& dir : ConfigDirs()) dirs.push_back((fs::path(dir) / "scanners").string());
  return dirs;
}

}  // namespace wallcal::pipeline
