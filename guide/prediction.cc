// SPDX-License-Identifier: Apache-2.0
#include "guide/prediction.h"

#include <algorithm>
#include <cmath>
#include <future>
#include <limits>
#include <memory>
#include <string>

#include <Eigen/Eigenvalues>

#include "common/angles.h"
#include "solvers/information.h"
#include "solvers/problem_extension.h"

namespace wallcal::guide {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// The candidate stops: angles every 10° over ±40° (those from which the wall is seen), a near,
// the usual and a far distance, short and long dwells, a quick move or a wait for the RTK error
// to decorrelate (its correlation time τ and twice it).
std::vector<double> CandidateAngles() {
  std::vector<double> angles;
  for (int deg = -40; deg <= 40; deg += 10) angles.push_back(deg * kDegToRad);
  return angles;
}

// The covariance of the data's information, with the site's systematic share on top.
Prediction FromInformation(const Eigen::Matrix3d& information, const StopModel& model) {
  Prediction prediction;
  Eigen::MatrixXd covariance;
  if (!solvers::CovarianceOfKept(information, &covariance)) return prediction;
  prediction.known = true;
  prediction.covariance = covariance + model.site_covariance;
  return prediction;
}

// The problem of the evidence and `extra`, built as calibrate builds it, at the evidence's
// solution (null: the observations have no noise model, or there are none).
std::unique_ptr<solvers::MountProblem> BuildProblem(
    const StopModel& model, const Evidence& evidence,
    const std::vector<calib::WallObservation>& extra, const std::vector<double>& extra_weights) {
  std::vector<calib::WallObservation> observations = evidence.observations;
  std::vector<double> weights = evidence.weights;
  weights.resize(observations.size(), 1.0);
  observations.insert(observations.end(), extra.begin(), extra.end());
  weights.insert(weights.end(), extra_weights.begin(), extra_weights.end());
  weights.resize(observations.size(), 1.0);
  if (observations.empty()) return nullptr;
  std::string error;
  std::unique_ptr<solvers::MountProblem> problem = solvers::BuildMountProblem(
      observations, model.walls, model.solver, model.mount, model.mount, &error, weights);
  if (problem && evidence.warm != nullptr) solvers::ApplyWarmStart(*evidence.warm, problem.get());
  return problem;
}

// The evidence's problem, built once for every candidate stop, and its information
// marginalised onto the blocks a candidate shares with it (solvers/problem_extension.h): a
// candidate then costs its own observations only.
struct PreparedEvidence {
  std::unique_ptr<solvers::MountProblem> problem;
  solvers::SharedInformation shared;
  bool ready() const { return problem != nullptr && shared.information.rows() >= 3; }
};

PreparedEvidence Prepare(const StopModel& model, const Evidence& evidence) {
  PreparedEvidence prepared;
  prepared.problem = BuildProblem(model, evidence, {}, {});
  if (prepared.problem) {
    prepared.shared =
        solvers::MarginalOntoShared(*prepared.problem, std::max(1, model.solver.num_threads));
  }
  return prepared;
}

// PredictMount on the prepared evidence: the same prediction (up to rounding), from the
// extension's observations only when they extend the evidence's problem; built anew when they
// would change it (solvers::ExtensionOutcome::kChangesBase).
Prediction PredictWith(const StopModel& model, const Evidence& evidence,
                       const PreparedEvidence& prepared,
                       const std::vector<calib::WallObservation>& extra,
                       const std::vector<double>& extra_weights) {
  if (prepared.ready()) {
    solvers::ExtensionOutcome outcome = solvers::ExtensionOutcome::kChangesBase;
    const std::unique_ptr<solvers::MountProblemExtension> extension = solvers::ExtendMountProblem(
        *prepared.problem, extra, model.walls, model.solver, model.mount, extra_weights, &outcome);
    if (extension) {
      if (evidence.warm != nullptr) solvers::ApplyWarmStart(*evidence.warm, extension.get());
      return FromInformation(solvers::ExtendedMountInformation(prepared.shared, *extension),
                             model);
    }
    if (outcome == solvers::ExtensionOutcome::kNoNoiseModel) return Prediction{};
  }
  return PredictMount(model, evidence, extra, extra_weights);
}

}  // namespace

double Prediction::sigma_x_m() const { return known ? std::sqrt(covariance(0, 0)) : kInfinity; }
double Prediction::sigma_y_m() const { return known ? std::sqrt(covariance(1, 1)) : kInfinity; }
double Prediction::sigma_yaw_rad() const {
  return known ? std::sqrt(covariance(2, 2)) : kInfinity;
}

Prediction PredictMount(const StopModel& model, const Evidence& evidence,
                        const std::vector<calib::WallObservation>& extra,
                        const std::vector<double>& extra_weights) {
  std::unique_ptr<solvers::MountProblem> problem =
      BuildProblem(model, evidence, extra, extra_weights);
  if (!problem) return Prediction{};
  return FromInformation(
      solvers::MountInformation(*problem, std::max(1, model.solver.num_threads)), model);
}

double WorstSigmaRatio(const Prediction& prediction,
                       const pipeline::AcceptanceOptions& acceptance) {
  if (!prediction.known) return kInfinity;
  return std::max({prediction.sigma_x_m() / acceptance.max_sigma_xy_m,
                   prediction.sigma_y_m() / acceptance.max_sigma_xy_m,
                   prediction.sigma_yaw_rad() / acceptance.max_sigma_yaw_rad});
}

const char* SigmaAxisName(SigmaAxis axis) {
  switch (axis) {
    case SigmaAxis::kX: return "x";
    case SigmaAxis::kY: return "y";
    case SigmaAxis::kYaw: return "yaw";
  }
  return "";
}

SigmaAxis WorstSigmaAxis(const Prediction& prediction,
                         const pipeline::AcceptanceOptions& acceptance) {
  if (!prediction.known) return SigmaAxis::kX;
  const double x = prediction.sigma_x_m() / acceptance.max_sigma_xy_m;
  const double y = prediction.sigma_y_m() / acceptance.max_sigma_xy_m;
  const double yaw = prediction.sigma_yaw_rad() / acceptance.max_sigma_yaw_rad;
  if (x >= y && x >= yaw) return SigmaAxis::kX;
  return y >= yaw ? SigmaAxis::kY : SigmaAxis::kYaw;
}

SigmaEllipse EllipseOf(const Prediction& prediction) {
  SigmaEllipse ellipse;
  if (!prediction.known) return ellipse;
  const Eigen::Matrix2d xy = prediction.covariance.topLeftCorner<2, 2>();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(xy);
  if (eigen.info() != Eigen::Success) return ellipse;
  // Eigenvalues in increasing order: the last is the major axis.
  ellipse.major_m = std::sqrt(std::max(eigen.eigenvalues()(1), 0.0));
  ellipse.minor_m = std::sqrt(std::max(eigen.eigenvalues()(0), 0.0));
  const Eigen::Vector2d major = eigen.eigenvectors().col(1);
  double angle = std::atan2(major.y(), major.x());
  if (angle > 0.5 * kPi) angle -= kPi;
  if (angle <= -0.5 * kPi) angle += kPi;
  ellipse.angle_rad = angle;
  return ellipse;
}

double AngleSpread(const std::vector<double>& angles_rad) {
  if (angles_rad.empty()) return 0.0;
  std::vector<double> folded;
  for (double a : angles_rad) folded.push_back(a - kPi * std::floor(a / kPi));  // [0, π)
  std::sort(folded.begin(), folded.end());
  double largest_gap = folded.front() + kPi - folded.back();
  for (size_t i = 1; i < folded.size(); ++i) {
    largest_gap = std::max(largest_gap, folded[i] - folded[i - 1]);
  }
  return kPi - largest_gap;
}

double Shortfall(const Prediction& prediction, const std::vector<double>& station_angles_rad,
                 const solvers::SolverOptions& solver,
                 const pipeline::AcceptanceOptions& acceptance) {
  double shortfall = WorstSigmaRatio(prediction, acceptance);
  const double spread = AngleSpread(station_angles_rad);
  if (spread < solver.min_heading_spread_rad) {
    shortfall += 1.0 + (solver.min_heading_spread_rad - spread) / solver.min_heading_spread_rad;
  }
  if (static_cast<int>(station_angles_rad.size()) < solver.min_stations) shortfall += 1.0;
  return shortfall;
}

std::vector<Advice> NextStops(const StopModel& model, const Evidence& evidence, double now_s,
                              const pipeline::AcceptanceOptions& acceptance, int count) {
  std::vector<Advice> advice;
  std::vector<calib::WallObservation> chosen;
  std::vector<double> chosen_weights;
  const PreparedEvidence prepared = Prepare(model, evidence);
  Prediction current = prepared.ready()
                           ? FromInformation(solvers::MountInformation(prepared.shared), model)
                           : PredictMount(model, evidence);
  std::vector<double> angles = evidence.station_angles_rad;
  StopSpec last = evidence.last_station;
  const StopSpec* previous = evidence.has_last_station ? &last : nullptr;
  double time_s = now_s;
  int station_id = model.next_station_id;
  const double tau_s = model.solver.gnss_bias_tau_s > 0.0 ? model.solver.gnss_bias_tau_s : 60.0;
  const std::vector<double> waits = {15.0, tau_s, 2.0 * tau_s};
  const std::vector<double> dwells = {20.0, 60.0};
  std::vector<double> distances;
  for (double d : {0.75, 1.0, 1.25}) distances.push_back(d * model.typical_distance_m);
  for (int n = 0; n < count; ++n) {
    const double before = Shortfall(current, angles, model.solver, acceptance);
    if (before <= 1.0) break;
    // Scores a candidate: the largest σ over its tolerance after it, and the drop per second.
    struct Scored {
      StopSpec stop;
      Prediction after;
      double ratio = kInfinity;
      double rate = -kInfinity;
      std::vector<calib::WallObservation> observations;
      std::vector<double> weights;
    };
    auto score = [&](const StopSpec& stop) {
      Scored scored;
      std::vector<calib::WallObservation> obs = chosen;
      std::vector<double> w = chosen_weights;
      const size_t old_size = obs.size();
      int ids = station_id;
      if (!AppendWaitAndStop(model, previous, stop, time_s, &ids, &obs, &w)) return scored;
      const Prediction after = PredictWith(model, evidence, prepared, obs, w);
      std::vector<double> angles_after = angles;
      angles_after.push_back(stop.vehicle_to_wall_rad);
      const double ratio = Shortfall(after, angles_after, model.solver, acceptance);
      const double spent = stop.wait_s + stop.dwell_s;
      scored.stop = stop;
      scored.after = after;
      scored.ratio = ratio;
      // Before the σ is known at all, the stop that makes it smallest; after, the steepest drop.
      scored.rate = std::isfinite(before) ? (before - ratio) / spent : -ratio;
      scored.observations.assign(obs.begin() + static_cast<long>(old_size), obs.end());
      scored.weights.assign(w.begin() + static_cast<long>(old_size), w.end());
      return scored;
    };
    // The candidates are scored on the solver's threads (each its own problem), then taken in
    // their order, the first of equal rates kept: the choice does not depend on the threads.
    auto take_best = [&](const std::vector<StopSpec>& stops, Scored* best) {
      std::vector<Scored> scored(stops.size());
      const size_t threads = std::clamp<size_t>(static_cast<size_t>(model.solver.num_threads), 1,
                                                std::max<size_t>(1, stops.size()));
      std::vector<std::future<void>> jobs;
      for (size_t t = 1; t < threads; ++t) {
        jobs.push_back(std::async(std::launch::async, [&, t]() {
          for (size_t i = t; i < stops.size(); i += threads) scored[i] = score(stops[i]);
        }));
      }
      for (size_t i = 0; i < stops.size(); i += threads) scored[i] = score(stops[i]);
      for (std::future<void>& job : jobs) job.get();
      for (Scored& candidate : scored) {
        if (candidate.rate > best->rate) *best = std::move(candidate);
      }
    };
    // First the place (wall, angle, distance) at a middle dwell and wait, then how long to stand
    // and to wait there.
    std::vector<StopSpec> places;
    for (int wall = 0; wall < static_cast<int>(model.walls.size()); ++wall) {
      for (double angle : CandidateAngles()) {
        for (double distance : distances) {
          StopSpec stop;
          stop.wall_index = wall;
          stop.vehicle_to_wall_rad = angle;
          stop.distance_m = distance;
          stop.dwell_s = 30.0;
          stop.wait_s = tau_s;
          places.push_back(stop);
        }
      }
    }
    Scored best;
    take_best(places, &best);
    if (!std::isfinite(best.rate) && !best.after.known) break;
    const StopSpec place = best.stop;
    std::vector<StopSpec> timings;
    for (double dwell : dwells) {
      for (double wait : waits) {
        StopSpec stop = place;
        stop.dwell_s = dwell;
        stop.wait_s = wait;
        timings.push_back(stop);
      }
    }
    take_best(timings, &best);
    chosen.insert(chosen.end(), best.observations.begin(), best.observations.end());
    chosen_weights.insert(chosen_weights.end(), best.weights.begin(), best.weights.end());
    advice.push_back(Advice{best.stop, best.after});
    current = best.after;
    angles.push_back(best.stop.vehicle_to_wall_rad);
    time_s += best.stop.wait_s + best.stop.dwell_s;
    station_id += 2;
    last = best.stop;
    previous = &last;
  }
  return advice;
}

void AppendPlanObservations(const StopModel& model, const std::vector<StopSpec>& stops,
                            double start_s, std::vector<calib::WallObservation>* observations,
                            std::vector<double>* weights) {
  double t = start_s;
  int station = model.next_station_id;
  const StopSpec* previous = nullptr;
  for (const StopSpec& stop : stops) {
    AppendWaitAndStop(model, previous, stop, t, &station, observations, weights);
    t += stop.wait_s + stop.dwell_s;
    previous = &stop;
  }
}

namespace {

constexpr double kPlanDwellsS[] = {10.0, 30.0, 60.0};

std::vector<double> PlanWaitsS(const StopModel& model) {
  const double tau_s = model.solver.gnss_bias_tau_s > 0.0 ? model.solver.gnss_bias_tau_s : 60.0;
  return {15.0, 0.5 * tau_s, tau_s, 2.0 * tau_s};
}

}  // namespace

double ShortestPlanS(const StopModel& model) {
  const std::vector<double> waits = PlanWaitsS(model);
  return kMinPlanStops * (kPlanDwellsS[0] + *std::min_element(waits.begin(), waits.end()));
}

Plan BestPlan(const StopModel& model, const pipeline::AcceptanceOptions& acceptance,
              double budget_s) {
  Plan best;
  double best_ratio = kInfinity;
  for (int wall = 0; wall < static_cast<int>(model.walls.size()); ++wall) {
    for (double spread_deg : {20.0, 30.0, 40.0}) {
      for (double dwell : kPlanDwellsS) {
        for (double wait : PlanWaitsS(model)) {
          const int n = static_cast<int>(std::floor(budget_s / (dwell + wait)));
          if (n < kMinPlanStops) continue;
          Plan plan;
          for (int i = 0; i < n; ++i) {
            // Alternate the sides so that each part of the spread is seen early and late.
            const int j = (i % 2 == 0) ? i / 2 : n - 1 - i / 2;
            const double v = n == 1 ? 0.0 : -1.0 + 2.0 * j / (n - 1.0);
            StopSpec stop;
            stop.wall_index = wall;
            stop.vehicle_to_wall_rad = v * spread_deg * kDegToRad;
            stop.distance_m = model.typical_distance_m;
            stop.dwell_s = dwell;
            stop.wait_s = wait;
            plan.stops.push_back(stop);
          }
          std::vector<calib::WallObservation> obs;
          std::vector<double> w;
          AppendPlanObservations(model, plan.stops, 0.0, &obs, &w);
          plan.predicted = PredictMount(model, Evidence{}, obs, w);
          plan.seconds = n * (dwell + wait);
          const double ratio = WorstSigmaRatio(plan.predicted, acceptance);
          if (ratio < best_ratio) {
            best_ratio = ratio;
            best = plan;
          }
        }
      }
    }
  }
  return best;
}

}  // namespace wallcal::guide
