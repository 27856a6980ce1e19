// SPDX-License-Identifier: Apache-2.0
#include "calib/rover_survey.h"

#include "calib/geodesy.h"

namespace wallcal::calib {

bool IsRoverSurvey(const std::vector<io::SurveyPoint>& survey) {
  return !survey.empty() && survey.front().frame == io::SurveyFrame::kGeodetic;
}

LocalFrame RoverSurveyFrame(const std::vector<io::SurveyPoint>& survey,
                            const std::string& survey_file, std::optional<io::UtmZone> zone) {
  const io::SurveyPoint& first = survey.front();
  try {
    return MakeLocalFrame(first.lat_deg, first.lon_deg, zone);
  } catch (const io::InputError& e) {
    throw io::InputError(io::Where(survey_file, first.line,
                                   std::string("the first rover point / utm_zone: ") + e.what()));
  }
}

std::vector<io::SurveyPoint> PlaceRoverPoints(const std::vector<io::SurveyPoint>& survey,
                                              const std::string& survey_file,
                                              const LocalFrame& frame, double default_sigma_m) {
  std::vector<io::SurveyPoint> placed = survey;
  for (io::SurveyPoint& point : placed) {
    try {
      const Eigen::Vector2d p_local = ToLocal(frame, point.lat_deg, point.lon_deg);
      point.x_m = p_local.x();
      point.y_m = p_local.y();
    } catch (const io::InputError& e) {
      throw io::InputError(io::Where(survey_file, point.line, e.what()));
    }
    if (!(point.sigma_m > 0.0)) point.sigma_m = default_sigma_m;
  }
  return placed;
}

SurveyTie RoverTie() { return SurveyTie{}; }

}  // namespace wallcal::calib
