// SPDX-License-Identifier: Apache-2.0
#pragma once
// The vehicle pose at any instant (scan times) from the GNSS position and heading streams, and
// the stations (dwells) where the vehicle stood still.
//
// Times are seconds on the session's logging clock; positions are the GNSS antenna in the
// local ground frame (calib/observation.h), metres; yaws are radians counter-clockwise from
// grid east (already converted from headings, see calib/geodesy.h).

#include <Eigen/Core>
#include <array>
#include <vector>

#include "calib/observation.h"
#include "calib/time_alignment_options.h"

namespace wallcal::calib {

struct PositionSample {
  double stamp_s = 0;
  Eigen::Vector2d p_local_m = Eigen::Vector2d::Zero();  // GNSS antenna, local frame
  double sigma_m = 0;  // per-axis 1σ (GST or a default); copied into VehiclePose::gnss_sigma_m
};

struct YawSample {
  double stamp_s = 0;
  double yaw_rad = 0;  // vehicle yaw in the local frame (ccw from grid east)
};

// A station: an interval during which the vehicle stood still.
struct Dwell {
  double start_s = 0, end_s = 0;  // stamps of its first and last GNSS sample
  Eigen::Vector2d mean_p_local_m = Eigen::Vector2d::Zero();  // mean GNSS position over it
  double mean_yaw_rad = 0;  // circular mean of the yaw samples within it, (-π, π]
  int num_yaw_samples = 0;  // how many yaw samples that mean averages (0: none, run mean used)
};

enum class PoseStatus { kOk, kBeforeStart, kAfterEnd, kGnssGap, kHeadingGap };

// "ok", "before the GNSS/heading logs", "after the GNSS/heading logs", "in a GNSS gap",
// "in a heading gap".
const char* PoseStatusName(PoseStatus status);

class PoseInterpolator {
 public:
  // Samples sorted by strictly increasing stamp, at least 2 of each; throws
  // std::invalid_argument otherwise (the pipeline sorts and filters first). The median sample
  // period of each stream times options.max_gap_periods is its largest bridgeable gap.
  //
  // Dwells are found here: the vehicle is still at a GNSS sample when, over a window of
  // options.stationary_window_s centred on it, the displacement / window is below
  // stationary_speed_mps and the yaw change / window below stationary_yaw_rate_rps. Runs of
  // still samples are then grown outwards sample by sample while position and yaw stay at the
  // run's mean (the window test alone trims about half a window off each end of a stop), and
  // neighbouring runs at the same pose are merged (one noisy heading pair fails a window and
  // would cut a station in two); grow and merge are done twice. Each run then loses
  // dwell_guard_s at both ends (the growth admits the last moments of a turn, which the dwell's
  // mean heading would misdescribe); runs still lasting at least min_dwell_s are dwells.
  PoseInterpolator(std::vector<PositionSample> positions, std::vector<YawSample> yaws,
                   const calib::AlignmentOptions& options);

  // The pose at stamp_s: position (and σ) interpolated linearly, yaw along the shorter arc;
  // outside a dwell, position and yaw by cubics through two samples each side (CubicAt).
  // Never extrapolates: outside [start_s(), end_s()] -> kBeforeStart / kAfterEnd; a bracketing
  // pair of samples further apart than the stream's max gap -> kGnssGap / kHeadingGap (GNSS
  // checked first). On kOk fills every field of *pose: stationary = inside a dwell; segment =
  // the dwell's index inside one, otherwise dwells().size() + floor((t − start_s()) / 5 s)
  // (a 5 s stretch of driving counts as one station for the geometry checks and the
  // bootstrap); gnss_segment = floor((t − start_s()) / segment_max_s), the GNSS-error slice
  // on one time grid for standing and moving scans alike;
  // velocity_local_mps and yaw_rate_rps = central differences over ±half the stationary
  // window (clipped to the streams; a few mm/s of noise inside a dwell). Inside a dwell also
  // dwell_yaw_rad / dwell_yaw_samples / dwell_mid_s from the Dwell; outside them 0.
  // On any other status *pose is left unchanged. O(log n).
  PoseStatus At(double stamp_s, VehiclePose* pose) const { return At(stamp_s, 0.0, pose); }
  // The same with the heading (yaw_rad, yaw_rate_rps) taken heading_shift_s later than the
  // position: the heading stream's delay relative to the GNSS epochs, as found so far
  // (pose.heading_shift_s). Dwells, segments and slices follow stamp_s; both times must lie
  // in [start_s(), end_s()].
  PoseStatus At(double stamp_s, double heading_shift_s, VehiclePose* pose) const;

  const std::vector<Dwell>& dwells() const { return dwells_; }
  double gnss_period_s() const { return gnss_period_s_; }        // median GNSS sample period
  double heading_period_s() const { return heading_period_s_; }  // median heading period
  double start_s() const { return start_s_; }                    // overlap of the two streams
  double end_s() const { return end_s_; }

 private:
  // Interpolation within one stream; false outside it or across a gap.
  bool PositionAt(double stamp_s, Eigen::Vector2d* p_local_m, double* sigma_m,
                  PoseStatus* failure) const;
  bool YawAt(double stamp_s, double* yaw_rad, PoseStatus* failure) const;
  // Cubic Hermite interpolation of both streams (central-difference tangents) for a moving
  // vehicle, the position at stamp_s and the yaw at yaw_stamp_s; false (outputs untouched)
  // unless two samples each side lie within the max gaps.
  // position_weights and yaw_weights receive the weights of the samples k − 1 .. k + 2 of
  // each stream (VehiclePose::gnss_fix_weights).
  bool CubicAt(double stamp_s, double yaw_stamp_s, Eigen::Vector2d* p_local_m, double* yaw_rad,
               std::array<double, 4>* position_weights, std::array<double, 4>* yaw_weights) const;
  void FindDwells();

  std::vector<PositionSample> positions_;
  std::vector<YawSample> yaws_;
  calib::AlignmentOptions options_;
  double gnss_period_s_ = 0, heading_period_s_ = 0;
  double gnss_max_gap_s_ = 0, heading_max_gap_s_ = 0;
  double start_s_ = 0, end_s_ = 0;
  std::vector<Dwell> dwells_;
};

}  // namespace wallcal::calib
