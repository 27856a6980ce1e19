// SPDX-License-Identifier: Apache-2.0
#pragma once
// calibrate --report DIR for a session with several scanners: besides each scanner's own page
// (DIR/ID/report.html, outputs/report.h), one page for the run, DIR/index.html: the run's
// verdict with its reasons, each scanner (joint mount with σ, verdict, change since --compare's
// file, a link to its page), the relative transforms with σ and verdict, and a site map with
// every scanner's wall detections in one SVG. Self-contained and XHTML-like as the one-scanner
// page; it renders the result and never reads a file.

#include <string>
#include <utility>

#include <Eigen/Core>

#include "calib/observation.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::outputs {

// The page as a string; for a failed run too (the scanners' table then says why).
std::string FormatSeveralReportHtml(const pipeline::SeveralScannersResult& several);

// The site map's drawing of one detection: the detected line (ρ, θ in the scanner frame)
// between its inliers' ranges, on the side of the line's foot where `wall`'s centre is, in the
// local frame (m) by the observation's vehicle pose and `mount` (the scanner in the vehicle).
std::pair<Eigen::Vector2d, Eigen::Vector2d> DetectionSegmentLocal(
    const calib::WallObservation& observation, const calib::WallGeometry& wall,
    const solvers::Mount& mount);

// Writes DIR/index.html (DIR created if missing; written atomically) and returns its path.
// Throws io::InputError when DIR cannot be created or written.
std::string WriteSeveralReport(const pipeline::SeveralScannersResult& several,
                               const std::string& dir);

}  // namespace wallcal::outputs
