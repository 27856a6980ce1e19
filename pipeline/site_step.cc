// SPDX-License-Identifier: Apache-2.0
// The site step of a calibration run (pipeline/internal/steps.h): where each scan's vehicle
// attitude comes from (an attitude stream, else the yard fitted to the antenna's RTK heights,
// else level), the scanner's height and tilt from session.yaml, and the checks of the stream
// against the yard.

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/angles.h"
#include "common/format.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {
namespace {

// Beyond this |roll| or |pitch| no vehicle stands still on a yard it is calibrated on.
constexpr double kMaxStandingTiltRad = 15.0 * kPi / 180.0;
// The stream's roll or pitch at the stations named as disagreeing with the yard when it
// correlates negatively with the yard's, or misses it by more than this many of the grade's σ.
constexpr double kDisagreementSigmas = 4.0;

// The antenna's height at every fix used, standing and driving, for the yard fit.
std::vector<calib::HeightSample> AntennaHeights(const RunState& state) {
  std::vector<calib::HeightSample> samples;
  samples.reserve(state.used_fixes.size());
  for (size_t i = 0; i < state.used_fixes.size(); ++i) {
    const io::GnssFix& fix = *state.used_fixes[i];
    samples.push_back({state.track_local_m[i], fix.height_m, fix.stamp_s});
  }
  return samples;
}

// The stream's samples: the session's attitude stream (attitude:, its offset applied by the
// reader), else the attitude sentences of the heading log or the GNSS log.
std::vector<io::AttitudeSample> StreamSamples(const RunState& state) {
  if (!state.attitudes.attitudes.empty()) return state.attitudes.attitudes;
  return !state.headings.attitudes.empty() ? state.headings.attitudes : state.gnss.attitudes;
}

// Compares the stream's mean roll and pitch at each station with the attitude the yard gives
// there (the vehicle standing on the plane at the station's heading).
void CheckStreamAgainstYard(const std::vector<calib::Dwell>& dwells,
                            const std::vector<io::AttitudeSample>& samples, SiteResult* site) {
  const calib::YardPlane& yard = site->yard;
  if (!yard.fitted || yard.grade.norm() < calib::kMinToldGrade) return;
  double sum_rr = 0.0, sum_pp = 0.0, yard_rr = 0.0, yard_pp = 0.0, miss_r = 0.0, miss_p = 0.0;
  int n = 0;
  for (const calib::Dwell& dwell : dwells) {
    double roll = 0.0, pitch = 0.0;
    int count = 0;
    for (const io::AttitudeSample& s : samples) {
      if (s.stamp_s < dwell.start_s || s.stamp_s > dwell.end_s) continue;
      roll += s.roll_rad;
      pitch += s.pitch_rad;
      ++count;
    }
    if (count == 0) continue;
    roll /= count;
    pitch /= count;
    const calib::Attitude expected = calib::AttitudeOnGround(yard.grade, dwell.mean_yaw_rad);
    sum_rr += roll * expected.roll_rad;
    sum_pp += pitch * expected.pitch_rad;
    yard_rr += expected.roll_rad * expected.roll_rad;
    yard_pp += expected.pitch_rad * expected.pitch_rad;
    miss_r += (roll - expected.roll_rad) * (roll - expected.roll_rad);
    miss_p += (pitch - expected.pitch_rad) * (pitch - expected.pitch_rad);
    ++n;
  }
  if (n < 3) return;
  site->roll_mismatch_rad = std::sqrt(miss_r / n);
  site->pitch_mismatch_rad = std::sqrt(miss_p / n);
  // The grade's σ as an angle: what the yard's attitude at a station may be off by.
  const double grade_sigma = yard.GradeSigma();
  const double allowed = kDisagreementSigmas * grade_sigma + 0.2 * yard.grade.norm();
  const auto disagrees = [&](double cross, double own, double mismatch) {
    // The yard varies this axis at the stations (more than its σ): the stream must follow it.
    if (std::sqrt(own / n) < 2.0 * grade_sigma) return false;
    return cross < 0.0 || mismatch > allowed;
  };
  site->roll_disagrees = disagrees(sum_rr, yard_rr, site->roll_mismatch_rad);
  site->pitch_disagrees = disagrees(sum_pp, yard_pp, site->pitch_mismatch_rad);
  const auto say = [&](const char* axis, double cross, double mismatch) {
    site->warnings.push_back(
        {WarningKind::kSite,
         Format("the attitude stream's %s disagrees with the yard the GNSS heights show "
                "(grade %.1f %% rising towards %.0f°): RMS %.2f° off at the stations",
                axis, yard.GradePercent(), yard.RiseDirectionDeg(1.0),
                mismatch * kRadToDeg) +
             (cross < 0.0 ? ", its sign reversed" : "") +
             "; check the stream's sign convention (roll positive right side down, pitch "
             "positive nose up) and how the sensor is mounted"});
  };
  if (site->roll_disagrees) say("roll", sum_rr, site->roll_mismatch_rad);
  if (site->pitch_disagrees) say("pitch", sum_pp, site->pitch_mismatch_rad);
}

}  // namespace

SiteResult SiteFromPoses(const CalibrationResult& so_far, const RunState& state) {
  SiteResult site;
  const io::SessionSpec& session = so_far.loaded.session;
  const solvers::SolverOptions& solver = so_far.loaded.options.solver;
  site.z_given = session.scanner_z_m.has_value();
  site.placement.z_m = session.scanner_z_m.value_or(0.0);
  site.z_sigma_m = session.scanner_z_sigma_m;
  site.tilt_given = session.scanner_tilt.given;
  site.placement.pitch_rad = session.scanner_tilt.pitch_rad;
  site.placement.roll_rad = session.scanner_tilt.roll_rad;
  site.tilt_sigma_rad = session.scanner_tilt.sigma_rad;

  const std::vector<calib::Dwell>& dwells = so_far.poses.interpolator->dwells();
  site.antenna_heights_m.reserve(state.used_fixes.size());
  for (const io::GnssFix* fix : state.used_fixes) {
    site.antenna_heights_m.emplace_back(fix->stamp_s, fix->height_m);
  }
  calib::HeightNoise noise;
  noise.bias_sigma_m = solver.gnss_bias_sigma_m;
  noise.bias_tau_s = solver.gnss_bias_tau_s;
  noise.white_sigma_m = so_far.poses.white_noise.gnss_white_sigma_m;
  site.yard = calib::FitYard(AntennaHeights(state), noise);
  const calib::YardPlane& yard = site.yard;
  const bool graded = yard.ToldFromLevel();

  std::vector<io::AttitudeSample> samples =
      StreamSamples(state);
  site.attitude_samples = static_cast<int64_t>(samples.size());
  if (samples.size() >= 2) {
    const auto [first, last] = std::minmax_element(
        samples.begin(), samples.end(),
        [](const io::AttitudeSample& a, const io::AttitudeSample& b) { return a.stamp_s < b.stamp_s; });
    const double span_s = last->stamp_s - first->stamp_s;
    site.attitude_rate_hz = span_s > 0.0 ? static_cast<double>(samples.size() - 1) / span_s : 0.0;
    site.roll_min_rad = site.roll_max_rad = samples.front().roll_rad;
    site.pitch_min_rad = site.pitch_max_rad = samples.front().pitch_rad;
    for (const io::AttitudeSample& s : samples) {
      site.roll_min_rad = std::min(site.roll_min_rad, s.roll_rad);
      site.roll_max_rad = std::max(site.roll_max_rad, s.roll_rad);
      site.pitch_min_rad = std::min(site.pitch_min_rad, s.pitch_rad);
      site.pitch_max_rad = std::max(site.pitch_max_rad, s.pitch_rad);
    }
    const double largest = std::max({std::abs(site.roll_min_rad), std::abs(site.roll_max_rad),
                                      std::abs(site.pitch_min_rad), std::abs(site.pitch_max_rad)});
    if (largest > kMaxStandingTiltRad) {
      site.warnings.push_back(
          {WarningKind::kSite,
           Format("the attitude stream reaches %.1f° of roll or pitch: beyond what a vehicle "
                  "stands on (%.0f°); check its fields and units (degrees)",
                  largest * kRadToDeg, kMaxStandingTiltRad * kRadToDeg)});
    }
    CheckStreamAgainstYard(dwells, samples, &site);
    site.attitude = calib::AttitudeModel::FromStream(std::move(samples),
                                                     session.attitude_sigma_rad, dwells);
  } else if (graded || (yard.fitted && site.placement.z_m != 0.0)) {
    // With the scanner's height given, the yard's fit is used whatever its grade (its σ goes
    // into the mount's): a grade too small to tell from level still moves a scanner metres
    // below the antenna. Without it, only a grade told from level is.
    site.attitude = calib::AttitudeModel::FromYard(yard);
  }
  site.yard_unmeasured = site.attitude.source() == calib::AttitudeSource::kLevel &&
                        !yard.fitted && site.placement.z_m != 0.0 && site.attitude_samples < 2;
  if (site.yard_unmeasured) {
    site.warnings.push_back(
        {WarningKind::kSite,
         "the stations do not spread over an area (all at one distance from the wall): the "
         "yard's grade cannot be measured from the GNSS heights and the site is taken as level; "
         "stand at two distances from the wall, or log an attitude stream (attitude:)"});
  }
  bool leaning = false;
  for (const calib::WallGeometry& wall : so_far.survey.walls) leaning |= wall.lean_rad != 0.0;
  const bool tilted = site.placement.pitch_rad != 0.0 || site.placement.roll_rad != 0.0;
  site.corrected =
      site.attitude.source() != calib::AttitudeSource::kLevel || tilted || leaning;
  return site;
}

std::vector<std::string> SiteReviews(const CalibrationResult& run,
                                     const solvers::MountEstimate& estimate) {
  std::vector<std::string> reasons;
  const SiteResult& site = run.site;
  if (run.solve.unknown_height_bias) {
    const Eigen::Vector3d& bias = *run.solve.unknown_height_bias;
    bool matters = false;
    for (int k = 0; k < 3; ++k) {
      matters |= std::abs(bias[k]) > std::sqrt(std::max(0.0, estimate.covariance(k, k))) / 3.0;
    }
    if (matters) {
      const std::string ground =
          site.yard.fitted
              ? Format("the yard rises %.1f %% towards %.0f° (from the GNSS heights)",
                       site.yard.GradePercent(), site.yard.RiseDirectionDeg(1.0))
              : std::string("the attitude stream shows the vehicle tilted");
      reasons.push_back(
          ground +
          Format(" and scanner.z_m is not given: a scanner %.1f m below the antenna would move "
                 "the mount by x %+.1f mm, y %+.1f mm, yaw %+.3f°",
                 -kAssumedLeverArmM, bias[0] * 1e3, bias[1] * 1e3, bias[2] * kRadToDeg) +
          " (more than a third of its σ); add scanner.z_m to session.yaml (tape from the "
          "antenna's reference point to the scanner's optical centre, negative below the "
          "antenna)");
    }
  }
  if (site.yard_unmeasured) {
    reasons.push_back(Format(
        "the yard's grade is not measured (the stations lie along one line) and the scanner is "
        "%.2f m from the antenna's height: a 2 %% grade would move it %.0f mm; stand at two "
        "distances from the wall or log an attitude stream (attitude:)",
        std::abs(site.placement.z_m), 20.0 * std::abs(site.placement.z_m)));
  }
  if (site.roll_disagrees || site.pitch_disagrees) {
    reasons.push_back(Format(
        "the attitude stream's %s disagrees with the grade the GNSS heights show (%.1f %% "
        "towards %.0f°): a sign convention reversed or the sensor mounted turned",
        site.roll_disagrees && site.pitch_disagrees ? "roll and pitch"
        : site.roll_disagrees                       ? "roll"
                                                    : "pitch",
        site.yard.GradePercent(), site.yard.RiseDirectionDeg(1.0)));
  }
  return reasons;
}

}  // namespace wallcal::pipeline
