// SPDX-License-Identifier: Apache-2.0
#pragma once
// Files for tests that read what they write: paths and folders inside one scratch folder per
// test program (removed when the process ends), writing and reading a file's bytes as given, and
// editing a copied input in place. ctest runs each test case in a process of its own, so a
// folder a case empties is its own.

#include <errno.h>  // program_invocation_short_name
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "test/support/scratch_dir.h"

namespace wallcal::testing_support {

// This process's scratch folder for `prefix`, made on first use and removed at exit.
inline const std::filesystem::path& ScratchRoot(const std::string& prefix) {
  static std::map<std::string, std::unique_ptr<ScratchDir>> scratch;
  std::unique_ptr<ScratchDir>& dir = scratch[prefix];
  if (!dir) dir = std::make_unique<ScratchDir>(prefix);
  return dir->path();
}

// The prefix of this test program's own scratch folder: its name.
inline std::string ProgramScratchPrefix() {
  return std::string(program_invocation_short_name) + "_";
}
inline const std::filesystem::path& ScratchRoot() { return ScratchRoot(ProgramScratchPrefix()); }

// <scratch folder for `prefix`>/<name>, made if missing.
inline std::string ScratchFolder(const std::string& prefix, const std::string& name) {
  const std::filesystem::path path = ScratchRoot(prefix) / name;
  std::filesystem::create_directories(path);
  return path.string();
}

// ScratchFolder(prefix, name) emptied first.
inline std::string FreshScratchFolder(const std::string& prefix, const std::string& name) {
  const std::string dir = ScratchFolder(prefix, name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// The same in this test program's scratch folder: a folder `name` (made if missing), an empty
// one as a string and as a path.
inline std::string ScratchFolder(const std::string& name) {
  return ScratchFolder(ProgramScratchPrefix(), name);
}
inline std::string FreshScratchFolder(const std::string& name) {
  return FreshScratchFolder(ProgramScratchPrefix(), name);
}
inline std::filesystem::path FreshScratchDir(const std::string& name) {
  return FreshScratchFolder(name);
}

// A file `name` in this test program's scratch folder (not created).
inline std::string ScratchPath(const std::string& name) { return (ScratchRoot() / name).string(); }

// Writes `content` to `path` byte for byte, replacing what was there; returns the path. A file
// that cannot be written fails the test.
inline std::string WriteFile(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  EXPECT_TRUE(out.good()) << "cannot write " << path;
  return path;
}

// The first `bytes` of `content` as the whole file at `path`: a log or recording still being
// written, cut anywhere.
inline std::string WriteFirstBytes(const std::string& path, const std::string& content,
                                   size_t bytes) {
  return WriteFile(path, content.substr(0, bytes));
}

// WriteFile(ScratchPath(name), content).
inline std::string WriteScratchFile(const std::string& name, const std::string& content) {
  return WriteFile(ScratchPath(name), content);
}

// A file's bytes ("" when it cannot be read).
inline std::string ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Replaces the first `from` in the file with `to`; fails the test when `from` is not there.
inline void ReplaceInFile(const std::string& path, const std::string& from, const std::string& to) {
  std::string text = ReadFile(path);
  const size_t at = text.find(from);
  ASSERT_NE(at, std::string::npos) << path << " has no " << from;
  text.replace(at, from.size(), to);
  WriteFile(path, text);
}

}  // namespace wallcal::testing_support
