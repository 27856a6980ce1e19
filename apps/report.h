#pragma once
// calibrate --report DIR: one self-contained HTML page (DIR/report.html) that shows what the
// calibration saw and concluded (issue 5 §1). Plots are inline SVG drawn here; the page has no
// script and fetches nothing (no fonts, styles or images from anywhere), so it opens offline.
// The markup is XHTML-like (every element closed, attributes quoted, text escaped) so it can be
// checked by an XML tokenizer.
//
// Sections (by id): "mount" (estimate, σ, (x, y) uncertainty ellipse, method, warnings,
// residual analysis / repeatability / time offset when present), "site-map", "scans",
// "hough", "residuals", "coverage", "counts".
//
// To draw the site map and the scans the report re-reads part of the session: the survey (to
// place control points), the GNSS log (the track) and the few scans it shows (re-detected with
// the detector options of the run and a tight gate around the final mount). That costs a pass
// over the scan log up to the last scan shown, nothing else.

#include <string>

#include "apps/pipeline.h"
#include "io/options.h"

namespace wallcal::app {

struct ReportOptions {
  int max_scan_panels = 4;  // stations whose scan is drawn (spread over the headings)
};

// The page as a string. `options` must be the options the calibration ran with (the detector
// settings decide which points are inliers). Works for an unusable estimate too (the mount
// section then says why; the panels show what exists). Throws io::InputError only if the
// session's files cannot be read again (they were read moments before).
std::string FormatReportHtml(const CalibrationResult& result, const io::CalibrateOptions& options,
                             const ReportOptions& report_options = ReportOptions());

// Writes DIR/report.html (DIR created if missing; written atomically) and returns its path.
// Throws io::InputError when DIR cannot be created or written.
std::string WriteReport(const CalibrationResult& result, const io::CalibrateOptions& options,
                        const std::string& dir,
                        const ReportOptions& report_options = ReportOptions());

}  // namespace wallcal::app
