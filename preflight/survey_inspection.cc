// SPDX-License-Identifier: Apache-2.0
// The report on one survey file (InspectSurveyFile): what a surveyor handed over, read as
// calibrate reads it, before it is named in a session.yaml.
#include <algorithm>
#include <limits>
#include <map>
#include <sstream>

#include "calib/rover_survey.h"
#include "io/survey/survey_reader.h"
#include "io/version.h"
#include "preflight/inspect.h"
#include "preflight/internal/inspect_internal.h"

namespace wallcal::preflight {

using namespace internal;  // the helpers shared by the inspect files

namespace {

std::string DelimiterName(char delimiter) {
  return delimiter == ';' ? "semicolon-separated (decimal commas accepted)"
         : delimiter == '\t' ? "tab-separated (decimal commas accepted)"
                             : "comma-separated";
}

// "min..max m (span m)" of the values.
std::string ExtentOf(const std::vector<double>& values) {
  const auto [low, high] = std::minmax_element(values.begin(), values.end());
  return Fmt("%.3f", *low) + " .. " + Fmt("%.3f", *high) + " m (span " +
         Fmt("%.3f", *high - *low) + " m)";
}

}  // namespace

std::string InspectSurveyFile(const std::string& path) {
  const io::SurveyFileKind kind = io::SniffSurveyFile(path);
  std::vector<io::SurveyPoint> observations = io::ReadSurvey(path);
  const bool rover = calib::IsRoverSurvey(observations);
  int file_sigmas = 0;
  if (rover) {
    // Placed as calibrate places them (east and north of the first point), so that repeated
    // points combine and the extents read in metres.
    for (const io::SurveyPoint& p : observations) file_sigmas += p.sigma_m > 0.0;
    const calib::LocalFrame frame = calib::RoverSurveyFrame(observations, path, std::nullopt);
    observations =
        calib::PlaceRoverPoints(observations, path, frame, io::kDefaultRoverPointSigmaM);
  }
  const io::SurveyCombination combined = io::CombineSurveyObservations(observations);
  std::ostringstream out;
  out << "wallcal inspect " << io::kToolVersion << ": survey file " << path << "\n";
  out << "  format    "
      << (kind.format == io::SurveyFormat::kGsi ? std::string("Leica GSI")
          : rover ? "rover CSV (latitude, longitude, ellipsoidal height), " +
                        DelimiterName(kind.delimiter)
                  : "CSV, " + DelimiterName(kind.delimiter))
      << "\n";
  if (rover) {
    out << "  frame     x, y: metres east and north of the first point; z: ellipsoidal height; "
        << file_sigmas << " of " << observations.size()
        << " points carry their own σ (the others: survey.point_sigma_m, default "
        << Fmt("%.3f", io::kDefaultRoverPointSigmaM) << " m)\n";
  }
  out << "  points    " << observations.size() << " observations, " << combined.points.size()
      << " points (" << combined.repeated_points << " measured more than once";
  if (combined.repeated_points > 0) {
    out << ", spread at most " << Fmt("%.3f", combined.max_repeat_spread_m) << " m";
  }
  out << ")\n";
  std::map<std::string, int> codes;
  for (const io::SurveyPoint& p : combined.points) ++codes[p.code];
  out << "  codes    ";
  for (const auto& [code, count] : codes) {
    out << " " << (code.empty() ? std::string("(none)") : code) << ": " << count << ";";
  }
  out << "\n";
  std::vector<double> x, y, z;
  for (const io::SurveyPoint& p : combined.points) {
    x.push_back(p.x_m);
    y.push_back(p.y_m);
    z.push_back(p.z_m);
  }
  out << "  extents   x (east)  " << ExtentOf(x) << "\n"
      << "            y (north) " << ExtentOf(y) << "\n"
      << "            z (up)    " << ExtentOf(z) << "\n";
  for (const std::string& w : combined.warnings) out << "  warning: " << w << "\n";
  out << "  (name it in session.yaml as survey.points; walls: pick their codes above, matched "
         "without case"
      << (rover ? "; no survey.control: rover points need no tie" : "") << ")\n";
  return out.str();
}

}  // namespace wallcal::preflight
