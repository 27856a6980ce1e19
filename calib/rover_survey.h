// SPDX-License-Identifier: Apache-2.0
#pragma once
// Wall points measured directly by a GNSS rover (docs/survey-files.md, "Rover points"): they
// are in the GNSS's own frame already, so there is no survey tie; the session's local frame
// (calib/observation.h) is put at the first of them.

#include <optional>
#include <string>
#include <vector>

#include "calib/observation.h"
#include "calib/survey_tie.h"
#include "io/types.h"

namespace wallcal::calib {

// True when the survey's points are a rover's (frame io::SurveyFrame::kGeodetic; a file holds
// one kind).
bool IsRoverSurvey(const std::vector<io::SurveyPoint>& survey);

// The local frame of a rover survey: origin at its first point, `zone` as MakeLocalFrame.
// Throws io::InputError (io::Where(survey_file, first point's line, ...)) as MakeLocalFrame.
LocalFrame RoverSurveyFrame(const std::vector<io::SurveyPoint>& survey,
                            const std::string& survey_file, std::optional<io::UtmZone> zone);

// The rover points placed in `frame`: x_m, y_m = ToLocal(frame, lat_deg, lon_deg) (ground
// metres), z_m (the ellipsoidal height) kept, sigma_m the file's or else default_sigma_m (> 0).
// Throws io::InputError (io::Where(survey_file, point.line, ...)) as ToLocal does.
std::vector<io::SurveyPoint> PlaceRoverPoints(const std::vector<io::SurveyPoint>& survey,
                                              const std::string& survey_file,
                                              const LocalFrame& frame, double default_sigma_m);

// A rover survey's tie: the identity, without error (FitWalls then takes the walls' σ from the
// points alone).
SurveyTie RoverTie();

}  // namespace wallcal::calib
