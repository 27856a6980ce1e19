// SPDX-License-Identifier: Apache-2.0
#include "io/config/config_writer.h"

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/angles.h"
#include "test/support/scratch_dir.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;

TEST(ConfigWriterTest, OffsetsYamlParsesBackToTheSameNumbers) {
  OffsetsDocument doc;
  doc.x_m = 2.5703;
  doc.y_m = 0.0561;
  doc.yaw_rad = 0.048869;
  const double cov[9] = {1.7e-5, 2e-7, -3e-8, 2e-7, 1.0e-5, 4e-9, -3e-8, 4e-9, 8.2e-7};
  std::copy(cov, cov + 9, doc.covariance);
  doc.method = "ceres";
  doc.scans_total = 45000;
  doc.scans_used = 43950;
  doc.heading_min_deg = 31.0;
  doc.heading_max_deg = 148.5;
  doc.residual_rms_m = 0.0061;
  doc.quality_extra = {{"stations", "12"}, {"walls", "{north_wall: 4100, east: 300}"}};
  doc.warnings = {"heading spread: only 45 deg", "quote \" and # hash: kept"};
  doc.session = "/data/sessions/sapporo north";
  doc.tool_version = "0.1.0";

  const YAML::Node root = YAML::Load(FormatOffsetsYaml(doc));
  const YAML::Node mount = root["scanner_mount"];
  EXPECT_EQ(mount["parent_frame"].as<std::string>(), "gnss_antenna");
  EXPECT_EQ(mount["child_frame"].as<std::string>(), "laser");
  EXPECT_NEAR(mount["x"].as<double>(), 2.5703, 1e-6);
  EXPECT_NEAR(mount["y"].as<double>(), 0.0561, 1e-6);
  EXPECT_NEAR(mount["yaw"].as<double>(), 0.048869, 1e-8);
  EXPECT_NEAR(mount["yaw_deg"].as<double>(), 0.048869 * 180 / kPi, 1e-4);
  EXPECT_NEAR(mount["stddev"]["x"].as<double>(), std::sqrt(1.7e-5), 1e-6);
  EXPECT_NEAR(mount["stddev"]["y"].as<double>(), std::sqrt(1.0e-5), 1e-6);
  EXPECT_NEAR(mount["stddev"]["yaw_deg"].as<double>(), std::sqrt(8.2e-7) * 180 / kPi, 1e-4);
  ASSERT_EQ(mount["covariance"].size(), 9u);
  for (int i = 0; i < 9; ++i) {
    EXPECT_NEAR(mount["covariance"][i].as<double>(), cov[i], std::abs(cov[i]) * 1e-6) << i;
  }
  const YAML::Node seed = root["barawid_2007_notation"];
  EXPECT_FALSE(root["seed_002_notation"].IsDefined());
  EXPECT_NEAR(seed["a"].as<double>(), -0.0561, 1e-6);
  EXPECT_NEAR(seed["b"].as<double>(), 2.5703, 1e-6);
  EXPECT_NEAR(seed["delta_deg"].as<double>(), 2.8000, 1e-4);
  const YAML::Node quality = root["quality"];
  EXPECT_EQ(quality["scans_total"].as<int64_t>(), 45000);
  EXPECT_EQ(quality["scans_used"].as<int64_t>(), 43950);
  EXPECT_DOUBLE_EQ(quality["headings_deg"]["min"].as<double>(), 31.0);
  EXPECT_DOUBLE_EQ(quality["headings_deg"]["max"].as<double>(), 148.5);
  EXPECT_NEAR(quality["residual_rms_m"].as<double>(), 0.0061, 1e-6);
  EXPECT_EQ(quality["stations"].as<int>(), 12);
  EXPECT_EQ(quality["walls"]["east"].as<int>(), 300);
  ASSERT_EQ(root["warnings"].size(), 2u);
  EXPECT_EQ(root["warnings"][1].as<std::string>(), "quote \" and # hash: kept");
  EXPECT_EQ(root["method"].as<std::string>(), "ceres");
  EXPECT_EQ(root["source"]["session"].as<std::string>(), "/data/sessions/sapporo north");
  EXPECT_EQ(root["source"]["tool_version"].as<std::string>(), "0.1.0");

  doc.warnings.clear();
  EXPECT_EQ(YAML::Load(FormatOffsetsYaml(doc))["warnings"].size(), 0u);
}

}  // namespace
}  // namespace wallcal::io
