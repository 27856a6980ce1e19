// SPDX-License-Identifier: Apache-2.0
#include "calib/attitude_model.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

#include "common/angles.h"

namespace wallcal::calib {
namespace {

// The smallest spread (1σ of the samples' positions along their narrower principal axis, m)
// over which a plane's grade is fitted: the stations of a session spread a few metres along
// the wall and towards it.
constexpr double kMinYardSpreadM = 0.5;
constexpr int kMinYardSamples = 3;

double SigmaOr(double sigma_rad, double fallback_rad) {
  return std::isfinite(sigma_rad) && sigma_rad > 0.0 ? sigma_rad : fallback_rad;
}

}  // namespace

double YardPlane::RiseDirectionRad() const {
  return WrapTwoPi(std::atan2(grade.x(), grade.y()));
}

double YardPlane::RiseDirectionDeg(double resolution_deg) const {
  const double deg =
      std::round(RiseDirectionRad() * 180.0 / kPi / resolution_deg) * resolution_deg;
  return deg >= 360.0 ? deg - 360.0 : deg;
}

YardPlane FitYard(const std::vector<HeightSample>& samples, double min_spacing_s,
                  double correlation_s) {
  std::vector<const HeightSample*> kept;
  for (const HeightSample& s : samples) {
    if (kept.empty() || s.stamp_s - kept.back()->stamp_s >= min_spacing_s) kept.push_back(&s);
  }
  YardPlane yard;
  const int n = static_cast<int>(kept.size());
  if (n < kMinYardSamples) return yard;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double mean_h = 0.0;
  for (const HeightSample* s : kept) {
    centre += s->p_local_m / n;
    mean_h += s->height_m / n;
  }
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  Eigen::Vector2d cross = Eigen::Vector2d::Zero();
  double extent_m = 0.0;
  for (const HeightSample* s : kept) {
    const Eigen::Vector2d d = s->p_local_m - centre;
    scatter += d * d.transpose();
    cross += d * (s->height_m - mean_h);
    extent_m = std::max(extent_m, d.norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter / n);
  if (!(eigen.eigenvalues().minCoeff() >= kMinYardSpreadM * kMinYardSpreadM)) return yard;
  yard.fitted = true;
  yard.centre_local_m = centre;
  yard.height_m = mean_h;
  yard.grade = scatter.ldlt().solve(cross);
  yard.samples = n;
  yard.extent_m = extent_m;
  double sum_sq_m2 = 0.0;
  for (const HeightSample* s : kept) {
    const double r = s->height_m - mean_h - yard.grade.dot(s->p_local_m - centre);
    sum_sq_m2 += r * r;
  }
  yard.residual_rms_m = std::sqrt(sum_sq_m2 / n);
  const double residual_var_m2 = n > 3 ? sum_sq_m2 / (n - 3) : sum_sq_m2;
  // The RTK error's vertical part is correlated over correlation_s: the samples count as
  // independent about once per correlation time.
  const double span_s = kept.back()->stamp_s - kept.front()->stamp_s;
  const double independent = std::max(3.0, std::min<double>(n, span_s / correlation_s + 1.0));
  yard.grade_covariance = residual_var_m2 * scatter.inverse() * (n / independent);
  return yard;
}

const char* AttitudeSourceName(AttitudeSource source) {
  switch (source) {
    case AttitudeSource::kLevel: return "level";
    case AttitudeSource::kStream: return "attitude stream";
    case AttitudeSource::kYard: return "yard plane";
  }
  return "?";
}

AttitudeModel AttitudeModel::FromStream(std::vector<io::AttitudeSample> samples,
                                        double sigma_rad, const std::vector<Dwell>& dwells) {
  AttitudeModel model;
  model.source_ = AttitudeSource::kStream;
  std::stable_sort(samples.begin(), samples.end(),
                   [](const io::AttitudeSample& a, const io::AttitudeSample& b) {
                     return a.stamp_s < b.stamp_s;
                   });
  model.samples_ = std::make_shared<const std::vector<io::AttitudeSample>>(std::move(samples));
  model.sigma_rad_ = sigma_rad;
  model.dwells_ = dwells;
  return model;
}

AttitudeModel AttitudeModel::FromYard(const YardPlane& yard) {
  AttitudeModel model;
  model.source_ = AttitudeSource::kYard;
  model.yard_ = yard;
  return model;
}

AttitudeModel AttitudeModel::WithGradeDelta(const Eigen::Vector2d& grade_delta) const {
  AttitudeModel model = *this;
  if (source_ == AttitudeSource::kYard) model.yard_.grade += grade_delta;
  return model;
}

Attitude AttitudeModel::At(const WallObservation& observation, double yaw_rad,
                           double* var_roll_rad2, double* var_pitch_rad2) const {
  *var_roll_rad2 = 0.0;
  *var_pitch_rad2 = 0.0;
  if (source_ == AttitudeSource::kLevel) return Attitude{};
  if (source_ == AttitudeSource::kYard) return AttitudeOnGround(yard_.grade, yaw_rad);
  const std::vector<io::AttitudeSample>& s = *samples_;
  if (s.empty()) return Attitude{};
  const auto before = [](const io::AttitudeSample& a, double t) { return a.stamp_s < t; };
  const calib::VehiclePose& pose = observation.pose;
  if (pose.stationary && pose.segment >= 0 && pose.segment < static_cast<int>(dwells_.size())) {
    // A station: the dwell's mean attitude, its noise averaged over its samples.
    const Dwell& dwell = dwells_[pose.segment];
    const auto first = std::lower_bound(s.begin(), s.end(), dwell.start_s, before);
    const auto last = std::lower_bound(first, s.end(), dwell.end_s + 1e-9, before);
    const long n = last - first;
    if (n > 0) {
      Attitude mean;
      double var_roll = 0.0, var_pitch = 0.0;
      for (auto it = first; it != last; ++it) {
        mean.roll_rad += it->roll_rad / n;
        mean.pitch_rad += it->pitch_rad / n;
        var_roll += std::pow(SigmaOr(it->roll_sigma_rad, sigma_rad_), 2);
        var_pitch += std::pow(SigmaOr(it->pitch_sigma_rad, sigma_rad_), 2);
      }
      *var_roll_rad2 = var_roll / (static_cast<double>(n) * n);
      *var_pitch_rad2 = var_pitch / (static_cast<double>(n) * n);
      return mean;
    }
  }
  // Moving (or a dwell without samples): linear between the samples around the stamp, the
  // nearest sample beyond the stream's ends.
  const auto next = std::lower_bound(s.begin(), s.end(), pose.stamp_s, before);
  const io::AttitudeSample& b = next == s.end() ? s.back() : *next;
  const io::AttitudeSample& a = next == s.begin() ? s.front() : *(next - 1);
  const double span_s = b.stamp_s - a.stamp_s;
  const double f = span_s > 0.0 ? std::clamp((pose.stamp_s - a.stamp_s) / span_s, 0.0, 1.0) : 0.0;
  Attitude attitude;
  attitude.roll_rad = a.roll_rad + f * (b.roll_rad - a.roll_rad);
  attitude.pitch_rad = a.pitch_rad + f * (b.pitch_rad - a.pitch_rad);
  *var_roll_rad2 = std::pow(SigmaOr(a.roll_sigma_rad, sigma_rad_), 2);
  *var_pitch_rad2 = std::pow(SigmaOr(a.pitch_sigma_rad, sigma_rad_), 2);
  return attitude;
}

}  // namespace wallcal::calib
