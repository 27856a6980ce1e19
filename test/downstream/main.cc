// SPDX-License-Identifier: Apache-2.0
// Calibrates a session in-process through the installed wallcal library and prints the mount.
// Usage: downstream SESSION   (exit 0 with "x_m y_m yaw_rad" on stdout, 1 not determined, 2 bad
// input)

#include <cstdio>
#include <iostream>

#include "io/types.h"
#include "outputs/summary.h"
#include "pipeline/calibration.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: downstream SESSION\n";
    return 2;
  }
  wallcal::pipeline::CalibrateRequest request;
  request.session_path = argv[1];
  try {
    const wallcal::pipeline::CalibrationResult result = wallcal::pipeline::RunCalibration(request);
    std::cerr << wallcal::outputs::FormatSummary(result);
    if (!result.solve.estimate.usable) return 1;
    std::printf("%.4f %.4f %.6f\n", result.solve.estimate.mount.x_m,
                result.solve.estimate.mount.y_m, result.solve.estimate.mount.yaw_rad);
    return 0;
  } catch (const wallcal::io::InputError& error) {
    std::cerr << "downstream: " << error.what() << "\n";
    return 2;
  }
}
