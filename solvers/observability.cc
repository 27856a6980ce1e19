#include "solvers/observability.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <set>

#include "solvers/geometry.h"

namespace wallcal::solvers {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kDegPerRad = 180.0 / kPi;

std::string Format(const char* format, double a, double b, double c, double d) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, format, a, b, c, d);
  return buffer;
}

}  // namespace

ObservabilityReport CheckObservability(const std::vector<calib::WallObservation>& observations,
                                       const std::vector<calib::WallGeometry>& walls,
                                       const io::SolverOptions& options) {
  ObservabilityReport report;
  report.num_observations = static_cast<int>(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    const int w = observations[i].wall_index;
    if (w < 0 || w >= static_cast<int>(walls.size())) {
      report.message = "observation " + std::to_string(i) + " (scan " +
                       std::to_string(observations[i].scan_index) + ") refers to wall index " +
                       std::to_string(w) + ", but there are " + std::to_string(walls.size()) +
                       " walls";
      return report;
    }
  }
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

  // Spread of φ (seed 002, Eq. 8) as axes: double the angles so that φ and φ + π coincide,
  // then the narrowest arc holding all of them is 2π minus the widest empty gap.
  std::vector<double> phi_rad;
  std::vector<double> doubled_rad;
  phi_rad.reserve(observations.size());
  doubled_rad.reserve(observations.size());
  for (const auto& observation : observations) {
    const OrientedWall wall =
        OrientWall(walls[observation.wall_index], observation.pose.antenna_local_m);
    const double phi = VehicleToWallAngle(wall, observation.pose.yaw_rad);
    phi_rad.push_back(phi);
    doubled_rad.push_back(WrapAngle(2.0 * phi));
  }
  std::sort(doubled_rad.begin(), doubled_rad.end());
  double widest_gap = doubled_rad.front() + 2.0 * kPi - doubled_rad.back();
  double arc_start = doubled_rad.front();
  for (size_t k = 1; k < doubled_rad.size(); ++k) {
    const double gap = doubled_rad[k] - doubled_rad[k - 1];
    if (gap > widest_gap) {
      widest_gap = gap;
      arc_start = doubled_rad[k];
    }
  }
  report.angle_spread_rad = 0.5 * (2.0 * kPi - widest_gap);
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
    const char* axis = std::abs(ux) >= std::abs(uy) ? "x (forward)" : "y (lateral)";
    report.message =
        Format(
            "the wall was seen only at vehicle-to-wall angles %.1f°–%.1f° (spread %.1f°, "
            "need %.1f°); ",
            report.angle_min_rad * kDegPerRad, report.angle_max_rad * kDegPerRad,
            report.angle_spread_rad * kDegPerRad, options.min_heading_spread_rad * kDegPerRad) +
        "the mount's " + axis + " offset is not determined: add stations turned ≥ 30° to each side";
    return report;
  }
  report.ok = true;
  return report;
}

}  // namespace wallcal::solvers
