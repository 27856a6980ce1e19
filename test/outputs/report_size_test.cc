// SPDX-License-Identifier: Apache-2.0
// The report stays small without losing a panel: SvgPlot::DotCloud draws each occupied pixel
// (or cell) once, and the sample's report is under its size bound with every section and
// every residual panel present.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "outputs/svg_plot.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"

namespace wallcal::outputs {
namespace {

namespace fs = std::filesystem;

size_t Count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::vector<Eigen::Vector2d> Cloud(size_t n) {
  std::mt19937 random(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<Eigen::Vector2d> points;
  for (size_t i = 0; i < n; ++i) points.emplace_back(noise(random), noise(random));
  return points;
}

TEST(DotCloudTest, EveryOccupiedPixelIsDrawnOnce) {
  const std::vector<Eigen::Vector2d> points = Cloud(20000);
  int clip = 0;
  SvgPlot plot(590, 300, &clip);
  plot.SetRange(-4, 4, -4, 4, false);
  const size_t drawn = plot.DotCloud(points, 1.8, "#000", 1.0);
  // The pixels the points fall on, as the plot maps them (whole pixels).
  std::set<std::pair<long long, long long>> pixels;
  for (const Eigen::Vector2d& p : points) {
    pixels.emplace(std::llround(plot.Px(p.x())), std::llround(plot.Py(p.y())));
  }
  EXPECT_EQ(drawn, pixels.size());
  EXPECT_LT(drawn, points.size());  // the dense middle shares pixels
  EXPECT_EQ(Count(plot.Svg("t"), "h0"), drawn);
}

TEST(DotCloudTest, CellsBoundTheCountByTheArea) {
  int clip = 0;
  SvgPlot dense(590, 300, &clip), sparse(590, 300, &clip);
  dense.SetRange(-4, 4, -4, 4, false);
  sparse.SetRange(-4, 4, -4, 4, false);
  const size_t many = dense.DotCloud(Cloud(200000), 1.8, "#000", 3.6);
  const size_t few = sparse.DotCloud(Cloud(20000), 1.8, "#000", 3.6);
  const double cells = (590.0 / 3.6 + 1) * (300.0 / 3.6 + 1);
  EXPECT_LE(static_cast<double>(many), cells);
  // Ten times the points, not ten times the dots: the cloud's outline is what grows.
  EXPECT_LT(static_cast<double>(many), 2.0 * static_cast<double>(few));
}

TEST(ReportSizeTest, SampleReportIsSmallAndWhole) {
  const testing_support::ScratchDir scratch("wallcal_report_size_");
  const fs::path report_dir = scratch.path() / "report";
  const testing_support::ProgramRun run = testing_support::RunWallcal(
      {"calibrate", std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo", "--report",
       report_dir.string(), "--output", (scratch.path() / "offsets.yaml").string(), "--quiet"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const fs::path report = report_dir / "report.html";
  ASSERT_TRUE(fs::exists(report));
  EXPECT_LE(fs::file_size(report), 400u * 1000u);
  std::ifstream in(report, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  const std::string html = text.str();
  for (const char* section : {"decision", "mount", "site-map", "scans", "hough", "residuals",
                              "coverage", "counts", "solver"}) {
    EXPECT_NE(html.find(std::string("<section id=\"") + section + "\">"), std::string::npos)
        << section;
  }
  for (const char* panel : {"Residual vs heading", "Residual vs range",
                            "Residual vs incidence angle", "Residual vs beam bearing"}) {
    const size_t at = html.find(std::string("<title>") + panel + "</title>");
    ASSERT_NE(at, std::string::npos) << panel;
    const std::string svg = html.substr(at, html.find("</svg>", at) - at);
    EXPECT_GT(Count(svg, "h0"), 100u) << panel << ": the residuals are drawn";
  }
}

}  // namespace
}  // namespace wallcal::outputs
