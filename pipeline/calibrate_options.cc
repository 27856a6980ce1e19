// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibrate_options.h"

namespace wallcal::pipeline {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

void AcceptanceOptions::Validate() const {
  CheckPositive("acceptance.max_sigma_xy_m", max_sigma_xy_m);
  CheckAnglePositive("acceptance.max_sigma_yaw_deg", max_sigma_yaw_rad, 180.0);
  CheckPositive("acceptance.max_change_xy_m", max_change_xy_m);
  CheckAnglePositive("acceptance.max_change_yaw_deg", max_change_yaw_rad, 180.0);
  CheckPositive("acceptance.max_change_sigmas", max_change_sigmas);
  CheckPositive("acceptance.relative_max_sigma_xy_m", relative_max_sigma_xy_m);
  CheckAnglePositive("acceptance.relative_max_sigma_yaw_deg", relative_max_sigma_yaw_rad, 180.0);
  CheckPositive("acceptance.relative_max_change_xy_m", relative_max_change_xy_m);
  CheckAnglePositive("acceptance.relative_max_change_yaw_deg", relative_max_change_yaw_rad,
                     180.0);
}

void CalibrateOptions::Validate() const {
  detector.Validate();
  alignment.Validate();
  solver.Validate();
  acceptance.Validate();
  CheckAtLeast("first_pass_max_scans", first_pass_max_scans, 1);
}

CalibrateOptions ReadCalibrateOptions(const std::string& file) {
  CalibrateOptions options;
  io::ReadOptionsFile(
      file,
      [&options](io::OptionsMap& top) {
        top.Section("detector",
                    [&](io::OptionsMap& m) { calib::VisitDetectorOptions(m, options.detector); });
        top.Section("alignment",
                    [&](io::OptionsMap& m) { calib::VisitAlignmentOptions(m, options.alignment); });
        top.Section("solver",
                    [&](io::OptionsMap& m) { solvers::VisitSolverOptions(m, options.solver); });
        top.Section("acceptance",
                    [&](io::OptionsMap& m) { VisitAcceptanceOptions(m, options.acceptance); });
        top.Integer("first_pass_max_scans", options.first_pass_max_scans);
      },
      [&options] { options.Validate(); });
  return options;
}

}  // namespace wallcal::pipeline
