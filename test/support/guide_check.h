// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's prediction against calibrate on the same data: a simulated session cut after a
// share of its scans (sim::CutTextSession), calibrated as calibrate does (every observation,
// the Ceres covariance; --force, so that a cut whose geometry calibrate would refuse still
// reports its σ) and assessed by the guide. Shared by test/guide/ and bench/guide_bench.

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "guide/guide.h"
#include "pipeline/calibration.h"
#include "sim/session_cut.h"
#include "sim/simulated_session.h"

namespace wallcal::testing_support {

struct CutCheck {
  double fraction = 1.0;
  bool calibrated = false;  // calibrate gave a σ
  bool predicted = false;   // the guide gave a σ
  std::array<double, 3> reported{};   // calibrate's σ: x_m, y_m, yaw_rad
  std::array<double, 3> prediction{};  // the guide's
  int stations = 0;
  double ratio(int axis) const { return prediction[axis] / reported[axis]; }
};

// Simulates `config` with `seed` into dir/full and checks each cut in dir/cut<k>.
inline std::vector<CutCheck> CheckGuideOnCuts(const sim::SimulationConfig& config, uint64_t seed,
                                              const std::filesystem::path& dir,
                                              const std::vector<double>& fractions,
                                              int threads = 1) {
  const std::filesystem::path full = dir / "full";
  sim::WriteSimulatedSession(config, seed, full.string());
  std::vector<CutCheck> checks;
  for (size_t k = 0; k < fractions.size(); ++k) {
    const std::filesystem::path cut = dir / ("cut" + std::to_string(k));
    sim::CutTextSession(full.string(), cut.string(), fractions[k]);
    CutCheck check;
    check.fraction = fractions[k];
    pipeline::CalibrateRequest request;
    request.session_path = cut.string();
    request.force = true;
    request.threads = threads;
    const pipeline::CalibrationResult result = pipeline::RunCalibration(request);
    if (result.solve.estimate.usable) {
      check.calibrated = true;
      for (int a = 0; a < 3; ++a)
        check.reported[a] = std::sqrt(result.solve.estimate.covariance(a, a));
    }
    guide::GuideOptions guide_request;
    guide_request.session_path = cut.string();
    guide_request.threads = threads;
    const guide::GuideReport report = guide::AssessSession(guide_request);
    check.stations = static_cast<int>(report.stations.size());
    if (report.predicted.known) {
      check.predicted = true;
      check.prediction = {report.predicted.sigma_x_m(), report.predicted.sigma_y_m(),
                          report.predicted.sigma_yaw_rad()};
    }
    checks.push_back(check);
    std::filesystem::remove_all(cut);
  }
  std::filesystem::remove_all(full);
  return checks;
}

}  // namespace wallcal::testing_support
