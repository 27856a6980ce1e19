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

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "analysis/repeatability.h"
#include "io/session_reader.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

TEST(PreviewTest, ThinnedPreviewAgreesWithTheCalibration) {
  io::SimulationConfig config = io::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_hour.yaml");
  config.num_stations = 8;
  config.dwell_s = 20.0;
  const fs::path dir = fs::path(::testing::TempDir()) / "wallcal_preview_thinned";
  fs::remove_all(dir);
  fs::create_directories(dir);
  sim::WriteSimulatedSession(config, 21, dir.string());

  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  const pipeline::CalibrationResult full = pipeline::RunCalibration(request);
  request.preview = true;
  const pipeline::CalibrationResult preview = pipeline::RunCalibration(request);
  ASSERT_TRUE(full.estimate.usable) << full.estimate.message;
  ASSERT_TRUE(preview.estimate.usable) << preview.estimate.message;

  // Thinned for the solve, every detection kept for inspect's counts.
  ASSERT_GT(full.observations.size(), 2u * analysis::kMaxRefitObservations);
  EXPECT_LE(preview.preview_observations_solved, analysis::kMaxRefitObservations);
  EXPECT_GT(preview.preview_observations_solved, analysis::kMaxRefitObservations / 2);
  EXPECT_GE(preview.observations.size(), full.observations.size());
  EXPECT_TRUE(preview.estimate.residual_rho_m.empty());  // they were the thinned set's

  const solvers::MountEstimate& f = full.estimate;
  const solvers::MountEstimate& p = preview.estimate;
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

}  // namespace
}  // namespace wallcal
