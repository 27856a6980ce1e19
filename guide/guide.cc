// SPDX-License-Identifier: Apache-2.0
#include "guide/guide.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "analysis/repeatability.h"
#include "common/angles.h"
#include "common/format.h"
#include "common/statistics.h"
#include "guide/guide_session.h"
#include "io/input_file.h"
#include "pipeline/calibration.h"
#include "pipeline/session.h"

namespace wallcal::guide {
namespace {

Eigen::Vector2d Lever(const calib::Mount& mount, double yaw_rad) {
  return Eigen::Vector2d(std::cos(yaw_rad) * mount.x_m - std::sin(yaw_rad) * mount.y_m,
                         std::sin(yaw_rad) * mount.x_m + std::cos(yaw_rad) * mount.y_m);
}

// The side of each wall the vehicle stood on (+1: n·p < d), by the observations' majority.
std::vector<double> Sides(const std::vector<calib::WallGeometry>& walls,
                          const std::vector<calib::WallObservation>& observations) {
  std::vector<double> votes(walls.size(), 0.0);
  for (const calib::WallObservation& o : observations) {
    const calib::WallGeometry& wall = walls[o.wall_index];
    votes[o.wall_index] += (wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m)) >= 0 ? 1 : -1;
  }
  std::vector<double> sides;
  for (double v : votes) sides.push_back(v >= 0.0 ? 1.0 : -1.0);
  return sides;
}

StopModel BaseModel(const pipeline::CalibrationResult& result) {
  StopModel model;
  model.walls = result.survey.walls;
  model.preset = result.loaded.preset;
  model.solver = result.SolverInUse();
  model.slice_s = result.loaded.options.alignment.segment_max_s;
  model.dwell_guard_s = result.loaded.options.alignment.dwell_guard_s;
  if (result.loaded.session.mount_guess) {
    model.mount =
        calib::Mount{result.loaded.session.mount_guess->x_m, result.loaded.session.mount_guess->y_m,
                     result.loaded.session.mount_guess->yaw_rad};
  }
  model.side.assign(model.walls.size(), 1.0);
  return model;
}

// The stations in the observations, and what the stop model learns from them.
std::vector<StationSummary> SummariseStations(const pipeline::CalibrationResult& result,
                                              double first_s, StopModel* model) {
  struct Accumulator {
    double start_s = 1e300, end_s = -1e300;
    int wall_index = 0;
    double sin_sum = 0.0, cos_sum = 0.0, distance_sum = 0.0;
    int count = 0;
    int heading_samples = 0;
    int64_t scans = 0;  // a scan's observations are adjacent: counted at each new scan_index
    int last_scan = -1;
    std::vector<const calib::WallObservation*> posed;  // every observation, for its mean pose
  };
  std::map<int, Accumulator> by_station;
  for (const calib::WallObservation& o : result.solve.observations) {
    if (!o.pose.stationary || o.pose.segment < 0) continue;
    Accumulator& a = by_station[o.pose.segment];
    const calib::WallGeometry& wall = result.survey.walls[o.wall_index];
    const double signed_distance = wall.offset_m - wall.normal_local.dot(o.pose.antenna_local_m);
    const double side = signed_distance >= 0 ? 1.0 : -1.0;
    const double angle = WrapAngle(
        std::atan2(side * wall.normal_local.y(), side * wall.normal_local.x()) - o.pose.yaw_rad);
    a.start_s = std::min(a.start_s, o.pose.stamp_s);
    a.end_s = std::max(a.end_s, o.pose.stamp_s);
    a.wall_index = o.wall_index;
    a.sin_sum += std::sin(angle);
    a.cos_sum += std::cos(angle);
    a.distance_sum += std::abs(signed_distance);
    ++a.count;
    a.heading_samples = std::max(a.heading_samples, o.pose.dwell_yaw_samples);
    if (o.scan_index != a.last_scan) {
      ++a.scans;
      a.last_scan = o.scan_index;
    }
    a.posed.push_back(&o);
  }
  std::vector<StationSummary> stations;
  std::vector<double> rates, heading_rates, distances;
  for (const auto& [id, a] : by_station) {
    StationSummary s;
    s.start_s = a.start_s - first_s;
    s.end_s = a.end_s - first_s;
    s.wall_index = a.wall_index;
    s.vehicle_to_wall_rad = std::atan2(a.sin_sum, a.cos_sum);
    s.distance_m = a.distance_sum / a.count;
    s.scans = a.scans;
    s.pose = MeanPose(a.posed).value_or(SitePose{});
    stations.push_back(s);
    distances.push_back(s.distance_m);
    const double span = a.end_s - a.start_s;
    if (span > 1.0 && a.scans > 1) {
      rates.push_back((a.scans - 1.0) / span);
      if (a.heading_samples > 0) {
        heading_rates.push_back(a.heading_samples / (span + 2.0 * model->dwell_guard_s));
      }
    }
    model->next_station_id = std::max(model->next_station_id, id + 1);
  }
  std::sort(stations.begin(), stations.end(),
            [](const StationSummary& a, const StationSummary& b) { return a.start_s < b.start_s; });
  model->scan_rate_hz = UpperMedian(rates, model->preset.rate_hz);
  model->heading_rate_hz = UpperMedian(heading_rates, 20.0);
  model->typical_distance_m = UpperMedian(distances, 8.0);
  return stations;
}

// The line fits' σ of the recorded standing scans over the beam model's (a sample of them).
double FitScale(const StopModel& model, const std::vector<calib::WallObservation>& observations) {
  std::vector<double> ratios;
  const size_t step = std::max<size_t>(1, observations.size() / 200);
  for (size_t i = 0; i < observations.size(); i += step) {
    const calib::WallObservation& o = observations[i];
    if (!o.pose.stationary || !(o.sigma_rho_m > 0.0)) continue;
    const Eigen::Vector2d scanner =
        o.pose.antenna_local_m + Lever(model.mount, o.pose.yaw_rad);
    LineFitModel fit;
    if (!ModelLineFit(model, model.walls[o.wall_index], scanner,
                      o.pose.yaw_rad + model.mount.yaw_rad, &fit)) {
      continue;
    }
    ratios.push_back(o.sigma_rho_m / fit.sigma_rho_m);
  }
  return UpperMedian(ratios, 1.0);
}

// The site as the map draws it: the walls, where the vehicle is, the dwells without a wall, and
// the warnings the observations give (walls not seen, calibrate's warnings on the logs).
void DescribeSite(const pipeline::CalibrationResult& result, double first_s,
                  GuideReport* report) {
  report->walls = result.survey.walls;
  double stamp_s = 0.0;
  if (result.poses.interpolator != nullptr) {
    calib::VehiclePose end;
    if (result.poses.interpolator->At(result.poses.interpolator->end_s(), &end) == calib::PoseStatus::kOk) {
      report->vehicle = SitePose{end.antenna_local_m, end.yaw_rad};
      stamp_s = end.stamp_s;
    }
  }
  if (!report->vehicle) report->vehicle = LatestPose(result.solve.observations, &stamp_s);
  if (report->vehicle) report->vehicle_s = stamp_s - first_s;
  const solvers::MountEstimate& estimate = result.solve.estimate;
  if (estimate.usable) {
    report->mount = estimate.mount;
  } else if (result.loaded.session.mount_guess) {
    const auto& guess = *result.loaded.session.mount_guess;
    report->mount = calib::Mount{guess.x_m, guess.y_m, guess.yaw_rad};
  }
  if (report->vehicle && report->mount) report->scanner = ScannerAt(*report->vehicle, *report->mount);

  std::set<int> seen_walls, seen_dwells;
  for (const calib::WallObservation& o : result.solve.observations) {
    seen_walls.insert(o.wall_index);
    if (o.pose.stationary) seen_dwells.insert(o.pose.segment);
  }
  if (result.poses.interpolator != nullptr) {
    const std::vector<calib::Dwell>& dwells = result.poses.interpolator->dwells();
    for (size_t d = 0; d < dwells.size(); ++d) {
      if (seen_dwells.count(static_cast<int>(d)) > 0) continue;
      report->stops_without_wall.push_back(SitePose{dwells[d].mean_p_local_m, dwells[d].mean_yaw_rad});
    }
    if (!report->stops_without_wall.empty()) {
      report->warnings.push_back(
          {GuideWarningKind::kStopsWithoutWall, "",
           Format("the vehicle stood %zu time(s) where no wall was detected",
                  report->stops_without_wall.size())});
    }
  }
  if (!report->stations.empty()) {
    for (size_t w = 0; w < result.survey.walls.size(); ++w) {
      if (seen_walls.count(static_cast<int>(w)) > 0) continue;
      report->warnings.push_back({GuideWarningKind::kWallNotSeen, result.survey.walls[w].id,
                                  "wall " + result.survey.walls[w].id +
                                      ": not detected from any station yet"});
    }
  }
  for (const pipeline::Warning& w : result.AllWarnings()) {
    if (pipeline::IsForced(w.kind)) continue;  // the note says it (report->message)
    // The run's own words (fixes below the accepted quality among them); the follower adds a
    // warning of its own when the GNSS log grows without accepted fixes (guide/follow.cc).
    report->warnings.push_back(
        {GuideWarningKind::kRun, pipeline::WarningKindName(w.kind), w.message});
  }
}

// The σ's worst axis and ellipse, for the reason a session is not enough and its picture.
void DescribeSigma(GuideReport* report) {
  report->worst_axis = WorstSigmaAxis(report->predicted, report->acceptance);
  report->worst_ratio = WorstSigmaRatio(report->predicted, report->acceptance);
  report->ellipse = EllipseOf(report->predicted);
}

}  // namespace

void GuideOptions::Validate() const {
  if (session_path.empty()) throw io::InputError("guide: no session given");
  if (max_next < 1 || max_next > 3) {
    throw io::InputError("guide: max_next " + std::to_string(max_next) + "; expected 1, 2 or 3");
  }
  if (threads < 0) {
    throw io::InputError("guide: threads " + std::to_string(threads) + "; expected 0 or more");
  }
}

GuideReport AssessSession(const GuideOptions& options) { return GuideSession(options).Refresh(); }

GuideReport ReportOn(const pipeline::CalibrationResult& result, int max_next) {
  GuideReport report;
  report.session_name = result.loaded.session.name;
  report.scanner_id = result.loaded.session.scanner_id;
  for (const calib::WallGeometry& wall : result.survey.walls) report.wall_ids.push_back(wall.id);
  report.acceptance = result.loaded.options.acceptance;
  StopModel model = BaseModel(result);
  double first_s = 1e300, last_s = -1e300;
  for (const calib::WallObservation& o : result.solve.observations) {
    first_s = std::min(first_s, o.pose.stamp_s);
    last_s = std::max(last_s, o.pose.stamp_s);
    if (!o.pose.stationary) ++report.moving_scans;
  }
  if (result.solve.observations.empty()) first_s = last_s = 0.0;
  report.logged_s = last_s - first_s;
  report.stations = SummariseStations(result, first_s, &model);
  model.side = Sides(model.walls, result.solve.observations);
  DescribeSite(result, first_s, &report);

  const solvers::MountEstimate& estimate = result.solve.estimate;
  const solvers::WarmStart* warm = estimate.solution_state.get();
  Evidence evidence;
  for (const pipeline::SolveResult::SiteTerm& term : result.solve.site_terms) {
    model.site_covariance += term.covariance;
  }
  if (estimate.usable && warm != nullptr) {
    model.mount = estimate.mount;
    model.wall_deltas = warm->wall_deltas;
    model.heading_drift_rad_per_s = warm->heading_drift_rad_per_s;
    model.heading_reference_s = estimate.heading_reference_s;
    analysis::ThinnedObservations thin = analysis::ThinForRefits(result.solve.observations);
    evidence.observations = std::move(thin.observations);
    evidence.weights.assign(evidence.observations.size(), thin.stride);
    evidence.warm = warm;
    for (const StationSummary& s : report.stations) {
      evidence.station_angles_rad.push_back(s.vehicle_to_wall_rad);
    }
    if (!report.stations.empty()) {
      const StationSummary& last = report.stations.back();
      evidence.has_last_station = true;
      evidence.last_station.wall_index = last.wall_index;
      evidence.last_station.vehicle_to_wall_rad = last.vehicle_to_wall_rad;
      evidence.last_station.distance_m = last.distance_m;
    }
    report.predicted = PredictMount(model, evidence);
  }
  if (!result.solve.observations.empty()) {
    const calib::WallObservation& o = result.solve.observations.front();
    const int slice = calib::GnssSegment(o);
    model.slice_start_s = o.pose.stamp_s - (slice + 0.5) * model.slice_s;
    model.gnss_sigma_m = result.solve.observations.back().pose.gnss_sigma_m;
    model.gnss_period_s = result.solve.observations.back().pose.gnss_period_s;
    model.fit_scale = FitScale(model, result.solve.observations);
    for (const calib::WallObservation& ob : result.solve.observations) {
      model.next_station_id = std::max(model.next_station_id, ob.pose.segment + 1);
    }
  }

  if (!report.predicted.known) {
    report.not_yet = result.solve.observations.empty() ? NotYet::kNoScans : NotYet::kNotDetermined;
    report.message = estimate.message.empty() ? "the data do not determine the mount yet"
                                              : estimate.message;
  } else if (!estimate.usable || estimate.forced) {
    report.message = estimate.message;
    if (report.message.empty() && !estimate.warnings.empty()) {
      report.message = estimate.warnings.front().message;
    }
  }
  report.forced = report.predicted.known && estimate.usable && estimate.forced;
  report.enough = report.predicted.known && estimate.usable && !estimate.forced &&
                  WorstSigmaRatio(report.predicted, report.acceptance) <= 1.0;
  if (!report.enough) {
    const int count = std::clamp(max_next, 1, 3);
    if (report.predicted.known) {
      report.next = NextStops(model, evidence, last_s, report.acceptance, count);
    } else {
      // Nothing determined yet: the start of the plan for twenty minutes.
      model.mount = estimate.usable ? estimate.mount : model.mount;
      const Plan plan = BestPlan(model, report.acceptance, 20.0 * 60.0);
      for (size_t i = 0; i < plan.stops.size() && static_cast<int>(i) < count; ++i) {
        report.next.push_back(Advice{plan.stops[i], Prediction{}});
      }
    }
  }
  std::vector<StopSpec> stops;
  for (const Advice& a : report.next) stops.push_back(a.stop);
  report.targets = TargetsFor(model, stops, report.vehicle);
  DescribeSigma(&report);
  return report;
}

GuideReport PlanSession(const GuideOptions& options, double budget_s) {
  options.Validate();
  pipeline::CalibrateRequest calibrate;
  calibrate.session_path = options.session_path;
  calibrate.scanner_id = options.scanner_id;
  calibrate.config_path = options.config_path;
  calibrate.threads = options.threads;
  pipeline::CalibrationSession run(calibrate);
  run.Load();
  run.Survey();
  const pipeline::CalibrationResult& result = run.result();
  GuideReport report;
  report.session_name = result.loaded.session.name;
  report.scanner_id = result.loaded.session.scanner_id;
  for (const calib::WallGeometry& wall : result.survey.walls) report.wall_ids.push_back(wall.id);
  report.acceptance = result.loaded.options.acceptance;
  const StopModel model = BaseModel(result);
  report.plan = BestPlan(model, report.acceptance, budget_s);
  report.plan_budget_s = budget_s;
  report.predicted = report.plan->predicted;
  report.enough = WorstSigmaRatio(report.predicted, report.acceptance) <= 1.0;
  if (report.plan->stops.empty()) {
    const double shortest_s = ShortestPlanS(model);
    report.not_yet = NotYet::kBudgetTooShort;
    report.message = Format("%.2f min is too short for a plan: the shortest has %d stops and "
                            "takes %.2f min; give at least --plan %.2f",
                            budget_s / 60.0, kMinPlanStops, shortest_s / 60.0, shortest_s / 60.0);
  }
  report.walls = result.survey.walls;
  if (result.loaded.session.mount_guess) report.mount = model.mount;
  report.targets = TargetsFor(model, report.plan->stops, std::nullopt);
  DescribeSigma(&report);
  return report;
}

}  // namespace wallcal::guide
