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
// The solve starts from seed 002's closed form (SolveMountBarawid), as calibrate's does. Prints
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

#include "io/options.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"

namespace {
using wallcal::kDegToRad;
using wallcal::kPi;
struct Synthetic {
  std::vector<wallcal::calib::WallGeometry> walls;
  std::vector<wallcal::calib::WallObservation> observations;
};

// One wall y = 10 m (x from −10 to 10); `segments` stations 7.5–8.5 m from it, headings spread
// evenly over 90° ± 35°, positions along it in a shuffled order; `per_segment` scans each.
Synthetic Make(int segments, int per_segment, double heading_rad, bool dwell_fields,
               uint32_t seed) {
  const double mount_x_m = 2.57, mount_y_m = 0.056, mount_yaw_rad = 2.8 * kDegToRad;
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  Synthetic data;
  wallcal::calib::WallGeometry wall;
  wall.id = "north";
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-10.0, 10.0);
  wall.end_b_local = Eigen::Vector2d(10.0, 10.0);
  wall.sigma_offset_m = 0.011;
  wall.sigma_angle_rad = 0.0008;
  wall.num_points = 62;
  data.walls.push_back(wall);
  const double sigma_rho_m = 0.002, sigma_theta_rad = 0.0005;
  const double white_m = 0.003, bias_m = 0.015;
  data.observations.reserve(static_cast<size_t>(segments) * per_segment);
  int scan = 0;
  for (int k = 0; k < segments; ++k) {
    const double f = segments > 1 ? static_cast<double>(k) / (segments - 1) : 0.5;
    const double yaw_true = 0.5 * kPi + 35.0 * kDegToRad * (2.0 * f - 1.0);
    const double u = segments > 1 ? static_cast<double>((k * 7) % segments) / (segments - 1) : 0.5;
    const Eigen::Vector2d antenna_true(-4.0 + 8.0 * u, 1.5 + 0.5 * (k % 3));
    const Eigen::Vector2d bias(bias_m * unit(rng), bias_m * unit(rng));
    // The dwell's heading samples at 20 Hz over the scans' 75 Hz span: their mean error.
    const int heading_samples = std::max(1, static_cast<int>(per_segment * 20.0 / 75.0));
    double heading_error_sum_rad = 0.0;
    for (int j = 0; j < heading_samples; ++j) heading_error_sum_rad += heading_rad * unit(rng);
    const double dwell_yaw_rad = yaw_true + heading_error_sum_rad / heading_samples;
    for (int j = 0; j < per_segment; ++j, ++scan) {
      const double c = std::cos(yaw_true), s = std::sin(yaw_true);
      const Eigen::Vector2d scanner =
          antenna_true + Eigen::Vector2d(c * mount_x_m - s * mount_y_m, s * mount_x_m + c * mount_y_m);
      wallcal::calib::WallObservation o;
      o.scan_index = scan;
      o.wall_index = 0;
      o.rho_m = 10.0 - scanner.y() + sigma_rho_m * unit(rng);
      o.theta_rad = std::remainder(0.5 * kPi - yaw_true - mount_yaw_rad +
                                       sigma_theta_rad * unit(rng),
                                   2.0 * kPi);
      o.sigma_rho_m = sigma_rho_m;
      o.sigma_theta_rad = sigma_theta_rad;
      o.num_inliers = 60;
      o.range_min_m = o.rho_m;
      o.range_max_m = o.rho_m * 1.5;
      o.pose.stamp_s = 1000.0 + k * 40.0 + j / 75.0;
      o.pose.antenna_local_m =
          antenna_true + bias + Eigen::Vector2d(white_m * unit(rng), white_m * unit(rng));
      o.pose.yaw_rad = yaw_true + heading_rad * unit(rng);
      o.pose.gnss_sigma_m = std::hypot(bias_m, white_m);
      o.pose.stationary = true;
      o.pose.segment = k;
      if (dwell_fields) {
        o.pose.dwell_yaw_rad = dwell_yaw_rad;
        o.pose.dwell_yaw_samples = heading_samples;
        o.pose.dwell_mid_s = 1000.0 + k * 40.0 + 0.5 * (per_segment - 1) / 75.0;
      }
      data.observations.push_back(o);
    }
  }
  return data;
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
  wallcal::io::SolverOptions options;
  options.gnss_white_sigma_m = 0.003;
  options.heading_sigma_rad = std::max(heading_rad, 1e-6);
  std::printf("| observations | segments | solve + covariance (s) | peak RSS (MB) | usable | "
              "x err (mm) | σx (mm) |\n|---|---|---|---|---|---|---|\n");
  for (int n : sizes) {
    const int per_segment = std::max(1, n / segments);
    const Synthetic data =
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
