// SPDX-License-Identifier: Apache-2.0
#pragma once
// Putting the total-station survey into the session's local ground frame (the "tie"), and the
// surveyed walls as lines in that frame.
//
// The survey is in the total station's own right-handed frame, in ground metres; the local
// frame (calib/observation.h) is also in ground metres with grid-aligned axes, so the tie is a
// rigid 2-D transform without scale: p_local = local_R_survey · p_survey + local_t_survey.
// Heights (z) play no part: the scan plane is treated as horizontal.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "calib/observation.h"
#include "io/types.h"

namespace wallcal::calib {

// The survey's error model (1σ), set in `solver:` of configs/calibrate.yaml
// (solvers::SolverOptions::survey()).
struct SurveySigmas {
  double control_sigma_m;        // RTK error of each control point
  double total_station_sigma_m;  // total-station error of each surveyed point
  double rotation_sigma_rad;     // survey.rotation_deg, used with one control point
};

// A control point's tie residual: its surveyed position mapped by the tie minus its RTK
// position, local frame, metres.
struct ControlResidual {
  std::string id;
  Eigen::Vector2d residual_m = Eigen::Vector2d::Zero();
};

struct SurveyTie {
  Eigen::Matrix2d local_R_survey = Eigen::Matrix2d::Identity();
  Eigen::Vector2d local_t_survey = Eigen::Vector2d::Zero();  // p_local = R * p_survey + t
  std::vector<ControlResidual> control_residuals;            // in the order of spec.control
  double control_rms_m = 0;        // RMS of the control residual norms (0 with one control point)
  double sigma_rotation_rad = 0;   // 1σ of the fitted (or given) rotation
  double sigma_translation_m = 0;  // 1σ per axis of the translation at the control centroid
  Eigen::Vector2d control_centroid_local = Eigen::Vector2d::Zero();
  int num_control = 0;
};

// Ties the survey to the local frame through spec.control (RTK-measured survey points).
//  - Two or more control points: least-squares rigid fit (rotation + translation) of their
//    survey coordinates onto their RTK positions ToLocal(frame, lat, lon); residuals reported.
//    spec.survey_rotation_rad is ignored.
//  - One control point: Barawid 2007, Eq. 4-5: p_local = R(ρ) (p_survey − p_survey_C) + p_local_C,
//    ρ = spec.survey_rotation_rad, the angle counter-clockwise from grid east to the survey's
//    x axis (R(ρ) maps survey axes onto grid axes).
// σ: sigma_rotation = σ / sqrt(Σ|r_i − r̄|²) with σ² = control_sigma² + total_station_sigma²
// and r_i the control points' survey positions (sigmas.rotation_sigma_rad with one control
// point); sigma_translation = σ / sqrt(n).
// Throws io::InputError (io::Where(spec.file, control.line, ...)) when there is no control
// point, when one control point comes without a rotation, when a control id is not in the
// survey or is there more than once, when two control points coincide (< 1 cm apart in the
// survey or in RTK), or when a control point disagrees with the fit by more than 1 m.
SurveyTie TieSurvey(const std::vector<io::SurveyPoint>& survey, const std::string& survey_file,
                    const io::SessionSpec& spec, const LocalFrame& frame,
                    const SurveySigmas& sigmas);

// True when two survey codes are the same without regard to case (ASCII): instrument software
// and a hand-typed session.yaml disagree on it (`wall1` for `WALL1`).
bool SameSurveyCode(const std::string& a, const std::string& b);

// The walls of spec.walls as lines in the local frame, in the same order: total least squares
// on the x, y of each wall's surveyed points (those whose code is the wall's code, compared by
// SameSurveyCode) mapped by
// the tie. The line direction points from the wall's first surveyed point (file order) towards
// its last; normal_local = direction rotated +90° (counter-clockwise); offset_m = normal · p.
// end_a/end_b: the extreme projections of the points onto the line (end_a towards the first
// point). sigma_offset_m (along the normal at the wall's centre, the midpoint of end_a/end_b)
// and sigma_angle_rad combine the fit (each point's sigma_m, a rover's, or else
// sigmas.total_station_sigma_m) and the tie (translation σ, and rotation σ times the centre's
// distance along the wall from the control centroid; nothing for a rover survey, whose tie is
// the identity). from_rover: every point of the wall is a rover's. rms_m: RMS of the points'
// distances to the fitted line.
// Throws io::InputError (io::Where(survey_file, 0, ...)) naming the wall id and code (and the
// codes the survey has) when the wall has fewer than 2 points, or when its points span less
// than 0.5 m.
std::vector<WallGeometry> FitWalls(const std::vector<io::SurveyPoint>& survey,
                                   const std::string& survey_file, const io::SessionSpec& spec,
                                   const SurveyTie& tie, const SurveySigmas& sigmas);

}  // namespace wallcal::calib
