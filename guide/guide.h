// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide at the wall: what a session's logs hold now (they may still be growing), the σ of the
// mount if it were calibrated now, whether the acceptance tolerances are met, and the next stops
// that would lower the largest σ most; or, before any log exists, the best plan for a time
// budget. Computed once into a GuideReport; guide_text.cc renders it. guide_session.h keeps the
// guide between refreshes of logs that grow; the command line is apps/guide_command.cc.

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "guide/guide_warnings.h"
#include "guide/prediction.h"
#include "guide/stop_poses.h"
#include "pipeline/calibrate_options.h"
#include "pipeline/calibration.h"

namespace wallcal::guide {

struct GuideOptions {
  std::string session_path;  // session.yaml or its folder
  std::string config_path;   // calibrate options (as calibrate's --config); empty: defaults
  int threads = 0;           // 0: every core
  int max_next = 3;          // stops to advise (1..3)
  // A session with `scanners:`: the scanner to guide (--scanner ID); empty: a one-scanner
  // session.
  std::string scanner_id;
  // Throws io::InputError naming the first bad field (no session, max_next outside 1..3,
  // threads < 0).
  void Validate() const;
};

// A station recorded so far (a dwell with the wall detected).
struct StationSummary {
  double start_s = 0.0;  // from the session's first scan used
  double end_s = 0.0;
  int wall_index = 0;
  double vehicle_to_wall_rad = 0.0;  // φ, Barawid et al. 2007 Eq. 8
  double distance_m = 0.0;           // the antenna from the wall
  int64_t scans = 0;                 // scans with the wall detected
  SitePose pose;  // the mean antenna position and yaw of its scans with the wall (local frame)
};

// Why no σ can be predicted yet (typed; the message says it for people).
enum class NotYet { kNone, kNoScans, kNotDetermined, kBudgetTooShort };

struct GuideReport {
  std::string session_name;
  std::string scanner_id;  // a session with scanners: the scanner guided (--scanner); else empty
  std::vector<std::string> wall_ids;
  std::vector<StationSummary> stations;
  int64_t moving_scans = 0;  // scans taken while driving that the prediction uses
  double logged_s = 0.0;     // first to last scan used (s)
  Prediction predicted;      // if calibrated now
  NotYet not_yet = NotYet::kNone;
  std::string message;  // for people: why not yet, or calibrate's refusal
  bool enough = false;  // the acceptance's σ tolerances met and calibrate would not refuse
  // The σ is the adjustment's forced past an observability check (calibrate would refuse
  // without --force; message says which): the stations do not determine the mount yet.
  bool forced = false;
  std::vector<Advice> next;
  pipeline::AcceptanceOptions acceptance;
  // --plan: the best plan for the budget (no logs read).
  std::optional<Plan> plan;
  double plan_budget_s = 0.0;

  // Why not enough, typed: the axis whose σ is furthest over its tolerance and by how much
  // (WorstSigmaRatio; +∞ when the σ is not known).
  SigmaAxis worst_axis = SigmaAxis::kX;
  double worst_ratio = std::numeric_limits<double>::infinity();
  SigmaEllipse ellipse;  // the σ of x and y as an ellipse (zero when not known)
  // The site as a map shows it, in the local frame (calib/observation.h). The surveyed walls:
  std::vector<calib::WallGeometry> walls;
  // The vehicle's latest pose: the pose logs' end when the run kept its pose interpolator, else
  // its pose at the last scan that saw a wall. None before any. Its time is counted as the
  // stations' are (s from the first scan used).
  std::optional<SitePose> vehicle;
  double vehicle_s = 0.0;
  // The mount the scanner is drawn with: the estimate when usable, else scanner.mount_guess; and
  // the scanner where it puts it at `vehicle` (none without either).
  std::optional<calib::Mount> mount;
  std::optional<ScannerPlace> scanner;
  // The dwells of the pose logs where no wall was detected, at their mean pose (known only when
  // the run kept its pose interpolator).
  std::vector<SitePose> stops_without_wall;
  // Each stop of `next` (with --plan, of plan->stops) as a pose on the site and the move to it:
  // the first from `vehicle`, each next from the stop before.
  std::vector<StopTarget> targets;
  // What the crew should know that is not a σ: walls not seen, fixes not accepted, and (added by
  // Follow) logs that stopped growing.
  std::vector<GuideWarning> warnings;
};

// Reads the session's logs as they are now (a text log's unfinished last line, a recording
// without its index or summary: what is complete) and predicts: one refresh of a new
// GuideSession (guide_session.h). Throws io::InputError for bad input (a session.yaml, survey
// or option file at fault).
GuideReport AssessSession(const GuideOptions& options);

// The report on a preview calibration's result (calibrate's observations, the estimate and
// where its adjustment ended): the stations, the σ if calibrated now, enough, and up to
// `max_next` next stops.
GuideReport ReportOn(const pipeline::CalibrationResult& result, int max_next);

// The best plan for `budget_s` from session.yaml, the survey and the options only.
GuideReport PlanSession(const GuideOptions& options, double budget_s);

}  // namespace wallcal::guide
