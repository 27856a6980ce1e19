// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the survey reader (CSV, or GSI when the input looks like it). Any input
// either gives points with finite coordinates and non-empty ids, or throws io::InputError.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "io/survey/survey_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<wallcal::io::SurveyPoint> points;
  try {
    points = wallcal::io::ParseSurvey(in, "fuzz.csv");
  } catch (const wallcal::io::InputError&) {
    return 0;
  }
  if (points.empty()) std::abort();  // promised: no points is an InputError
  for (const wallcal::io::SurveyPoint& p : points) {
    if (p.id.empty()) std::abort();
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) std::abort();
    if (p.line < 1) std::abort();
  }
  // Repeated ids are observations: combining keeps every one of them in some point.
  const wallcal::io::SurveyCombination combined = wallcal::io::CombineSurveyObservations(points);
  size_t observations = 0;
  for (const wallcal::io::SurveyPoint& p : combined.points) {
    observations += static_cast<size_t>(p.observations);
  }
  if (combined.points.empty() || observations != points.size()) std::abort();
  return 0;
}
