// SPDX-License-Identifier: Apache-2.0
#pragma once
// What calib/ hands to solvers/: the surveyed walls and, per scan, the wall line the scanner saw
// together with the vehicle pose at that instant. All in the session's local ground frame:
//   p_local = (p_utm - origin_utm) / k0
// i.e. UTM grid axes (x = grid east, y = grid north) with grid distances turned back into ground
// metres by the point scale k0 at the origin, so that scanner, total station and local
// distances share one unit.

#include <array>
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace wallcal::calib {

struct LocalFrame {
  int zone = 0;             // UTM zone, 1..60
  bool north = true;        // hemisphere
  double origin_e_m = 0.0;  // UTM easting of the local origin (grid metres)
  double origin_n_m = 0.0;  // UTM northing of the local origin (grid metres)
  double scale_k0 = 1.0;    // UTM point scale at the origin (grid m per ground m)
  double convergence_rad = 0.0;  // meridian convergence γ at the origin (true north -> grid north)
};

// A surveyed wall as the line {q : normal_local · q = offset_m} in the local ground frame.
struct WallGeometry {
  std::string id;
  Eigen::Vector2d normal_local = Eigen::Vector2d::UnitX();  // unit
  double offset_m = 0.0;
  Eigen::Vector2d end_a_local = Eigen::Vector2d::Zero();  // extent of the surveyed points
  Eigen::Vector2d end_b_local = Eigen::Vector2d::Zero();
  // Uncertainty of the line from the survey and its tie to UTM (1σ): offset along the normal
  // at the wall's centre, and direction. Used as priors on the wall nuisance parameters.
  double sigma_offset_m = 0.0;
  double sigma_angle_rad = 0.0;
  // The covariance of the two (m·rad; the rotation error of the tie moves the offset at the
  // centre when the centre is not abreast of the control centroid).
  double cov_offset_angle = 0.0;
  // The part every wall of a session shares: all of them are moved by the same survey tie
  // (calib/survey_tie.h), a translation error of tie_sigma_translation_m per axis and a
  // rotation error of tie_sigma_rotation_rad about the control centroid, which moves this
  // wall's offset by tie_lever_m (m, the centre's distance along the wall from the control
  // centroid) per radian. Zero for walls made without a tie: the solver then takes the walls'
  // errors as independent.
  double tie_sigma_translation_m = 0.0;
  double tie_sigma_rotation_rad = 0.0;
  double tie_lever_m = 0.0;
  int num_points = 0;
  double rms_m = 0.0;  // total-least-squares residual RMS of the surveyed points
  // Its points were measured by a GNSS rover (a geodetic survey): then sigma_offset_m and
  // sigma_angle_rad are the rover points' fit alone, and there is no tie.
  bool from_rover = false;
  // The wall as a plane (calib/site_geometry.h): normal_local and offset_m describe its trace
  // at reference_height_m (the mean height of its survey points, on the GNSS's ellipsoidal
  // heights through the control points' vertical tie; NaN without one), and its top leans
  // towards +normal_local by tan(lean_rad) per metre of height. lean_fitted: the survey's
  // heights span enough to fit a lean (fitted_lean_rad, its 1σ sigma_lean_rad); lean_rad is
  // that fit where it is beyond 4 σ from upright, else 0.
  double lean_rad = 0.0;
  double fitted_lean_rad = 0.0;
  double sigma_lean_rad = 0.0;
  bool lean_fitted = false;
  double reference_height_m = std::numeric_limits<double>::quiet_NaN();
};

// The scanner mount: vehicle_T_scanner, the scanner's origin and x axis in the vehicle frame
// (x forward, y left, yaw ccw), which the calibration estimates.
struct Mount {
  double x_m = 0.0;    // scanner origin in the vehicle frame, forward
  double y_m = 0.0;    // left
  double yaw_rad = 0.0;  // scanner x axis from vehicle x axis, ccw
};

// The vehicle at one instant, interpolated from GNSS and heading.
struct VehiclePose {
  double stamp_s = 0.0;
  Eigen::Vector2d antenna_local_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;  // ccw from grid east (ψ = 90° − grid heading)
  double gnss_sigma_m = 0.0;     // per-axis 1σ of the GNSS position (GST or default), 0 if unknown
  bool stationary = false;
  int segment = -1;  // the station (dwell index) or, moving, the time slice; -1 none
  // The slice of time sharing one value of the correlated GNSS error (one 2-D bias in the
  // solver, chained to its neighbours by the Gauss–Markov prior): floor((t − start) /
  // alignment.segment_max_s), one time grid whether the vehicle stands or drives, since the
  // RTK error wanders within a dwell (τ ≈ 1 min). -1: use `segment` (observations not built
  // by the pose interpolator).
  int gnss_segment = -1;
  // Rates at that instant (from the GNSS and heading samples around it), for the pose at a
  // slightly different time: p(t + dt) ≈ p + v·dt, ψ(t + dt) ≈ ψ + ω·dt (scanner clock offset).
  Eigen::Vector2d velocity_local_mps = Eigen::Vector2d::Zero();  // antenna, local frame
  double yaw_rate_rps = 0.0;  // ccw
  // The heading (yaw_rad, yaw_rate_rps) was taken this much later than the position (s): the
  // heading stream's delay after the GNSS epochs as far as the clock rounds have found it
  // (solvers/solve_policy.h); 0 from a plain PoseInterpolator::At.
  double heading_shift_s = 0.0;
  // How far the clock rounds have moved this pose from its scan's stamp (s): stamp_s is the
  // scan's stamp plus this (calib::ShiftObservations); 0 before any round.
  double clock_shift_s = 0.0;
  // The median GNSS sample period of the stream the position was interpolated from (s; 0:
  // unknown): a moving scan's interpolation error and how many scans share one fix's noise.
  double gnss_period_s = 0.0;
  // The GNSS fixes the position was interpolated from and the heading samples the yaw was (at
  // stamp_s + heading_shift_s): the index k of the one at or before that time in the
  // interpolator's stream (-1: unknown) and the weights the interpolation gave the samples
  // k − 1, k, k + 1, k + 2 (they sum to 1): (0, 1 − f, f, 0) for a linear interpolation at the
  // fraction f of the way from k to k + 1, all four for a moving pose from cubics (Hermite
  // weights, PoseInterpolator::CubicAt). Several scanners' scans interpolated from the same
  // samples share those samples' white noise (solvers/joint_mounts.cc).
  int gnss_fix = -1;
  std::array<double, 4> gnss_fix_weights{};
  int heading_sample = -1;
  std::array<double, 4> heading_sample_weights{};
  // Inside a dwell (stationary): the circular mean of the heading samples over the whole dwell
  // (rad, same frame as yaw_rad), how many samples it averages, and the dwell's middle time (s).
  // The vehicle's true yaw is constant over a dwell, so the solver uses this mean instead of the
  // noisy per-scan yaw (see docs/method.md, "Heading errors"). dwell_yaw_samples = 0: not
  // filled (moving, or observations not built by PoseInterpolator); the solver then averages
  // the yaws of the segment's observations itself.
  double dwell_yaw_rad = 0.0;
  int dwell_yaw_samples = 0;
  double dwell_mid_s = 0.0;
};

// The wall line one scan saw: {p_scanner : cos(theta)·px + sin(theta)·py = rho}, rho > 0,
// theta the direction of the normal pointing from the scanner to the wall (rad, ccw from the
// scanner's x axis, in (−π, π]).
struct WallObservation {
  int scan_index = 0;  // 0-based scan number in the log
  int wall_index = 0;  // into the WallGeometry vector
  double rho_m = 0.0;
  double theta_rad = 0.0;
  double sigma_rho_m = 0.0;      // from the line fit (point noise only)
  double sigma_theta_rad = 0.0;  // from the line fit
  double cov_rho_theta = 0.0;    // covariance between the two (m·rad)
  int num_inliers = 0;
  // The variance (m²) the vehicle attitude's noise adds to rho_m (pipeline's site step; 0 on a
  // level site). A float beside num_inliers: it fills what would be padding.
  float attitude_var_rho_m2 = 0.0f;
  // The line fit's response to an offset on every range of the scan, per metre of offset
  // (WallDetection::range_offset_gain): rho (m/m) and theta (rad/m). A relative scale error δk
  // moves rho by rho_m·δk and theta not at all.
  float drho_drange_offset = 0.0f;
  float dtheta_drange_offset_per_m = 0.0f;
  double range_min_m = 0.0;   // range span of the inliers
  double range_max_m = 0.0;
  double residual_rms_m = 0.0;  // RMS of the inliers about the fitted line
  VehiclePose pose;             // the vehicle at the scan's time
};

// The key of the GNSS-error slice an observation belongs to (see VehiclePose::gnss_segment).
inline int GnssSegment(const WallObservation& observation) {
  return observation.pose.gnss_segment >= 0 ? observation.pose.gnss_segment
                                            : observation.pose.segment;
}

}  // namespace wallcal::calib
