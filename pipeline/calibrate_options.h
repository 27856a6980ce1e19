// SPDX-License-Identifier: Apache-2.0
#pragma once
// Everything configs/calibrate.yaml sets: each module's options (declared beside the module)
// and the verdict's tolerances (`acceptance:`), read strictly from YAML.

#include <string>

#include "calib/time_alignment_options.h"
#include "calib/wall_detector_options.h"
#include "common/angles.h"
#include "io/config/options_map.h"
#include "solvers/solver_options.h"

namespace wallcal::pipeline {

// The verdict's tolerances (`acceptance:`): a usable mount within all of them is ACCEPT; a σ
// beyond them is REJECT; a change since the previous calibration (--compare) beyond them is
// REVIEW (the scanner may have been moved or bumped: a person decides). pipeline/verdict.h.
struct AcceptanceOptions {
  double max_sigma_xy_m = 0.02;             // 1σ of x and of y
  double max_sigma_yaw_rad = 0.0034906585;  // 1σ of yaw, 0.2 deg
  double max_change_xy_m = 0.02;            // |Δx|, |Δy| since the previous calibration
  double max_change_yaw_rad = 0.0052359878;  // |Δyaw|, 0.3 deg
  // A change is also REVIEW when it exceeds this many combined σ (σ_now² + σ_previous²)^½:
  // larger than the two calibrations' errors explain.
  double max_change_sigmas = 3.0;
  // The relative transforms of a session with several scanners (the pose of one scanner in
  // another's frame: what merging their scans needs). Its σ beyond them is REJECT, a change
  // since the previous calibration beyond them REVIEW (max_change_sigmas applies too).
  // Defaults: a relative yaw of 0.05° moves the other scanner's points by 9 mm at 10 m and
  // 5 mm of x or y by 5 mm: together about an LMS 291's 10 mm range noise, so the merged scans
  // of one wall stay one line within the noise. A change of twice that (0.1°, 10 mm) is more
  // than two such calibrations differ by: one scanner was moved against the other.
  double relative_max_sigma_xy_m = 0.005;
  double relative_max_sigma_yaw_rad = 0.00087266463;  // 0.05 deg
  double relative_max_change_xy_m = 0.01;
  double relative_max_change_yaw_rad = 0.0017453293;  // 0.1 deg
  void Validate() const;
};

// The `acceptance:` keys and their checks, for any visitor of io/config/options_map.h.
template <class V>
void VisitAcceptanceOptions(V& v, AcceptanceOptions& o) {
  v.Number("max_sigma_xy_m", o.max_sigma_xy_m, io::Positive());
  v.Scaled("max_sigma_yaw_deg", o.max_sigma_yaw_rad, kRadToDeg, io::AboveUpTo(0.0, 180.0));
  v.Number("max_change_xy_m", o.max_change_xy_m, io::Positive());
  v.Scaled("max_change_yaw_deg", o.max_change_yaw_rad, kRadToDeg, io::AboveUpTo(0.0, 180.0));
  v.Number("max_change_sigmas", o.max_change_sigmas, io::Positive());
  v.Number("relative_max_sigma_xy_m", o.relative_max_sigma_xy_m, io::Positive());
  v.Scaled("relative_max_sigma_yaw_deg", o.relative_max_sigma_yaw_rad, kRadToDeg,
           io::AboveUpTo(0.0, 180.0));
  v.Number("relative_max_change_xy_m", o.relative_max_change_xy_m, io::Positive());
  v.Scaled("relative_max_change_yaw_deg", o.relative_max_change_yaw_rad, kRadToDeg,
           io::AboveUpTo(0.0, 180.0));
}

// configs/calibrate.yaml: one section per module, each optional.
struct CalibrateOptions {
  calib::DetectorOptions detector;
  calib::AlignmentOptions alignment;
  solvers::SolverOptions solver;
  AcceptanceOptions acceptance;
  int first_pass_max_scans = 3000;  // scans sampled evenly for the first (wide-gate) pass
  void Validate() const;
};

// Reads an options file (configs/calibrate.yaml's keys: detector, alignment, solver, acceptance,
// first_pass_max_scans; each section optional, unknown keys refused) and validates it. Throws
// io::InputError "file:line: ..." naming the key at fault.
CalibrateOptions ReadCalibrateOptions(const std::string& file);

}  // namespace wallcal::pipeline
