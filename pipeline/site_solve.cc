// SPDX-License-Identifier: Apache-2.0
// The site's part of the solve step (pipeline/internal/steps.h): each observation moved into the
// level model the adjustment works in (calib::LevelCorrection), the variance the attitude
// stream's noise adds to it, and the site's systematic inputs (the scanner's height, its tilt,
// the yard's grade, the walls' leans) propagated into the mount's covariance by re-solving at
// each input moved by its σ.

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

#include <Eigen/Eigenvalues>

#include "pipeline/internal/steps.h"
#include "solvers/mount_problem.h"

namespace wallcal::pipeline {
namespace {

// The step (rad) of the attitude's numerical derivative.
constexpr double kAttitudeStepRad = 1e-4;

// The antenna's height at `stamp_s`, linear between the fixes around it.
double AntennaHeightAt(const std::vector<std::pair<double, double>>& heights, double stamp_s) {
  if (heights.empty()) return 0.0;
  const auto next = std::lower_bound(
      heights.begin(), heights.end(), stamp_s,
      [](const std::pair<double, double>& h, double t) { return h.first < t; });
  if (next == heights.begin()) return next->second;
  if (next == heights.end()) return heights.back().second;
  const auto& a = *(next - 1);
  const auto& b = *next;
  const double span_s = b.first - a.first;
  const double f = span_s > 0.0 ? (stamp_s - a.first) / span_s : 0.0;
  return a.second + f * (b.second - a.second);
}

// The wall as the corrections use it: its lean only where the survey's heights are tied to
// the GNSS's (else upright).
calib::WallGeometry UsableWall(const calib::WallGeometry& wall) {
  calib::WallGeometry out = wall;
  if (!std::isfinite(wall.reference_height_m)) out.lean_rad = 0.0;
  return out;
}

}  // namespace

// The level correction of `o` on `site` at `mount` (`usable`: the walls as UsableWall gives
// them), with the attitude's variances of roll and pitch.
Eigen::Vector2d CorrectionOf(const calib::WallObservation& o, const SiteResult& site,
                             const std::vector<calib::WallGeometry>& usable,
                             const calib::Mount& mount, calib::Attitude* attitude,
                             calib::Heights* heights, double* var_roll, double* var_pitch) {
  const calib::WallGeometry& wall = usable[o.wall_index];
  heights->antenna_m = AntennaHeightAt(site.antenna_heights_m, o.pose.stamp_s);
  heights->wall_reference_m = std::isfinite(wall.reference_height_m) ? wall.reference_height_m
                                                                      : heights->antenna_m;
  *attitude = site.attitude.At(o, calib::SolverYaw(o), var_roll, var_pitch);
  return calib::LevelCorrection(o, wall, mount, *attitude, site.placement, *heights);
}

std::vector<calib::WallGeometry> UsableWalls(const std::vector<calib::WallGeometry>& walls) {
  std::vector<calib::WallGeometry> usable;
  usable.reserve(walls.size());
  for (const calib::WallGeometry& wall : walls) usable.push_back(UsableWall(wall));
  return usable;
}

void ApplySiteCorrections(const SiteResult& site, const std::vector<calib::WallGeometry>& walls,
                          const calib::Mount& mount,
                          std::vector<calib::WallObservation>* observations,
                          const SiteCorrectionsMade* made) {
  if (!site.corrected && (made == nullptr || !made->site->corrected)) return;
  const std::vector<calib::WallGeometry> usable = UsableWalls(walls);
  std::vector<calib::WallGeometry> made_usable;
  if (made != nullptr) made_usable = UsableWalls(*made->walls);
  // How many observations share one attitude error: a station's scans of one wall share its
  // dwell's mean, a drive's scans between two samples share those samples.
  std::map<std::pair<int, int64_t>, int> sharing;
  const double rate_hz = std::max(site.attitude_rate_hz, 1e-3);
  const auto share_key = [rate_hz](const calib::WallObservation& o) {
    const bool standing = o.pose.stationary && o.pose.segment >= 0;
    return std::make_pair(o.wall_index, standing ? -1 - static_cast<int64_t>(o.pose.segment)
                                                 : static_cast<int64_t>(std::floor(o.pose.stamp_s * rate_hz)));
  };
  for (const calib::WallObservation& o : *observations) ++sharing[share_key(o)];
  for (calib::WallObservation& o : *observations) {
    calib::Attitude attitude;
    calib::Heights heights;
    double var_roll = 0.0, var_pitch = 0.0;
    if (made != nullptr && made->site->corrected) {
      // The correction made before, made again (it is a function of the observation, the site
      // and the mount) and put back.
      const Eigen::Vector2d before = CorrectionOf(o, *made->site, made_usable, made->mount,
                                                  &attitude, &heights, &var_roll, &var_pitch);
      o.rho_m += before.x();
      o.theta_rad += before.y();
    }
    o.attitude_var_rho_m2 = 0.0f;
    if (!site.corrected) continue;
    const Eigen::Vector2d correction =
        CorrectionOf(o, site, usable, mount, &attitude, &heights, &var_roll, &var_pitch);
    o.rho_m -= correction.x();
    o.theta_rad -= correction.y();
    if (var_roll + var_pitch <= 0.0) continue;
    const calib::WallGeometry& wall = usable[o.wall_index];
    calib::Attitude rolled = attitude, pitched = attitude;
    rolled.roll_rad += kAttitudeStepRad;
    pitched.pitch_rad += kAttitudeStepRad;
    const double d_roll =
        (calib::LevelCorrection(o, wall, mount, rolled, site.placement, heights).x() -
         correction.x()) / kAttitudeStepRad;
    const double d_pitch =
        (calib::LevelCorrection(o, wall, mount, pitched, site.placement, heights).x() -
         correction.x()) / kAttitudeStepRad;
    // Counted as white at the variance times the observations sharing it, their mean gets the
    // shared error's variance (as the GNSS white noise of the scans between two fixes).
    o.attitude_var_rho_m2 = static_cast<float>(
        (d_roll * d_roll * var_roll + d_pitch * d_pitch * var_pitch) * sharing[share_key(o)]);
  }
}

void PropagateSiteTerms(const CalibrationResult& so_far, const calib::Mount& corrected_at,
                        SolveResult* step) {
  const SiteResult& site = so_far.site;
  solvers::MountEstimate& e = step->estimate;
  if (!e.usable || !e.solution_state || !e.covariance.allFinite()) return;
  const bool unknown_height = !site.z_given &&
                              site.attitude.source() != calib::AttitudeSource::kLevel;
  if (!site.corrected && !unknown_height) return;
  const std::vector<calib::WallGeometry>& walls = so_far.survey.walls;
  const solvers::SolverOptions solver = so_far.SolverInUse();
  // The mount's move when the observations are corrected with `moved` in place of the site.
  const auto shift = [&](const SiteResult& moved,
                         const std::vector<calib::WallGeometry>& moved_walls) -> Eigen::Vector3d {
    std::vector<calib::WallObservation> obs = step->observations;
    const SiteCorrectionsMade made{&site, &walls, corrected_at};
    ApplySiteCorrections(moved, moved_walls, corrected_at, &obs, &made);
    const solvers::MountEstimate re =
        solvers::ClockRoundStep(obs, walls, solver, e, *e.solution_state, nullptr);
    if (!re.usable) return Eigen::Vector3d::Zero();
    return Eigen::Vector3d(re.mount.x_m - e.mount.x_m, re.mount.y_m - e.mount.y_m,
                           re.mount.yaw_rad - e.mount.yaw_rad);
  };
  const auto add = [&](const SiteTermKind kind, const Eigen::Vector3d& d) {
    SolveResult::SiteTerm* term = nullptr;
    for (SolveResult::SiteTerm& t : step->site_terms) {
      if (t.kind == kind) term = &t;
    }
    if (term == nullptr) {
      step->site_terms.push_back({kind, Eigen::Matrix3d::Zero()});
      term = &step->site_terms.back();
    }
    term->covariance += d * d.transpose();
  };
  SiteResult moved = site;
  moved.corrected = true;
  if (site.z_given) {
    moved.placement.z_m = site.placement.z_m + site.z_sigma_m;
    add(SiteTermKind::kLeverArmHeight, shift(moved, walls));
    moved.placement = site.placement;
  } else if (unknown_height) {
    moved.placement.z_m = kAssumedLeverArmM;
    step->unknown_height_bias = shift(moved, walls);
    moved.placement = site.placement;
  }
  if (site.corrected) {
    for (double* angle : {&moved.placement.pitch_rad, &moved.placement.roll_rad}) {
      *angle += site.tilt_sigma_rad;
      add(SiteTermKind::kScannerTilt, shift(moved, walls));
      moved.placement = site.placement;
    }
    if (site.attitude.source() == calib::AttitudeSource::kYard) {
      const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(site.yard.grade_covariance);
      for (int k = 0; k < 2; ++k) {
        const double sigma = std::sqrt(std::max(0.0, eigen.eigenvalues()[k]));
        if (sigma <= 0.0) continue;
        moved.attitude = site.attitude.WithGradeDelta(sigma * eigen.eigenvectors().col(k));
        add(SiteTermKind::kVehicleAttitude, shift(moved, walls));
      }
      moved.attitude = site.attitude;
    }
    for (size_t w = 0; w < walls.size(); ++w) {
      if (walls[w].lean_rad == 0.0 || !std::isfinite(walls[w].reference_height_m)) continue;
      std::vector<calib::WallGeometry> leaned = walls;
      leaned[w].lean_rad += walls[w].sigma_lean_rad;
      add(SiteTermKind::kWallLean, shift(moved, leaned));
    }
  }
  for (const SolveResult::SiteTerm& t : step->site_terms) e.covariance += t.covariance;
}

}  // namespace wallcal::pipeline
