// SPDX-License-Identifier: Apache-2.0
#include "calib/wall_detector_options.h"

#include <string>
#include <tuple>

namespace wallcal::calib {
namespace {

using namespace io::option_checks;  // NOLINT: the checks every Validate() makes

// Cells of the accumulator DetectWall allocates for a gate (calib/wall_detector.cc: the gate's
// width in steps plus margins, in both directions).
double HoughCells(double angle_gate_rad, double offset_gate_m, double theta_step_rad,
                  double rho_step_m) {
  return (2.0 * angle_gate_rad / theta_step_rad + 3.0) * (2.0 * offset_gate_m / rho_step_m + 3.0);
}

}  // namespace

void DetectorOptions::Validate() const {
  io::CheckOptions("detector.", *this, VisitDetectorOptions<io::OptionChecker>);
  // Tiny steps make an accumulator no memory holds (an OpenCV assertion, once): bounded here.
  for (const auto& [angle_rad, offset_m, name] :
       {std::tuple{wide_angle_gate_rad, wide_offset_gate_m, "wide"},
        std::tuple{tight_angle_gate_rad, tight_offset_gate_m, "tight"}}) {
    const double cells = HoughCells(angle_rad, offset_m, hough_theta_step_rad, hough_rho_step_m);
    if (!(cells <= kMaxHoughCells)) {
      Fail("detector.hough_rho_step_m",
           "large enough that the " + std::string(name) +
               " gate's Hough accumulator has at most " + Number(kMaxHoughCells) +
               " cells (with detector.hough_theta_step_deg " +
               Number(hough_theta_step_rad * kRadToDeg) + ")",
           Number(hough_rho_step_m) + " (" + Number(cells) + " cells)");
    }
  }
}

}  // namespace wallcal::calib
