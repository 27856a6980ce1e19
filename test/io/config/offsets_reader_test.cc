// SPDX-License-Identifier: Apache-2.0
// Reading an earlier offsets.yaml for calibrate --compare (io/config/offsets_reader.h): what
// FormatOffsetsYaml writes reads back to the same mount, and a file that cannot be compared
// with is an InputError naming it.

#include "io/config/offsets_reader.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "io/config/config_writer.h"
#include "io/types.h"
#include "test/support/scratch_dir.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;

std::string Write(const fs::path& dir, const std::string& name, const std::string& text) {
  const fs::path path = dir / name;
  std::ofstream(path) << text;
  return path.string();
}

OffsetsDocument Document() {
  OffsetsDocument doc;
  doc.x_m = 2.542159;
  doc.y_m = 0.063017;
  doc.yaw_rad = 0.04869531;
  const double cov[9] = {2.36e-4, 4.0e-8, -2.9e-8, 4.0e-8, 7.2e-5, -1.7e-6, -2.9e-8, -1.7e-6, 6.5e-7};
  std::copy(cov, cov + 9, doc.covariance);
  doc.method = "ceres";
  doc.created_utc = "2026-11-26T16:00:00Z";
  doc.session = "samples/lms291-sapporo/session.yaml";
  return doc;
}

TEST(OffsetsReaderTest, WhatTheWriterWritesReadsBack) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  const OffsetsDocument doc = Document();
  const PreviousOffsets read =
      ReadPreviousOffsets(Write(scratch.path(), "offsets.yaml", FormatOffsetsYaml(doc)));
  // The writer keeps 6 decimals of a metre and 8 of a radian.
  EXPECT_NEAR(read.x_m, doc.x_m, 0.5e-6);
  EXPECT_NEAR(read.y_m, doc.y_m, 0.5e-6);
  EXPECT_NEAR(read.yaw_rad, doc.yaw_rad, 0.5e-8);
  ASSERT_TRUE(read.sigma_known);
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(read.covariance[i], doc.covariance[i], 1e-6 * std::abs(doc.covariance[i])) << i;
  }
  EXPECT_EQ(read.created_utc, doc.created_utc);
}

TEST(OffsetsReaderTest, AFileWithoutSigmaReadsAsSigmaUnknown) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  OffsetsDocument doc = Document();
  doc.sigma_known = false;
  doc.method = "barawid";
  const PreviousOffsets read =
      ReadPreviousOffsets(Write(scratch.path(), "offsets.yaml", FormatOffsetsYaml(doc)));
  EXPECT_FALSE(read.sigma_known);
  EXPECT_NEAR(read.x_m, doc.x_m, 0.5e-6);
}

TEST(OffsetsReaderTest, FilesThatCannotBeComparedWithAreInputErrors) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  const auto message = [&](const std::string& name, const std::string& text) -> std::string {
    const std::string path = Write(scratch.path(), name, text);
    try {
      ReadPreviousOffsets(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_THROW(ReadPreviousOffsets((scratch.path() / "absent.yaml").string()), InputError);
  const std::string not_yaml = message("not_yaml.yaml", "scanner_mount: [1, 2\n");
  EXPECT_NE(not_yaml.find("not_yaml.yaml"), std::string::npos) << not_yaml;
  const std::string no_mount = message("no_mount.yaml", "quality: {scans_used: 3}\n");
  EXPECT_NE(no_mount.find("no_mount.yaml"), std::string::npos) << no_mount;
  const std::string nan_x =
      message("nan_x.yaml", "scanner_mount:\n  x: .nan\n  y: 0.1\n  yaw: 0.01\n");
  EXPECT_NE(nan_x.find("nan_x.yaml"), std::string::npos) << nan_x;
}

}  // namespace
}  // namespace wallcal::io
