// SPDX-License-Identifier: Apache-2.0
#include "pipeline/config_dirs.h"

#include <cstdlib>
#include <filesystem>
#include <system_error>

#include "io/config/session_reader.h"

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

std::vector<std::string> SessionPresetDirs(const std::string& session_dir) {
  std::vector<std::string> dirs = PresetDirs();
  if (!session_dir.empty()) dirs.insert(dirs.begin(), (fs::path(session_dir) / "scanners").string());
  return dirs;
}

io::ScannerPreset LoadSessionPreset(const std::string& model, const std::string& session_dir) {
  return io::LoadScannerPreset(model, SessionPresetDirs(session_dir));
}

std::string SessionPresetPath(const std::string& model, const std::string& session_dir) {
  if (model.empty() || model.find_first_of("/\\") != std::string::npos || model == "." ||
      model == "..") {
    return "";
  }
  std::error_code error;
  for (const std::string& dir : SessionPresetDirs(session_dir)) {
    const fs::path candidate = fs::path(dir) / (model + ".yaml");
    if (fs::is_regular_file(candidate, error)) return candidate.string();
  }
  return "";
}

}  // namespace wallcal::pipeline
