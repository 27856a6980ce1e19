// SPDX-License-Identifier: Apache-2.0
// inspect's preview of a long session: solved on every k-th observation, each weighted by k
// (pipeline/calibration.h), it must agree with the calibration it previews.
//
// Tolerances. The session (8 stations of 20 s at 75 Hz, about 12 000 observations) has its
// mount σ set by the survey tie and the correlated GNSS error (error budget: scanner noise
// under 1 % of each variance), and thinning keeps every station and GNSS-error stretch, so the
// preview's σ stays near the whole set's: within 0.8–1.25 (measured: 0.88–1.00; the weighted
// observation counts as k independent ones where k neighbouring scans share some noise, so
// the preview's σ is the smaller one). Its estimate differs from the whole set's by the noise
// of the observations left out, a small part of σ: within one σ of the calibration (measured
// 0.37 σ in x, the largest).

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "analysis/repeatability.h"
#include "io/config/session_reader.h"
#include "pipeline/calibration.h"
#include "pipeline/config_dirs.h"
#include "preflight/internal/inspect_internal.h"
#include "recording/recording_streams.h"
#include "sim/simulated_session.h"
#include "test/support/scratch_dir.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

TEST(PreviewTest, ThinnedPreviewAgreesWithTheCalibration) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_hour.yaml");
  config.num_stations = 8;
  config.dwell_s = 20.0;
  const testing_support::ScratchDir scratch("wallcal_preview_thinned_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(config, 21, dir.string());

  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  const pipeline::CalibrationResult full = pipeline::RunCalibration(request);
  request.preview = true;
  const pipeline::CalibrationResult preview = pipeline::RunCalibration(request);
  ASSERT_TRUE(full.solve.estimate.usable) << full.solve.estimate.message;
  ASSERT_TRUE(preview.solve.estimate.usable) << preview.solve.estimate.message;

  // Thinned for the solve, every detection kept for inspect's counts.
  ASSERT_GT(full.solve.observations.size(), 2u * analysis::kMaxRefitObservations);
  EXPECT_LE(preview.solve.preview_observations_solved, analysis::kMaxRefitObservations);
  EXPECT_GT(preview.solve.preview_observations_solved, analysis::kMaxRefitObservations / 2);
  EXPECT_GE(preview.solve.observations.size(), full.solve.observations.size());
  EXPECT_TRUE(preview.solve.estimate.residual_rho_m.empty());  // they were the thinned set's

  const solvers::MountEstimate& f = full.solve.estimate;
  const solvers::MountEstimate& p = preview.solve.estimate;
  const double full_values[3] = {f.mount.x_m, f.mount.y_m, f.mount.yaw_rad};
  const double preview_values[3] = {p.mount.x_m, p.mount.y_m, p.mount.yaw_rad};
  for (int k = 0; k < 3; ++k) {
    const double sigma_full = std::sqrt(f.covariance(k, k));
    const double sigma_preview = std::sqrt(p.covariance(k, k));
    std::printf("[ preview  ] axis %d: full %.6g ± %.3g, preview %.6g ± %.3g\n", k, full_values[k],
                sigma_full, preview_values[k], sigma_preview);
    EXPECT_GT(sigma_preview / sigma_full, 0.8) << "axis " << k;
    EXPECT_LT(sigma_preview / sigma_full, 1.25) << "axis " << k;
    EXPECT_LT(std::abs(preview_values[k] - full_values[k]), sigma_full) << "axis " << k;
  }
}

// inspect takes its scan-log summary from the preview's second pass instead of reading the log
// again (preflight/session_inspection.cc): the tally must be what reading the log gives, for
// the scans the pass detects in and for those it passes over (here: scans before the GNSS and
// heading logs start, and a malformed line).
TEST(PreviewTest, SecondPassTallyIsTheScanLogSummary) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
  const testing_support::ScratchDir scratch("wallcal_preview_tally_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(config, 7, dir.string());
  // Five copies of the first scan, 100 s and more before it, and a malformed line after them.
  const fs::path log = dir / "scans.clf";
  std::stringstream text;
  text << std::ifstream(log).rdbuf();
  std::vector<std::string> lines;
  for (std::string line; std::getline(text, line);) lines.push_back(line);
  size_t first_scan = 0;
  while (lines[first_scan].rfind("RAWLASER1", 0) != 0) ++first_scan;
  const std::string& scan = lines[first_scan];
  const double stamp_s = std::stod(scan.substr(scan.find_last_of(' ') + 1));
  std::vector<std::string> early;
  for (int k = 5; k >= 1; --k) {
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.3f", stamp_s - 100.0 * k);
    early.push_back(scan.substr(0, scan.find_last_of(' ') + 1) + stamp);
  }
  early.push_back("RAWLASER1 0 -1.57 3.14 0.0174 80 0.01 0 181 1.0 2.0");
  lines.insert(lines.begin() + static_cast<long>(first_scan), early.begin(), early.end());
  {
    std::ofstream out(log);
    for (const std::string& line : lines) out << line << "\n";
  }

  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.preview = true;
  const pipeline::CalibrationResult preview = pipeline::RunCalibration(request);
  ASSERT_TRUE(preview.solve.estimate.usable) << preview.solve.estimate.message;
  ASSERT_TRUE(preview.detection.scan_log.has_value());
  const calib::ScanLogTally& tally = *preview.detection.scan_log;

  const io::SessionSpec spec = io::ReadSession(dir.string());
  const io::ScannerPreset preset = io::LoadScannerPreset(spec.scanner_model, pipeline::PresetDirs());
  const recording::ScanOpener opener = recording::MakeScanOpener(spec, &preset);
  const calib::DetectorOptions& detector = preview.loaded.options.detector;
  const preflight::internal::ScanLogSummary read = preflight::internal::ReadScanLog(
      spec.scanner_log, spec.scanner_time_offset_s, &preset, detector.min_range_m,
      detector.mixed_pixel_jump_m, &opener);

  ASSERT_GT(preview.ScansSkipped().count(calib::ScanSkip::kNoPoseBeforeLogs), 0u);
  EXPECT_EQ(preview.ScansSkipped().at(calib::ScanSkip::kNoPoseBeforeLogs), 5);
  EXPECT_EQ(tally.stamps_s, read.stamps_s);
  EXPECT_EQ(tally.beams, read.beams);
  EXPECT_EQ(tally.readings.valid, read.readings.valid);
  EXPECT_EQ(tally.readings.no_return, read.readings.no_return);
  EXPECT_EQ(tally.readings.error_code, read.readings.error_code);
  EXPECT_EQ(tally.readings.too_close, read.readings.too_close);
  EXPECT_EQ(tally.readings.non_finite, read.readings.non_finite);
  EXPECT_EQ(tally.first_start_rad, read.first_start_rad);
  EXPECT_EQ(tally.first_step_rad, read.first_step_rad);
  EXPECT_EQ(tally.first_max_range_m, read.first_max_range_m);
  const preflight::internal::ScanLogSummary shared = preflight::internal::SummaryFromTally(
      spec.scanner_log, tally, preview.detection.scan_lines_skipped);
  EXPECT_EQ(shared.stats.records, read.stats.records);
  EXPECT_EQ(shared.stats.start_s, read.stats.start_s);
  EXPECT_EQ(shared.stats.end_s, read.stats.end_s);
  EXPECT_EQ(shared.stats.not_increasing, read.stats.not_increasing);
  EXPECT_EQ(shared.skipped.Total(), read.skipped.Total());
  EXPECT_EQ(shared.skipped.Problems(), 1);  // the malformed line
  EXPECT_EQ(read.skipped.Problems(), 1);
}

}  // namespace
}  // namespace wallcal
