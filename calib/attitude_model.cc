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
// The yard filter's flat priors: on the plane's height at the centre (m) and on its grade.
constexpr double kFlatHeightM = 100.0;
constexpr double kFlatGrade = 1.0;
// The smallest white noise of a height the filter takes (m): RTK heights are logged to 1 mm
// and better, and a height log without noise would leave the filter nothing to weigh.
constexpr double kMinHeightWhiteSigmaM = 0.001;

double SigmaOr(double sigma_rad, double fallback_rad) {
  return std::isfinite(sigma_rad) && sigma_rad > 0.0 ? sigma_rad : fallback_rad;
}

}  // namespace

double YardPlane::RiseDirectionRad() const {
  return WrapTwoPi(std::atan2(grade.x(), grade.y()));
}

double YardPlane::GradeSigma() const {
  return std::sqrt(std::max(0.0, grade_covariance.trace()));
}

bool YardPlane::ToldFromLevel() const {
  return fitted && grade.norm() >= kMinToldGrade && grade.norm() > kGradeSignificance * GradeSigma();
}

double YardPlane::RiseDirectionDeg(double resolution_deg) const {
  const double deg =
      std::round(RiseDirectionRad() * 180.0 / kPi / resolution_deg) * resolution_deg;
  return deg >= 360.0 ? deg - 360.0 : deg;
}

YardPlane FitYard(const std::vector<HeightSample>& samples, const HeightNoise& noise) {
  YardPlane yard;
  const int n = static_cast<int>(samples.size());
  if (n < kMinYardSamples) return yard;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  double mean_h = 0.0;
  for (const HeightSample& s : samples) {
    centre += s.p_local_m / n;
    mean_h += s.height_m / n;
  }
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  double extent_m = 0.0;
  for (const HeightSample& s : samples) {
    const Eigen::Vector2d d = s.p_local_m - centre;
    scatter += d * d.transpose();
    extent_m = std::max(extent_m, d.norm());
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(scatter / n);
  if (!(eigen.eigenvalues().minCoeff() >= kMinYardSpreadM * kMinYardSpreadM)) return yard;

  // Kalman filter over (h0, grade x, grade y, bias): the plane's three numbers are constants
  // (flat priors), the bias a Gauss–Markov process; at the last sample the constants' estimate
  // and covariance are the generalised least-squares fit to every sample.
  const double var_bias_m2 = noise.bias_sigma_m * noise.bias_sigma_m;
  const double white_m = std::max(noise.white_sigma_m, kMinHeightWhiteSigmaM);
  const double var_white_m2 = white_m * white_m;
  Eigen::Vector4d state = Eigen::Vector4d::Zero();
  Eigen::Matrix4d p = Eigen::Vector4d(kFlatHeightM * kFlatHeightM, kFlatGrade * kFlatGrade,
                                      kFlatGrade * kFlatGrade, var_bias_m2)
                          .asDiagonal();
  double chi2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const HeightSample& s = samples[static_cast<size_t>(k)];
    if (k > 0) {
      const double dt_s = std::max(0.0, s.stamp_s - samples[static_cast<size_t>(k - 1)].stamp_s);
      const double phi = noise.bias_tau_s > 0.0 ? std::exp(-dt_s / noise.bias_tau_s) : 0.0;
      state(3) *= phi;
      p.row(3) *= phi;
      p.col(3) *= phi;
      p(3, 3) += var_bias_m2 * (1.0 - phi * phi);
    }
    const Eigen::Vector2d d = s.p_local_m - centre;
    const Eigen::Vector4d h(1.0, d.x(), d.y(), 1.0);
    const double innovation = s.height_m - mean_h - h.dot(state);
    const double variance = h.dot(p * h) + var_white_m2;
    const Eigen::Vector4d gain = p * h / variance;
    state += gain * innovation;
    // Joseph form: stays symmetric and positive with the flat priors.
    const Eigen::Matrix4d keep = Eigen::Matrix4d::Identity() - gain * h.transpose();
    p = keep * p * keep.transpose() + var_white_m2 * gain * gain.transpose();
    chi2 += innovation * innovation / variance;
  }
  yard.fitted = true;
  yard.centre_local_m = centre;
  yard.height_m = mean_h + state(0);
  yard.grade = state.segment<2>(1);
  yard.samples = n;
  yard.extent_m = extent_m;
  double sum_sq_m2 = 0.0;
  for (const HeightSample& s : samples) {
    const double r = s.height_m - yard.height_m - yard.grade.dot(s.p_local_m - centre);
    sum_sq_m2 += r * r;
  }
  yard.residual_rms_m = std::sqrt(sum_sq_m2 / n);
  // The noise's level from the data: the innovations' χ² over its degrees of freedom (the
  // three constants take three). Only the shape (τ, bias against white) is assumed.
  const double variance_factor = n > 3 ? chi2 / (n - 3) : 1.0;
  yard.noise_factor = std::sqrt(variance_factor);
  yard.grade_covariance = variance_factor * p.block<2, 2>(1, 1);
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
