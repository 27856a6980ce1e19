// libFuzzer target: the survey CSV reader. Any input either gives points with finite
// coordinates and unique, non-empty ids, or throws io::InputError.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <set>
#include <sstream>
#include <string>

#include "io/survey_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  std::vector<wallcal::io::SurveyPoint> points;
  try {
    points = wallcal::io::ParseSurvey(in, "fuzz.csv");
  } catch (const wallcal::io::InputError&) {
    return 0;
  }
  if (points.empty()) std::abort();  // promised: no points is an InputError
  std::set<std::string> ids;
  for (const wallcal::io::SurveyPoint& p : points) {
    if (p.id.empty() || !ids.insert(p.id).second) std::abort();
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) std::abort();
    if (p.line < 1) std::abort();
  }
  return 0;
}
