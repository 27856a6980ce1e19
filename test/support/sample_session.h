// SPDX-License-Identifier: Apache-2.0
#pragma once
// A fixture for the program-level tests that edit a session: each test gets its own copy of the
// bundled sample (samples/lms291-sapporo) in root_/S, removed after the test.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

namespace wallcal::testing_support {

// The bundled sample session, read-only: tests that edit it work on a copy.
inline const std::filesystem::path kSampleSession =
    std::filesystem::path(WALLCAL_SOURCE_DIR) / "samples" / "lms291-sapporo";

class SampleSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    namespace fs = std::filesystem;
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    root_ = fs::temp_directory_path() / ("wallcal_" + std::string(info->test_suite_name()) + "_" +
                                         std::to_string(::getpid()) + "_" + info->name());
    fs::remove_all(root_);
    session_ = root_ / "S";
    fs::create_directories(session_);
    for (const char* name : {"session.yaml", "scans.clf", "gnss.nmea", "heading.nmea", "survey.csv"}) {
      fs::copy_file(kSampleSession / name, session_ / name);
    }
  }
  void TearDown() override { std::filesystem::remove_all(root_); }

  std::filesystem::path root_;     // the test's own folder
  std::filesystem::path session_;  // root_/S: the copy of the sample session
};

}  // namespace wallcal::testing_support
