// SPDX-License-Identifier: Apache-2.0
#pragma once
// calibrate --report DIR: one self-contained HTML page (DIR/report.html) that shows what the
// calibration saw and concluded. Plots are inline SVG (outputs/svg_plot.h); the page has no
// script and fetches nothing (no fonts, styles or images from anywhere), so it opens offline.
// The markup is XHTML-like (every element closed, attributes quoted, text escaped) so it can be
// checked by an XML tokenizer.
//
// Sections (by id): "decision" (verdict with reasons, estimate and σ, change since the previous
// calibration, error against truth, error budget), "mount" ((x, y) uncertainty ellipse, method,
// warnings, repeatability / time offset when present), "site-map", "scans"; then folded in
// <details id="diagnostics">: "hough", "residuals", "coverage", "counts", "solver".
//
// The page renders the result and its ReportData (pipeline/report_data.h, filled when the run
// was asked for it): no file is read here and no decision of the pipeline is repeated.

#include <string>

#include "pipeline/calibration.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::outputs {

// The page as a string. Works for an unusable estimate too (the mount section then says why;
// the panels show what exists). `joint` (a scanner of several): the page shows its joint mount,
// σ, clock offset, verdict and change, and says which figures are its own run's.
std::string FormatReportHtml(const pipeline::CalibrationResult& result,
                             const pipeline::JointScannerResult* joint = nullptr);

// Writes DIR/report.html (DIR created if missing; written atomically) and returns its path.
// Throws io::InputError when DIR cannot be created or written.
std::string WriteReport(const pipeline::CalibrationResult& result, const std::string& dir,
                        const pipeline::JointScannerResult* joint = nullptr);

}  // namespace wallcal::outputs
