// SPDX-License-Identifier: Apache-2.0
#include "io/output_file.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/angles.h"
#include "io/types.h"
#include "test/support/scratch_files.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchFolder;
using testing_support::ReadFile;

size_t FilesIn(const std::string& dir) {
  size_t n = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    (void)entry;
    ++n;
  }
  return n;
}

TEST(OutputFileTest, WriteFileAtomicallyCreatesAndReplaces) {
  const std::string dir = FreshScratchFolder("atomic");
  const std::string path = dir + "/offsets.yaml";
  WriteFileAtomically(path, "first\n");
  EXPECT_EQ(ReadFile(path), "first\n");
  WriteFileAtomically(path, "second, longer content\n");
  EXPECT_EQ(ReadFile(path), "second, longer content\n");
  EXPECT_EQ(FilesIn(dir), 1u);  // no temporary file left behind
  const auto permissions = fs::status(path).permissions();
  EXPECT_NE(permissions & fs::perms::others_read, fs::perms::none);
}

TEST(OutputFileTest, WriteFileAtomicallyFailsCleanlyOnAMissingFolder) {
  const std::string dir = FreshScratchFolder("missing_parent") + "/no_such_folder";
  const std::string path = dir + "/offsets.yaml";
  try {
    WriteFileAtomically(path, "content\n");
    FAIL() << "no exception";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(path + ": ", 0), 0u) << e.what();
  }
  EXPECT_FALSE(fs::exists(dir));
}

TEST(OutputFileTest, WriteFileAtomicallyKeepsTheOldFileWhenTheTargetIsAFolder) {
  const std::string dir = FreshScratchFolder("target_is_folder");
  const std::string path = dir + "/offsets.yaml";
  fs::create_directories(path + "/inside");  // rename over a non-empty folder fails
  EXPECT_THROW(WriteFileAtomically(path, "content\n"), InputError);
  EXPECT_TRUE(fs::is_directory(path));
  EXPECT_EQ(FilesIn(dir), 1u);  // the temporary file was removed
}

}  // namespace
}  // namespace wallcal::io
