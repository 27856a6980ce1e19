// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where each scan's vehicle attitude comes from (calib/site_geometry.h): an attitude stream
// ($PASHR, $PTNL,AVR, sensor_msgs/Imu), or the yard the vehicle stood on, a plane fitted to the
// GNSS antenna's RTK heights (the antenna stays at one height above the ground it stands on);
// or, with neither, a level site.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "calib/site_geometry.h"
#include "calib/time_alignment.h"
#include "io/types.h"

namespace wallcal::calib {

// One antenna height for the yard fit: where (local frame, m), how high (m, ellipsoidal) and
// when (s).
struct HeightSample {
  Eigen::Vector2d p_local_m = Eigen::Vector2d::Zero();
  double height_m = 0.0;
  double stamp_s = 0.0;
};

// The yard as a plane h = height_m + grade · (p − centre_local_m).
struct YardPlane {
  bool fitted = false;  // enough samples spread over an area (else level, grade 0)
  Eigen::Vector2d centre_local_m = Eigen::Vector2d::Zero();
  double height_m = 0.0;  // at the centre
  Eigen::Vector2d grade = Eigen::Vector2d::Zero();  // rise per metre along local x, y
  // The grade's covariance: the generalised least-squares fit's (FitYard), its level from the
  // data (noise_factor).
  Eigen::Matrix2d grade_covariance = Eigen::Matrix2d::Zero();
  // The heights' noise found against the one assumed (HeightNoise): the square root of the
  // fit's χ² over its degrees of freedom. RTK heights are usually about twice as noisy as the
  // horizontal positions the assumption is taken from.
  double noise_factor = 1.0;
  double residual_rms_m = 0.0;  // the heights about the plane
  int samples = 0;
  double extent_m = 0.0;  // the samples' spread: the largest distance from the centre
  double GradePercent() const { return 100.0 * grade.norm(); }
  // The grade's σ as a magnitude (√ of its covariance's trace).
  double GradeSigma() const;
  // Fitted, and its grade beyond kMinToldGrade and kGradeSignificance σ: not level.
  bool ToldFromLevel() const;
  // The direction the ground rises towards, clockwise from grid north (rad, [0, 2π)).
  double RiseDirectionRad() const;
  // The same in degrees rounded to `resolution_deg`, in [0, 360) after the rounding.
  double RiseDirectionDeg(double resolution_deg) const;
};

// A grade counts as told from level beyond this many of its σ and this grade (0.2 %: below it
// a 3 m lever arm moves the scanner 6 mm).
inline constexpr double kGradeSignificance = 3.0;
inline constexpr double kMinToldGrade = 0.002;

// The antennas' height noise in shape: a Gauss–Markov bias (σ, correlation time τ) plus white
// noise on each height, in the proportions of the horizontal RTK error (solver options, the
// white noise in use). Its level is taken from the fit.
struct HeightNoise {
  double bias_sigma_m = 0.0;
  double bias_tau_s = 0.0;
  double white_sigma_m = 0.0;
};

// Fits the plane to every sample (in time order; standing and driving alike: the antenna stays
// at one height above the ground) by generalised least squares under `noise`, whose time
// correlation lets the heights logged a few seconds apart while driving tell the grade despite
// the slowly wandering RTK error. Needs 3 samples spread over at least 0.5 m (1σ) in two
// directions, else fitted is false.
YardPlane FitYard(const std::vector<HeightSample>& samples, const HeightNoise& noise);

enum class AttitudeSource { kLevel, kStream, kYard };
const char* AttitudeSourceName(AttitudeSource source);  // "level", "attitude stream", "yard plane"

// The attitude of each scan, and the variance its noise adds.
class AttitudeModel {
 public:
  // A level site (every attitude zero).
  AttitudeModel() = default;
  // From a stream: samples sorted by stamp (logger clock, the stream's offset applied), the σ
  // of a sample where it gives none, and the dwells (a standing scan takes its dwell's mean).
  static AttitudeModel FromStream(std::vector<io::AttitudeSample> samples, double sigma_rad,
                                  const std::vector<Dwell>& dwells);
  // From the yard's plane.
  static AttitudeModel FromYard(const YardPlane& yard);

  AttitudeSource source() const { return source_; }
  // The vehicle's attitude at the observation (its dwell's mean at a station), and the
  // variance (rad²) of its roll and of its pitch from the stream's noise (0 for the yard: its
  // error is the plane's, common to every scan).
  Attitude At(const WallObservation& observation, double yaw_rad, double* var_roll_rad2,
              double* var_pitch_rad2) const;
  // The yard's plane with its grade shifted by `grade_delta` (for the sensitivity of the mount
  // to the grade's error); the model unchanged when not from the yard.
  AttitudeModel WithGradeDelta(const Eigen::Vector2d& grade_delta) const;
  const YardPlane& yard() const { return yard_; }
  const std::vector<io::AttitudeSample>& samples() const { return *samples_; }

 private:
  AttitudeSource source_ = AttitudeSource::kLevel;
  YardPlane yard_;
  std::shared_ptr<const std::vector<io::AttitudeSample>> samples_ =
      std::make_shared<const std::vector<io::AttitudeSample>>();
  double sigma_rad_ = 0.0;
  std::vector<Dwell> dwells_;
};

}  // namespace wallcal::calib
