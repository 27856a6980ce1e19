// SPDX-License-Identifier: Apache-2.0
// The survey step of a calibration run (pipeline/internal/steps.h): the survey read, tied to the
// GNSS (total-station points through control points; a rover's points need no tie) and the walls
// fitted.

#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "calib/geodesy.h"
#include "calib/rover_survey.h"
#include "calib/survey_tie.h"
#include "common/format.h"
#include "io/survey/survey_reader.h"
#include "pipeline/checks.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {

SurveyResult TieSurveyAndFitWalls(const io::SessionSpec& session,
                                  const solvers::SolverOptions& solver, bool swap_survey_axes) {
  SurveyResult step;
  std::vector<io::SurveyPoint> observations =
      io::ReadSurvey(session.survey_points, session.survey_columns);
  if (calib::IsRoverSurvey(observations)) {
    // A rover's points are where the GNSS is: no tie, the frame at the first point.
    if (!session.control.empty()) {
      throw io::InputError(io::Where(
          session.file, session.control.front().line,
          "survey.control given, but " + session.survey_points +
              " holds rover points (latitude, longitude): they need no tie; expected no "
              "survey.control with a rover survey"));
    }
    step.frame = calib::RoverSurveyFrame(observations, session.survey_points, session.utm_zone);
    observations = calib::PlaceRoverPoints(
        observations, session.survey_points, step.frame,
        session.survey_point_sigma_m.value_or(io::kDefaultRoverPointSigmaM));
    // Points measured more than once are averaged (io/survey_reader.h).
    const io::SurveyCombination combined = io::CombineSurveyObservations(observations);
    step.points = combined.points;
    for (const std::string& w : combined.warnings) {
      step.warnings.push_back({WarningKind::kSurveyPoints, w});
    }
    step.tie = calib::RoverTie();
    step.walls =
        calib::FitWalls(step.points, session.survey_points, session, step.tie, solver.survey());
    return step;
  }
  if (session.control.empty()) {
    throw io::InputError(io::Where(
        session.file, 0,
        "no survey.control, but " + session.survey_points +
            " holds total-station coordinates; expected control points tying them to the GNSS "
            "(survey.control), or a rover survey in latitude and longitude"));
  }
  // Points measured more than once (both faces, two set-ups) are averaged (io/survey_reader.h).
  const io::SurveyCombination combined = io::CombineSurveyObservations(observations);
  step.points = combined.points;
  if (swap_survey_axes) {
    for (io::SurveyPoint& p : step.points) std::swap(p.x_m, p.y_m);
  }
  for (const std::string& w : combined.warnings) {
    step.warnings.push_back({WarningKind::kSurveyPoints, w});
  }
  const io::ControlPoint& first_control = session.control.front();
  try {
    step.frame =
        calib::MakeLocalFrame(first_control.lat_deg, first_control.lon_deg, session.utm_zone);
  } catch (const io::InputError& e) {
    // The frame comes from session.yaml's first control point and utm_zone: name the line.
    throw io::InputError(io::Where(session.file, first_control.line,
                                   std::string("survey.control[0] / utm_zone: ") + e.what()));
  }
  // Before the tie: a mirrored survey would fail it with a message about one control point.
  CheckSurveyNotMirrored(step.points, session, step.frame);
  step.tie =
      calib::TieSurvey(step.points, session.survey_points, session, step.frame, solver.survey());
  step.walls =
      calib::FitWalls(step.points, session.survey_points, session, step.tie, solver.survey());
  if (step.tie.num_control >= 2 &&
      step.tie.control_rms_m >
          3.0 * std::hypot(solver.control_sigma_m, solver.total_station_sigma_m)) {
    step.warnings.push_back({WarningKind::kControlFit,
                             "control points fit the survey with RMS " +
                                 Format("%.3f", step.tie.control_rms_m) +
                                 " m, more than 3x the expected RTK + total-station error"});
  }
  return step;
}

}  // namespace wallcal::pipeline
