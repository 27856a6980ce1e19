// SPDX-License-Identifier: Apache-2.0
#include "solvers/observability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <set>
#include <string>

#include <Eigen/Eigenvalues>

#include "calib/geodesy.h"
#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "common/circular.h"
#include "common/format.h"

namespace wallcal::solvers {

ObservabilityReport CheckObservability(const std::vector<calib::WallObservation>& observations,
                                       const std::vector<calib::WallGeometry>& walls,
                                       const solvers::SolverOptions& options) {
  ObservabilityReport report;
  report.num_observations = static_cast<int>(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const int w = observations[i].wall_index;
    if (w < 0 || w >= static_cast<int>(walls.size())) {
      report.message = "observation " + std::to_string(i) + " (scan " +
                       std::to_string(observations[i].scan_index) + ") refers to wall index " +
                       std::to_string(w) + ", but there are " + std::to_string(walls.size()) +
                       " walls";
      report.solvable = false;
      return report;
    }
  }
  report.solvable = !observations.empty();
  if (observations.empty() || report.num_observations < options.min_observations) {
    report.message = "only " + std::to_string(observations.size()) +
                     " wall observations; need at least " +
                     std::to_string(std::max(options.min_observations, 1));
    return report;
  }

  std::set<int> stations;
  for (const auto& observation : observations) {
    if (observation.pose.segment >= 0) stations.insert(observation.pose.segment);
  }
  report.num_stations = static_cast<int>(stations.size());
  if (report.num_stations < options.min_stations) {
    report.message = "the wall was seen from only " + std::to_string(report.num_stations) +
                     " stations (GNSS segments); need at least " +
                     std::to_string(options.min_stations) +
                     ": with fewer, one station's GNSS error cannot be told apart from the mount";
    return report;
  }

  // Spread of φ (Barawid 2007, Eq. 8) as axes: double the angles so that φ and φ + π coincide,
  // then the narrowest arc holding all of them is 2π minus the widest empty gap.
  std::vector<double> phi_rad;
  std::vector<double> doubled_rad;
  phi_rad.reserve(observations.size());
  doubled_rad.reserve(observations.size());
  for (const auto& observation : observations) {
    const calib::OrientedWall wall =
        calib::OrientWall(walls[observation.wall_index], observation.pose.antenna_local_m);
    const double phi = calib::VehicleToWallAngle(wall, observation.pose.yaw_rad);
    phi_rad.push_back(phi);
    doubled_rad.push_back(WrapAngle(2.0 * phi));
  }
  const CircularArc doubled_arc = NarrowestArc(std::move(doubled_rad));
  const double arc_start = doubled_arc.start_rad;
  report.angle_spread_rad = 0.5 * doubled_arc.width_rad;
  // Mean axis, and the extreme φ about it (an observation of the opposite face counts on the
  // same axis).
  const double mean_axis_rad = WrapAngle(0.5 * arc_start + 0.5 * report.angle_spread_rad);
  double min_dev = 0.0;
  double max_dev = 0.0;
  bool first = true;
  for (double phi : phi_rad) {
    double dev = WrapAngle(phi - mean_axis_rad);
    if (dev > 0.5 * kPi) dev -= kPi;
    if (dev < -0.5 * kPi) dev += kPi;
    min_dev = first ? dev : std::min(min_dev, dev);
    max_dev = first ? dev : std::max(max_dev, dev);
    first = false;
  }
  report.angle_min_rad = WrapAngle(mean_axis_rad + min_dev);
  report.angle_max_rad = report.angle_min_rad + (max_dev - min_dev);

  if (report.angle_spread_rad < options.min_heading_spread_rad) {
    // Every observation constrains only n_v · (x, y); with all n_v close to the mean axis, the
    // component along u = (−sin φ̄, cos φ̄) (parallel to the wall, in vehicle coordinates) is
    // left free.
    const double ux = -std::sin(mean_axis_rad);
    const double uy = std::cos(mean_axis_rad);
    const char* axis = std::abs(ux) >= std::abs(uy) ? "forward offset x" : "lateral offset y";
    report.message =
        std::string(axis) + " is not determined: the wall was seen only at headings " +
        HeadingArc(observations) +
        Format(" (vehicle-to-wall angles %.1f°–%.1f°, spread %.1f°, need %.1f°)",
               report.angle_min_rad * kRadToDeg, report.angle_max_rad * kRadToDeg,
               report.angle_spread_rad * kRadToDeg, options.min_heading_spread_rad * kRadToDeg) +
        "; add stations turned ≥ 30° to each side, or survey a second wall at a right angle";
    return report;
  }
  report.ok = true;
  return report;
}

std::string HeadingArc(const std::vector<calib::WallObservation>& observations) {
  if (observations.empty()) return "(none)";
  // Grid heading = 90° − yaw, in [0, 2π); the narrowest arc is the circle minus its widest gap.
  std::vector<double> headings;
  headings.reserve(observations.size());
  for (const auto& o : observations) {
    headings.push_back(WrapTwoPi(HeadingFromYaw(o.pose.yaw_rad)));
  }
  const CircularArc arc = NarrowestArc(std::move(headings));
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.0f°–%.0f°", arc.start_rad * kRadToDeg,
                arc.end_rad * kRadToDeg);
  return buffer;
}

DeterminationReport CheckDetermination(const Eigen::Matrix3d& information,
                                       const std::vector<calib::WallObservation>& observations,
                                       const std::vector<calib::WallGeometry>& walls,
                                       const solvers::SolverOptions& options) {
  DeterminationReport report;
  // Scaled parameters u = D⁻¹ (x, y, yaw) with D = the largest accepted σ per axis: the
  // information of u is D I D, and every direction is determined when its smallest eigenvalue
  // is at least 1 (σ ≤ 1 along every unit direction of u).
  const Eigen::Vector3d scale(options.max_sigma_xy_m, options.max_sigma_xy_m,
                              options.max_sigma_yaw_rad);
  const Eigen::Matrix3d scaled = scale.asDiagonal() * information * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (scaled + scaled.transpose()));
  const double smallest = eigen.eigenvalues()[0];
  const Eigen::Vector3d weakest = eigen.eigenvectors().col(0);
  const Eigen::FullPivLU<Eigen::Matrix3d> lu(information);
  if (information.allFinite() && lu.isInvertible()) {
    const Eigen::Matrix3d covariance = lu.inverse();
    for (int k = 0; k < 3; ++k) {
      report.sigma[k] = covariance(k, k) > 0.0 ? std::sqrt(covariance(k, k))
                                               : std::numeric_limits<double>::infinity();
    }
  } else {
    report.sigma.setConstant(std::numeric_limits<double>::infinity());
  }
  if (information.allFinite() && smallest >= 1.0) {
    report.ok = true;
    return report;
  }
  // Name the direction by its large components (squared share ≥ 20 %), largest first.
  static const char* const kNames[3] = {"forward offset x", "lateral offset y", "yaw"};
  std::vector<int> order = {0, 1, 2};
  std::sort(order.begin(), order.end(),
            [&weakest](int a, int b) { return std::abs(weakest[a]) > std::abs(weakest[b]); });
  std::string name = kNames[order[0]];
  for (int k = 1; k < 3; ++k) {
    if (weakest[order[k]] * weakest[order[k]] >= 0.2) name += std::string(" with ") + kNames[order[k]];
  }
  report.weak_direction = name;
  const ObservabilityReport spread = CheckObservability(observations, walls, options);
  char buffer[512];
  const double sigma_along = smallest > 0.0 ? 1.0 / std::sqrt(smallest)
                                            : std::numeric_limits<double>::infinity();
  std::snprintf(buffer, sizeof buffer,
                "%s is not determined (σ along it %.1f× the accepted %.3f m / %.2f°; σ x %.3f m, "
                "y %.3f m, yaw %.3f°): the wall was seen only at headings %s (vehicle-to-wall "
                "angles %.1f°–%.1f°, %d stations); ",
                name.c_str(), sigma_along, options.max_sigma_xy_m,
                options.max_sigma_yaw_rad * kRadToDeg, report.sigma[0], report.sigma[1],
                report.sigma[2] * kRadToDeg, HeadingArc(observations).c_str(),
                spread.angle_min_rad * kRadToDeg, spread.angle_max_rad * kRadToDeg,
                spread.num_stations);
  report.message = buffer;
  if (order[0] == 2) {
    report.message +=
        "add stations and scans (the yaw comes from the wall's direction in every scan: check "
        "the heading sensor's noise and the wall detection)";
  } else {
    report.message +=
        "add stations turned ≥ 30° to each side, or survey a second wall at a right angle to "
        "this one";
  }
  return report;
}

}  // namespace wallcal::solvers
