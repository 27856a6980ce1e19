// SPDX-License-Identifier: Apache-2.0
// solver_scaling: how long the joint Ceres adjustment (solve + mount covariance) takes as the
// number of wall observations grows, up to an hour of LMS 291 scans at 75 Hz (270 000
// observations) in 100 GNSS segments. Synthetic observations (no scans, no files): stations
// along a wall, headings spread ±35°, per-station GNSS bias, white pose noise, line-fit noise.
// Headings as the pipeline builds them: 20 Hz heading samples with white noise; each scan's
// pose.yaw_rad is the true yaw plus one sample's noise, and the dwell fields (dwell_yaw_rad,
// dwell_yaw_samples, dwell_mid_s) hold the mean of the dwell's samples, as PoseInterpolator
// fills them. --per-scan-only leaves the dwell fields empty (the solver then averages the
// scans' own yaws).
//
//   solver_scaling [--observations N] [--segments S] [--heading-sigma-deg D] [--per-scan-only]
//   (default: 27 000, 90 000 and 270 000 observations in 100 segments, heading noise 0.05°)
//
// The solve starts from Barawid 2007's closed form (SolveMountBarawid), as calibrate's does. Prints
// observations, segments, seconds (Barawid start + Ceres solve + covariance), peak RSS, the x
// error against the truth and σx, and Ceres' brief report on stderr. Not a test.

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <vector>

#include "solvers/solver_options.h"
#include "sim/synthetic_observations.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"

namespace {
using wallcal::kDegToRad;
using wallcal::kPi;
// The shared fixture (sim/synthetic_observations.h): one wall, `segments` stations 40 s apart,
// `per_segment` scans each at 75 Hz, heading samples at 20 Hz averaged over each dwell.
wallcal::sim::SimData Make(int segments, int per_segment, double heading_rad, bool dwell_fields,
                           uint32_t seed) {
  wallcal::sim::SimSettings s;
  s.stations = segments;
  s.scans_per_station = per_segment;
  s.fit_sigma_rho_m = 0.002;
  s.fit_sigma_theta_rad = 0.0005;
  s.gnss_white_sigma_m = 0.003;
  s.gnss_bias_sigma_m = 0.015;
  s.heading_sigma_rad = heading_rad;
  s.wall_sigma_offset_m = 0.011;
  s.wall_sigma_angle_rad = 0.0008;
  s.station_spacing_s = 40.0;
  s.scan_period_s = 1.0 / 75.0;
  s.dwell_heading_samples = dwell_fields ? std::max(1, static_cast<int>(per_segment * 20.0 / 75.0)) : 0;
  std::mt19937 rng(seed);
  return wallcal::sim::SimulateObservations(s, rng);
}

double PeakRssMb() {
  struct rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;  // Linux: kB
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<int> sizes = {27000, 90000, 270000};
  int segments = 100;
  double heading_rad = 0.05 * kDegToRad;
  bool dwell_fields = true;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--observations" && i + 1 < argc) {
      sizes = {std::atoi(argv[++i])};
    } else if (a == "--segments" && i + 1 < argc) {
      segments = std::atoi(argv[++i]);
    } else if (a == "--heading-sigma-deg" && i + 1 < argc) {
      heading_rad = std::atof(argv[++i]) * kDegToRad;
    } else if (a == "--per-scan-only") {
      dwell_fields = false;
    } else {
      std::fprintf(stderr,
                   "usage: solver_scaling [--observations N] [--segments S] "
                   "[--heading-sigma-deg D] [--per-scan-only]\n");
      return 2;
    }
  }
  if (segments < 3) {
    std::fprintf(stderr, "solver_scaling: --segments must be >= 3\n");
    return 2;
  }
  wallcal::solvers::SolverOptions options;
  options.gnss_white_sigma_m = 0.003;
  options.heading_sigma_rad = std::max(heading_rad, 1e-6);
  std::printf("| observations | segments | solve + covariance (s) | peak RSS (MB) | usable | "
              "x err (mm) | σx (mm) |\n|---|---|---|---|---|---|---|\n");
  for (int n : sizes) {
    const int per_segment = std::max(1, n / segments);
    const wallcal::sim::SimData data =
        Make(segments, per_segment, heading_rad, dwell_fields,
             270000u + static_cast<uint32_t>(n));
    const auto start = std::chrono::steady_clock::now();
    const wallcal::solvers::MountEstimate first =
        wallcal::solvers::SolveMountBarawid(data.observations, data.walls, options);
    const wallcal::solvers::MountEstimate estimate = wallcal::solvers::SolveMountCeres(
        data.observations, data.walls, options, first.mount);
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf("| %zu | %d | %.2f | %.0f | %s | %.2f | %.2f |\n", data.observations.size(),
                segments, seconds, PeakRssMb(), estimate.usable ? "yes" : "no",
                1000.0 * (estimate.mount.x_m - 2.57),
                1000.0 * std::sqrt(std::max(0.0, estimate.covariance(0, 0))));
    if (!estimate.usable) std::printf("  (%s)\n", estimate.message.c_str());
    std::fprintf(stderr, "%s\n", estimate.solver_report.c_str());
    std::fflush(stdout);
  }
  return 0;
}
