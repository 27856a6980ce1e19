// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the HTML report shows beyond the calibration result, collected during the run (from the
// inputs the run already read, and one extra pass over the scans the report draws), so that the
// report renders a plain struct and never reads a file or repeats a decision of the pipeline.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "calib/detection_pass.h"
#include "calib/observation.h"
#include "calib/range_model.h"
#include "calib/wall_detector.h"
#include "io/types.h"

namespace wallcal::pipeline {

// A dwell the observations came from, in time order: mean antenna position and circular-mean
// yaw over its scans, the scanner there with the mount the report shows.
struct Station {
  int segment = -1;
  Eigen::Vector2d antenna_local_m = Eigen::Vector2d::Zero();
  double yaw_rad = 0.0;
  std::vector<int> observations;  // indices into SolveResult::observations
  Eigen::Vector2d scanner_local_m = Eigen::Vector2d::Zero();
};

struct ControlMark {
  std::string id;
  Eigen::Vector2d survey_local_m = Eigen::Vector2d::Zero();  // the survey point, tied
  Eigen::Vector2d rtk_local_m = Eigen::Vector2d::Zero();     // its RTK position
};

// One station's scan, detected again around the shown mount with the second pass's gates.
struct ScanPanel {
  int station = 0;       // into ReportData::stations
  int observation = 0;   // into SolveResult::observations
  int line = 0;          // the scan's line in its log
  bool have_scan = false;
  calib::ScanPoints points;
  calib::LineGate gate;
  calib::WallDetection detection;
};

// The Hough accumulator of one panel's scan over a window wider than the gates.
struct HoughView {
  bool have = false;
  int panel = 0;
  calib::LineGate window;
  calib::WallDetection detection;  // with the accumulator kept
};

struct ReportData {
  bool collected = false;
  // The mount the panels and the site map use, and where it came from.
  calib::Mount mount;
  bool have_mount = false;
  std::string mount_source;
  calib::Gates tight_gates;  // the second pass's gate half-widths
  // Site map: the GNSS track (thinned to at most 3000 vertices), surveyed wall points and
  // control points in the local frame.
  std::vector<Eigen::Vector2d> track_local_m;
  double gnss_first_s = 0.0, gnss_last_s = 0.0;
  int64_t gnss_fixes = 0;
  std::vector<Eigen::Vector2d> wall_points_local_m;
  std::vector<ControlMark> controls;
  std::vector<Station> stations;
  std::vector<ScanPanel> panels;  // sorted by grid heading
  HoughView hough;
  std::optional<calib::Mount> truth;  // the simulator's truth.yaml beside session.yaml
  std::vector<std::string> notes;  // what could not be collected, for the page
};

struct CalibrationResult;

// The report's drawings of `result` again around `mount` (a scanner's joint mount among
// several): the scanner at each station, each panel's gate and detection from the scan points
// it kept, the Hough view; nothing is read. The site map's track and survey do not depend on
// the mount. result.report not collected: returned as it is.
ReportData ReportAround(const CalibrationResult& result, const calib::Mount& mount,
                        const std::string& mount_source);

}  // namespace wallcal::pipeline
