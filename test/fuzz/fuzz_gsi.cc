// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the Leica GSI reader. Any input either parses into points with non-empty,
// printable ids, finite coordinates and line numbers, which combine and dump without trouble,
// or throws io::InputError.

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>

#include "io/survey/internal/leica_gsi.h"
#include "io/survey/survey_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  wallcal::io::GsiFile file;
  try {
    file = wallcal::io::ParseGsi(text, "fuzz.gsi");
  } catch (const wallcal::io::InputError&) {
    return 0;
  }
  if (file.records.empty()) std::abort();  // promised: no point is an InputError
  const std::vector<wallcal::io::SurveyPoint> points = wallcal::io::GsiSurveyPoints(file);
  if (points.size() != file.records.size()) std::abort();
  for (const wallcal::io::SurveyPoint& p : points) {
    if (p.id.empty() || p.line < 1) std::abort();
    for (char c : p.id + p.code) {
      if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) {
        std::abort();
      }
    }
    if (!std::isfinite(p.x_m) || !std::isfinite(p.y_m) || !std::isfinite(p.z_m)) std::abort();
  }
  const wallcal::io::SurveyCombination combined = wallcal::io::CombineSurveyObservations(points);
  if (combined.points.empty() || combined.points.size() > points.size()) std::abort();
  size_t observations = 0;
  for (const wallcal::io::SurveyPoint& p : combined.points) {
    if (p.observations < 1) std::abort();
    observations += static_cast<size_t>(p.observations);
  }
  if (observations != points.size()) std::abort();
  const std::string dump = wallcal::io::FormatSurveyDumpCsv(points);
  if (dump.compare(0, 20, "id,x_m,y_m,z_m,code\n") != 0) std::abort();
  return 0;
}
