// SPDX-License-Identifier: Apache-2.0
#pragma once
// Several scanners on one vehicle in one adjustment. Every scanner's wall observations share the
// vehicle's error states (the GNSS-error slices with their Gauss–Markov chain, the dwells'
// heading offsets, the heading drift), the walls and their survey tie; each scanner has its own
// mount vehicle_T_scanner = [x_m, y_m, yaw_rad] and its own time block [clock offset, heading
// delay]. The joint covariance of all mounts comes from the one information path
// (solvers/information.h): the shared errors show in it as the correlation between the mounts,
// and cancel in the relative transform between two scanners (RelativeMount).
//
// What the scanners do not share is each unit's range model: an offset δb on every range of a
// unit and a relative scale error δk off its preset's correction (io::ScannerPreset
// range_model_sigma). A scanner whose preset gives them a σ has them as a parameter block with
// a zero-mean prior of that σ (solvers/unit_range_cost.h): the data tell the units apart as far
// as they can (the relative transform of two units is then known to the extent their offsets
// are), and the covariance carries what they cannot.

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "solvers/mount_solver.h"
#include "solvers/solver_options.h"

namespace wallcal::solvers {

// One scanner's part: its final wall observations (poses as its own clock rounds left them) and
// where its own adjustment ended (the start of the joint one).
struct ScannerObservations {
  std::string id;
  const std::vector<calib::WallObservation>* observations = nullptr;  // not owned, not empty
  Mount initial;                                 // its own estimate
  std::shared_ptr<const WarmStart> warm;         // its own solution state (may be null)
  // How far this unit's range model may be off the one its ranges were corrected with (1σ):
  // relative scale and offset (m), the prior of its estimate. 0: taken as exact.
  double range_scale_sigma = 0.0;
  double range_offset_sigma_m = 0.0;
};

struct JointMountEstimate {
  bool usable = false;
  std::string message;  // why not usable
  std::vector<Mount> mounts;  // one per scanner, in input order
  // The joint covariance of [x_0, y_0, yaw_0, x_1, y_1, yaw_1, ...] (m, rad), every nuisance
  // parameter (time blocks included) marginalised, the units' range models included.
  Eigen::MatrixXd covariance;
  // The units' range models' share of `covariance` (same order; zero when every σ is 0):
  // covariance − range_model_covariance is the covariance with each unit's model held at its
  // estimate.
  Eigen::MatrixXd range_model_covariance;
  // Per scanner: its unit's range offset (m) and relative scale error as estimated, and their
  // σ (0 and 0 when its preset gives them no σ).
  struct UnitRange {
    bool estimated = false;
    double offset_m = 0.0, scale = 0.0;
    double sigma_offset_m = 0.0, sigma_scale = 0.0;
  };
  std::vector<UnitRange> unit_ranges;
  // Per scanner: the clock offset (s, total: what its poses carry plus what the joint time
  // block adds) and whether the joint problem estimated it.
  std::vector<double> time_offset_s;
  std::vector<bool> time_offset_estimated;
  int observations_used = 0;
  std::string solver_report;
};

// Solves all scanners jointly, starting at each scanner's own estimate. The walls are the
// session's (one vector for every scanner). Never throws; failures come back as usable = false.
JointMountEstimate SolveJointMounts(const std::vector<ScannerObservations>& scanners,
                                    const std::vector<calib::WallGeometry>& walls,
                                    const SolverOptions& options);

// The pose of scanner `to` in the frame of scanner `from` (from_T_to = vehicle_T_from⁻¹ ·
// vehicle_T_to) and its covariance (m, rad) from the 6x6 joint covariance of
// [from (x, y, yaw), to (x, y, yaw)], to first order.
struct RelativeMount {
  Mount from_T_to;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};
RelativeMount RelativeMountOf(const Mount& from, const Mount& to,
                              const Eigen::Matrix<double, 6, 6>& joint_covariance);

}  // namespace wallcal::solvers
