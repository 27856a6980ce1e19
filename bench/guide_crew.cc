// SPDX-License-Identifier: Apache-2.0
// The crew loop: on the simulator, a crew that follows the guide's first advised stop, stop by
// stop, against a crew driving the field guide's fixed pattern (stations evenly over ±35°, 4 s
// each, one every 24 s: ten in four minutes, the pattern again if needed). Both stop as soon as
// calibrate (the whole run, every observation) accepts. The session is simulated anew after
// each stop with the same seed: the trajectory so far is the same, and so are its noise draws
// (the simulator draws them in time order), as if the crew had kept recording.

#include "guide_crew.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "common/angles.h"
#include "guide/guide.h"
#include "guide/guide_text.h"
#include "pipeline/calibration.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"

namespace wallcal::bench {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxStops = 24;
constexpr double kBudgetS = 15.0 * 60.0;

struct Outcome {
  int stations = 0;
  double seconds = 0.0;  // from the start to the end of the last dwell
  bool accepted = false;
  double sigma[3] = {NAN, NAN, NAN};  // calibrate's σ at the end (m, m, rad)
};

double SessionSeconds(const std::vector<sim::SimStop>& stops) {
  double t = 0.0;
  for (const sim::SimStop& s : stops) t += s.wait_s + s.dwell_s;
  return t;
}

// Simulates the stops so far into `dir`.
void Simulate(const sim::SimulationConfig& base, const std::vector<sim::SimStop>& stops,
              uint64_t seed, const fs::path& dir) {
  sim::SimulationConfig config = base;
  config.stops = stops;
  fs::remove_all(dir);
  sim::WriteSimulatedSession(config, seed, dir.string());
}

// calibrate on the stops so far: accepted when usable, not forced and within the σ tolerances.
bool Calibrate(const sim::SimulationConfig& base, const std::vector<sim::SimStop>& stops,
               uint64_t seed, const fs::path& dir, Outcome* outcome) {
  Simulate(base, stops, seed, dir);
  pipeline::CalibrateRequest request;
  request.session_path = dir.string();
  request.threads = 2;
  const pipeline::CalibrationResult result = pipeline::RunCalibration(request);
  outcome->stations = static_cast<int>(stops.size());
  outcome->seconds = SessionSeconds(stops);
  const pipeline::AcceptanceOptions& a = result.loaded.options.acceptance;
  if (result.solve.estimate.usable) {
    for (int k = 0; k < 3; ++k)
      outcome->sigma[k] = std::sqrt(result.solve.estimate.covariance(k, k));
  }
  outcome->accepted = result.solve.estimate.usable && !result.solve.estimate.forced &&
                      outcome->sigma[0] <= a.max_sigma_xy_m &&
                      outcome->sigma[1] <= a.max_sigma_xy_m &&
                      outcome->sigma[2] <= a.max_sigma_yaw_rad;
  return outcome->accepted;
}

std::vector<sim::SimStop> FixedPattern(int count) {
  std::vector<sim::SimStop> stops;
  for (int i = 0; i < count; ++i) {
    const int j = i % 10;
    sim::SimStop s;
    s.vehicle_to_wall_rad = (-35.0 + 70.0 * j / 9.0) * kDegToRad;
    s.distance_m = 8.0;
    s.dwell_s = 4.0;
    s.wait_s = i == 0 ? 0.0 : 20.0;
    stops.push_back(s);
  }
  return stops;
}

// The fixed crew: one more pattern station at a time until calibrate accepts (or the budget
// ends); `until_s` > 0: every station that fits in that time, accepted or not.
Outcome FixedCrew(const sim::SimulationConfig& config, uint64_t seed, const fs::path& dir,
                  double until_s) {
  Outcome outcome;
  for (int n = 3; n <= kMaxStops; ++n) {
    const std::vector<sim::SimStop> stops = FixedPattern(n);
    if (until_s > 0.0) {
      if (SessionSeconds(FixedPattern(n + 1)) <= until_s) continue;
      Calibrate(config, stops, seed, dir, &outcome);
      return outcome;
    }
    if (Calibrate(config, stops, seed, dir, &outcome)) return outcome;
    if (SessionSeconds(stops) > kBudgetS) break;
  }
  return outcome;
}

// The guided crew: the guide's plan's first three stops, then each time the first stop the
// guide advises, until it says enough (checked by calibrate) or the budget ends. `config_path`:
// the options the guide uses (tighter tolerances keep it advising, for the σ in a given time).
Outcome GuidedCrew(const sim::SimulationConfig& config, uint64_t seed, const fs::path& dir,
                   const std::string& config_path, double until_s, bool print = false) {
  std::vector<sim::SimStop> stops;
  for (double deg : {-30.0, 30.0, 0.0}) {
    sim::SimStop s;
    s.vehicle_to_wall_rad = deg * kDegToRad;
    s.dwell_s = 4.0;
    s.wait_s = stops.empty() ? 0.0 : 10.0;
    stops.push_back(s);
  }
  Outcome outcome;
  while (static_cast<int>(stops.size()) <= kMaxStops) {
    // To the given time, calibrate runs once at the end (below); to acceptance, after each stop.
    if (until_s > 0.0) {
      Simulate(config, stops, seed, dir);
    } else if (Calibrate(config, stops, seed, dir, &outcome)) {
      return outcome;
    }
    guide::GuideOptions request;
    request.session_path = dir.string();
    request.config_path = config_path;
    request.threads = 2;
    request.max_next = 1;
    const guide::GuideReport report = guide::AssessSession(request);
    if (print) std::printf("$ guide SESSION\n%s\n", guide::GuideText(report).c_str());
    if (report.next.empty()) break;
    const guide::StopSpec& next = report.next.front().stop;
    sim::SimStop s;
    s.vehicle_to_wall_rad = next.vehicle_to_wall_rad;
    s.distance_m = next.distance_m;
    s.dwell_s = next.dwell_s;
    s.wait_s = next.wait_s;
    std::vector<sim::SimStop> more = stops;
    more.push_back(s);
    const double limit = until_s > 0.0 ? until_s : kBudgetS;
    if (SessionSeconds(more) > limit) break;
    stops = more;
  }
  if (until_s > 0.0 || outcome.stations != static_cast<int>(stops.size())) {
    Calibrate(config, stops, seed, dir, &outcome);
  }
  return outcome;
}

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(std::lround(q * (v.size() - 1)))];
}

void PrintRow(const char* name, const std::vector<Outcome>& outcomes) {
  std::vector<double> stations, minutes, sx, sy, syaw;
  int accepted = 0;
  for (const Outcome& o : outcomes) {
    stations.push_back(o.stations);
    minutes.push_back(o.seconds / 60.0);
    sx.push_back(o.sigma[0] * 1000.0);
    sy.push_back(o.sigma[1] * 1000.0);
    syaw.push_back(o.sigma[2] * kRadToDeg);
    accepted += o.accepted ? 1 : 0;
  }
  std::printf("%-28s %2d/%zu  stations %4.1f / %4.1f  minutes %5.2f / %5.2f  σx mm %5.1f / %5.1f  "
              "σy mm %5.1f / %5.1f  σyaw deg %.3f / %.3f\n",
              name, accepted, outcomes.size(), Quantile(stations, 0.5), Quantile(stations, 1.0),
              Quantile(minutes, 0.5), Quantile(minutes, 1.0), Quantile(sx, 0.5),
              Quantile(sx, 1.0), Quantile(sy, 0.5), Quantile(sy, 1.0), Quantile(syaw, 0.5),
              Quantile(syaw, 1.0));
  std::fflush(stdout);
}

}  // namespace

int Transcript(const fs::path& dir) {
  const sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_guide_crew.yaml");
  const Outcome outcome = GuidedCrew(config, 2000, dir, "", 0.0, true);
  std::printf("calibrate: %d stations, %.1f min, σ x %.4f m y %.4f m yaw %.3f deg, %s\n",
              outcome.stations, outcome.seconds / 60.0, outcome.sigma[0], outcome.sigma[1],
              outcome.sigma[2] * kRadToDeg, outcome.accepted ? "accepted" : "not accepted");
  return 0;
}

int RunCrew(int seeds, const fs::path& scratch) {
  const sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_guide_crew.yaml");
  // Tolerances a quarter of the defaults: the guide keeps advising until the time is up.
  const fs::path tight = scratch / "tight.yaml";
  {
    std::ofstream out(tight);
    out << "acceptance:\n  max_sigma_xy_m: 0.005\n  max_sigma_yaw_deg: 0.05\n";
  }
  const fs::path dir = scratch / "crew";
  std::vector<Outcome> fixed, guided, fixed_timed, guided_timed;
  const double given_s = 5.0 * 60.0;
  for (int s = 0; s < seeds; ++s) {
    const uint64_t seed = 2000 + s;
    fixed.push_back(FixedCrew(config, seed, dir, 0.0));
    guided.push_back(GuidedCrew(config, seed, dir, "", 0.0));
    fixed_timed.push_back(FixedCrew(config, seed, dir, given_s));
    guided_timed.push_back(GuidedCrew(config, seed, dir, tight.string(), given_s));
    std::fprintf(stderr, "seed %d: fixed %d st %.1f min, guided %d st %.1f min; in 5 min σx %.1f vs %.1f mm\n",
                 s, fixed.back().stations, fixed.back().seconds / 60, guided.back().stations,
                 guided.back().seconds / 60, fixed_timed.back().sigma[0] * 1e3,
                 guided_timed.back().sigma[0] * 1e3);
  }
  fs::remove_all(dir);
  std::printf("crew (median / worst over %d seeds)  accepted\n", seeds);
  PrintRow("fixed pattern, to accept", fixed);
  PrintRow("guided, to accept", guided);
  PrintRow("fixed pattern, 5 minutes", fixed_timed);
  PrintRow("guided, 5 minutes", guided_timed);
  return 0;
}

}  // namespace wallcal::bench
