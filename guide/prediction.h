// SPDX-License-Identifier: Apache-2.0
#pragma once
// The mount's σ a set of wall observations would give, by calibrate's own problem building and
// information path (solvers::BuildMountProblem, solvers::MountInformation: every nuisance
// parameter marginalised, the correlated GNSS error and the survey tie included), without a
// solve; and the stops that would lower the largest σ most.

#include <vector>

#include <Eigen/Core>

#include "calib/observation.h"
#include "guide/stop_model.h"
#include "pipeline/calibrate_options.h"
#include "solvers/mount_problem.h"

namespace wallcal::guide {

// The predicted covariance of the mount (x, y, yaw: m², m·rad, rad²). known false: the data do
// not determine every direction yet (or hold no observation).
struct Prediction {
  bool known = false;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double sigma_x_m() const;
  double sigma_y_m() const;
  double sigma_yaw_rad() const;
};

// The observations recorded so far with their weights (a thinned set: each stands for
// weight scans), and where the adjustment on them ended (null: at zero).
struct Evidence {
  std::vector<calib::WallObservation> observations;
  std::vector<double> weights;
  const solvers::WarmStart* warm = nullptr;
  // The vehicle-to-wall angles of the stations so far (rad): calibrate refuses a session whose
  // angles span less than solver.min_heading_spread_rad (modulo 180°) or that has fewer than
  // solver.min_stations stations, whatever its σ.
  std::vector<double> station_angles_rad;
  // The last station, where a wait before the next stop is spent standing (none: no station).
  bool has_last_station = false;
  StopSpec last_station;
};

// The extent of `angles_rad` taken modulo 180° (rad): 180° less the largest gap between them.
double AngleSpread(const std::vector<double>& angles_rad);

// How far the evidence is from acceptance: WorstSigmaRatio, plus 1 and the missing share for a
// spread of angles calibrate would refuse, plus 1 for too few stations. ≤ 1: enough.
double Shortfall(const Prediction& prediction, const std::vector<double>& station_angles_rad,
                 const solvers::SolverOptions& solver, const pipeline::AcceptanceOptions& acceptance);

// The prediction for `evidence` plus `extra` (synthetic stops, their own weights).
Prediction PredictMount(const StopModel& model, const Evidence& evidence,
                        const std::vector<calib::WallObservation>& extra = {},
                        const std::vector<double>& extra_weights = {});

// The largest σ over its tolerance: max(σx, σy)/max_sigma_xy, σyaw/max_sigma_yaw; +∞ when not
// known. ≤ 1: the σ part of the acceptance is met.
double WorstSigmaRatio(const Prediction& prediction, const pipeline::AcceptanceOptions& acceptance);

// The axis whose σ is furthest over its tolerance (σ/tolerance largest; x first on a tie).
enum class SigmaAxis { kX, kY, kYaw };
const char* SigmaAxisName(SigmaAxis axis);  // "x", "y", "yaw"
// The axis WorstSigmaRatio takes its ratio from (kX when the σ is not known).
SigmaAxis WorstSigmaAxis(const Prediction& prediction,
                         const pipeline::AcceptanceOptions& acceptance);

// The 1σ ellipse of the mount's x and y (vehicle frame: x forward, y left): its semi-axes (m)
// and the major axis' direction (rad, ccw from the vehicle's x, in (−π/2, π/2]).
struct SigmaEllipse {
  double major_m = 0.0;
  double minor_m = 0.0;
  double angle_rad = 0.0;
};
// The ellipse of `prediction` (all zero when it is not known).
SigmaEllipse EllipseOf(const Prediction& prediction);

// A stop and the prediction once it (and the advised stops before it) is made.
struct Advice {
  StopSpec stop;
  Prediction after;
};

// Up to `count` stops, chosen one at a time: each the candidate (vehicle-to-wall angle, distance,
// dwell, wait) whose observations lower the largest σ over its tolerance most per second spent
// (wait + dwell), given the evidence and the stops advised before it. The first starts
// `now_s` + its wait. Stops once the tolerances are met.
std::vector<Advice> NextStops(const StopModel& model, const Evidence& evidence, double now_s,
                              const pipeline::AcceptanceOptions& acceptance, int count);

// A plan for a session not yet recorded: stations at vehicle-to-wall angles spread evenly over
// ±spread, each standing dwell_s after a wait of wait_s, as many as the budget holds.
struct Plan {
  std::vector<StopSpec> stops;
  Prediction predicted;
  double seconds = 0.0;  // the time the plan takes
};
// The fewest stops a plan has.
inline constexpr int kMinPlanStops = 3;
// The time the shortest plan takes: kMinPlanStops of the shortest dwell and wait searched.
double ShortestPlanS(const StopModel& model);
// The plan of the smallest largest-σ-over-tolerance that fits `budget_s`, searched over the
// spread, dwell and wait. stops empty when not even kMinPlanStops stops fit (ShortestPlanS).
Plan BestPlan(const StopModel& model, const pipeline::AcceptanceOptions& acceptance,
              double budget_s);

// The stops of a plan, starting at start_s, as observations.
void AppendPlanObservations(const StopModel& model, const std::vector<StopSpec>& stops,
                            double start_s, std::vector<calib::WallObservation>* observations,
                            std::vector<double>* weights);

}  // namespace wallcal::guide
