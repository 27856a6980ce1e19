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

// What outputs/multi_offsets.h writes for two scanners, cut to the keys read.
const char* kTwoScanners = R"(scanner_mounts:
  - id: front_left
    parent_frame: gnss_antenna
    child_frame: front_left
    x: 2.458000  # m
    y: 0.753800  # m
    yaw: 0.52365155  # rad
    yaw_deg: 30.0030
    stddev: {x: 0.013400, y: 0.006500, yaw_deg: 0.0460}
    covariance: [1.8e-04, 1.3e-06, -4.3e-07, 1.3e-06, 4.2e-05, -1.7e-06, -4.3e-07, -1.7e-06, 6.4e-07]
  - id: front_right
    parent_frame: gnss_antenna
    child_frame: laser_right
    x: 2.458200
    y: -0.746100
    yaw: -0.52351389
    covariance: [1.8e-04, 1.3e-06, -4.3e-07, 1.3e-06, 4.2e-05, -1.7e-06, -4.3e-07, -1.7e-06, 6.4e-07]
relative_mounts:
  - from: front_left
    to: front_right
    x: -0.749900
    y: -1.299000
    yaw: -1.04716544
    covariance: [1.6e-07, 0, 0, 0, 3.6e-07, 0, 0, 0, 3.0e-10]
source:
  created_utc: "2026-11-26T22:06:48Z"
)";

TEST(OffsetsReaderTest, SeveralScannersReadByIdWithTheirRelativeTransforms) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  const PreviousSeveralOffsets read =
      ReadPreviousSeveralOffsets(Write(scratch.path(), "offsets.yaml", kTwoScanners));
  EXPECT_TRUE(read.several);
  EXPECT_EQ(read.created_utc, "2026-11-26T22:06:48Z");
  ASSERT_EQ(read.scanners.size(), 2u);
  EXPECT_EQ(read.scanners[0].id, "front_left");
  EXPECT_EQ(read.scanners[1].id, "front_right");  // the id, not the child frame
  EXPECT_DOUBLE_EQ(read.scanners[1].offsets.y_m, -0.7461);
  EXPECT_TRUE(read.scanners[1].offsets.sigma_known);
  ASSERT_EQ(read.relative.size(), 1u);
  EXPECT_EQ(read.relative[0].from_id, "front_left");
  EXPECT_EQ(read.relative[0].to_id, "front_right");
  EXPECT_DOUBLE_EQ(read.relative[0].offsets.yaw_rad, -1.04716544);
  EXPECT_DOUBLE_EQ(read.relative[0].offsets.covariance[4], 3.6e-7);
}

TEST(OffsetsReaderTest, OneScannerFileReadsAsOneScannerNamedByItsFrame) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  OffsetsDocument doc = Document();
  doc.child_frame = "laser_front";
  const PreviousSeveralOffsets read =
      ReadPreviousSeveralOffsets(Write(scratch.path(), "offsets.yaml", FormatOffsetsYaml(doc)));
  EXPECT_FALSE(read.several);
  ASSERT_EQ(read.scanners.size(), 1u);
  EXPECT_EQ(read.scanners[0].id, "laser_front");
  EXPECT_NEAR(read.scanners[0].offsets.x_m, doc.x_m, 0.5e-6);
  EXPECT_TRUE(read.relative.empty());
  // The one-scanner reader names what it found instead.
  const std::string several = Write(scratch.path(), "several.yaml", kTwoScanners);
  try {
    ReadPreviousOffsets(several);
    ADD_FAILURE() << "a several-scanner file read as one scanner";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("several.yaml:2: scanner_mounts: holds several"),
              std::string::npos)
        << e.what();
  }
}

TEST(OffsetsReaderTest, SeveralScannerEntriesWithoutIdOrMountAreInputErrors) {
  const testing_support::ScratchDir scratch("wallcal_offsets_reader_");
  const auto message = [&](const std::string& text) -> std::string {
    try {
      ReadPreviousSeveralOffsets(Write(scratch.path(), "bad.yaml", text));
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(message("scanner_mounts:\n  - {x: 1, y: 2, yaw: 0}\n").find(
                "bad.yaml:2: scanner_mounts[1].id: expected a name"),
            std::string::npos);
  EXPECT_NE(message("scanner_mounts:\n  - {id: a, x: 1, yaw: 0}\n").find(
                "scanner_mounts[1] ('a').y: expected a finite number"),
            std::string::npos);
  EXPECT_NE(message("scanner_mounts:\n  - {id: a, x: 1, y: 2, yaw: 0}\nrelative_mounts:\n"
                    "  - {from: a, x: 0, y: 0, yaw: 0}\n")
                .find("bad.yaml:4: relative_mounts[1].to: expected a name"),
            std::string::npos);
  EXPECT_NE(message("quality: {}\n").find("neither scanner_mounts nor scanner_mount"),
            std::string::npos);
}

}  // namespace
}  // namespace wallcal::io
