// SPDX-License-Identifier: Apache-2.0
// The mirrored-survey probe of a calibration run (pipeline/internal/steps.h). Two control
// points fit a mirrored survey (x and y swapped) by a rotation as well as the right one: their
// distance apart does not change. The scans tell: the walls reflected about the control points'
// line are where the scanner sees them. So when the run found no wall where the survey puts it,
// the detection and a preview solve are tried on the walls of the survey with its axes swapped,
// from the poses and scans the run already has (the local frame is the first control point's,
// so the poses do not move); a mount determined there is a mirrored survey, named as such
// (exit 2) instead of "not determined".

#include <string>

#include "pipeline/checks.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {
namespace {

// No scan sees the surveyed wall where the survey puts it: the first pass found no wall at all,
// or its estimate put the wall where no scan sees it.
bool SurveyDoesNotMatchSite(const CalibrationResult& result) {
  const solvers::MountEstimate& first_pass = result.detection.first_pass;
  const bool first_pass_found_nothing =
      !first_pass.usable && first_pass.failure == solvers::EstimateFailure::kWallNotDetected;
  return !result.solve.estimate.usable && result.solve.observations.empty() &&
         (first_pass.usable || first_pass_found_nothing);
}

}  // namespace

void ProbeMirroredSurvey(const CalibrateRequest& request, const CalibrationResult& so_far,
                         const RunState& state) {
  if (!SurveyDoesNotMatchSite(so_far) || so_far.survey.tie.num_control < 2) return;
  CalibrateRequest preview = request;
  preview.preview = true;
  preview.collect_report_data = false;
  const io::SessionSpec& session = so_far.loaded.session;
  CalibrationResult probe;
  probe.loaded = so_far.loaded;
  probe.poses = so_far.poses;
  RunState probe_state;
  try {
    probe.survey = TieSurveyAndFitWalls(session, so_far.loaded.options.solver, true);
    CheckTrackNearWalls(state.track_local_m, probe.survey.walls, probe.loaded.preset, session);
    // The passes of the run, on the swapped walls.
    probe_state.pass = state.pass;
    probe_state.pass.preset = &probe.loaded.preset;
    probe_state.pass.detector = &probe.loaded.options.detector;
    probe_state.pass.walls = &probe.survey.walls;
    probe_state.pass.poses = probe.poses.interpolator.get();
    probe_state.passes_prepared = true;
    probe.detection.moving_by_default = so_far.detection.moving_by_default;
    const FirstPassStep first = FirstPass(preview, ProgressFn(), probe, probe_state);
    if (first.stopped) return;
    probe.detection.first_pass = first.estimate;
    probe.detection.scans_in_log = first.scans_in_log;
    SecondPass(preview, ProgressFn(), probe, &probe_state);
    probe.solve = Solve(preview, ProgressFn(), probe, std::move(probe_state.detections),
                        first.estimate.mount);
  } catch (const io::InputError&) {
    return;  // the swapped survey fails too: not a mirror
  }
  if (!probe.solve.estimate.usable || probe.solve.observations.empty()) return;
  throw io::InputError(io::Where(
      session.file, session.control.empty() ? 0 : session.control.front().line,
      "mirrored survey: no scan sees the surveyed wall where the survey puts it, but with the "
      "survey's x and y (easting and northing) exchanged " +
          std::to_string(probe.solve.observations.size()) +
          " wall observations determine the mount; check whether the x and y (easting and "
          "northing) columns are swapped (survey.columns PNEZD against PENZD, or the header) in " +
          session.survey_points));
}

}  // namespace wallcal::pipeline
