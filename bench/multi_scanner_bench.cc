// SPDX-License-Identifier: Apache-2.0
// multi_scanner_bench: two scanners on one vehicle (session.yaml scanners:). For each scenario,
// simulates N two-scanner sessions (seeds first..first+N−1), calibrates each with
// pipeline::RunSeveralScanners, and reports per scanner and axis the RMS error of the joint
// estimate, the mean reported σ, RMS(error/σ) and the joint Cramér–Rao bound over all the data
// (bench/crb.h ComputeJointCrb: the vehicle's errors common to both scanners, one mount and
// one clock offset per scanner); the same for the relative transform (the pose of the second
// scanner in the first's frame), beside the RMS error of differencing the two scanners' own
// one-scanner calibrations of the same data. Prints Markdown tables (docs/results.md).
//
//   multi_scanner_bench [--runs N] [--scenario NAME] [--first-seed S] [--max-all-obs M]
//                       [--csv FILE] [--options CALIBRATE_YAML] [--oracle]
//                       [--sim SIMULATE_YAML]
//
// --sim runs one session config with `scanners:` of its own (held-out settings) instead of
// the four scenarios, with --options or bench/calibrate_matched.yaml.
//
// --options replaces the scenario's calibrate options (bench/calibrate_matched*.yaml), for
// trying one option against the same sessions.
// --oracle: per run, also the first scanner's mount from the linear GLS with the true
// covariance over the wall lines calibrate extracted (bench/crb.h CrbResult::oracle_error),
// whose RMS over the runs tells the draws' own spread from the estimator's: the calibrate RMS
// over the oracle's RMS is the estimator's loss on those very sessions.
//
// Not a test: no assertions, no ctest registration.

#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench/crb.h"
#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "io/config/session_reader.h"
#include "pipeline/config_dirs.h"
#include "pipeline/multi_scanner.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"

namespace wallcal::bench {
namespace {

namespace fs = std::filesystem;

struct Scenario {
  std::string name, label, sim_file, options_file;
};

std::vector<Scenario> Scenarios() {
  const std::string src = WALLCAL_SOURCE_DIR;
  const std::string sim = src + "/configs/simulate/bench_two_scanners_";
  // The two-scanner sessions jitter their scan stamps by U(0, 0.5 ms) and nothing else: the
  // matched model's moving timing noise is that jitter's σ.
  const std::string matched = src + "/bench/calibrate_matched_scan_jitter.yaml";
  const std::string moving = src + "/bench/calibrate_matched_moving_scan_jitter.yaml";
  return {{"stopgo", "LMS 291 stop-and-go", sim + "stopgo.yaml", matched},
          {"continuous", "LMS 291 continuous driving", sim + "continuous.yaml", moving},
          {"urg04lx", "URG-04LX", sim + "urg04lx.yaml", matched},
          {"clutter", "LMS 291 among clutter", sim + "clutter.yaml", matched}};
}

struct Args {
  int runs = 50;
  int first_seed = 1;
  int max_all_obs = 2400;
  std::string scenario, csv;
  std::string options;  // calibrate options instead of the scenario's own
  bool oracle = false;
  std::string sim;  // a simulation config of its own instead of the four scenarios
};

[[noreturn]] void Usage(const std::string& message) {
  std::fprintf(stderr,
               "multi_scanner_bench: %s\nusage: multi_scanner_bench [--runs N] [--scenario "
               "stopgo|continuous|urg04lx|clutter] [--first-seed S] [--max-all-obs M] [--csv "
               "FILE] [--options CALIBRATE_YAML] [--oracle] [--sim SIMULATE_YAML]\n",
               message.c_str());
  std::exit(2);
}

Args ParseArgs(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    const auto value = [&]() -> std::string {
      if (i + 1 >= argc) Usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--runs") {
      args.runs = std::atoi(value().c_str());
    } else if (a == "--first-seed") {
      args.first_seed = std::atoi(value().c_str());
    } else if (a == "--max-all-obs") {
      args.max_all_obs = std::atoi(value().c_str());
    } else if (a == "--scenario") {
      args.scenario = value();
    } else if (a == "--csv") {
      args.csv = value();
    } else if (a == "--options") {
      args.options = value();
    } else if (a == "--oracle") {
      args.oracle = true;
    } else if (a == "--sim") {
      args.sim = value();
    } else {
      Usage("unknown argument " + a);
    }
  }
  if (args.runs < 1) Usage("--runs needs a number >= 1");
  return args;
}

double Axis(const solvers::Mount& m, int axis) {
  return axis == 0 ? m.x_m : axis == 1 ? m.y_m : m.yaw_rad;
}
double Show(int axis, double value) { return axis < 2 ? value * 1000.0 : value * kRadToDeg; }
const char* kAxisName[3] = {"x", "y", "yaw"};
const char* Unit(int axis) { return axis < 2 ? "mm" : "deg"; }

struct AxisStats {
  double error2 = 0.0, sigma = 0.0, z2 = 0.0, own_error2 = 0.0, data_sigma = 0.0;
  int n = 0;
  // sigma_value: the reported σ; data_sigma_value: the same without the units' range models.
  void Add(double error, double sigma_value, double data_sigma_value = 0.0) {
    error2 += error * error;
    sigma += sigma_value;
    data_sigma += data_sigma_value;
    z2 += sigma_value > 0.0 ? error * error / (sigma_value * sigma_value) : 0.0;
    ++n;
  }
  double Rms() const { return n ? std::sqrt(error2 / n) : 0.0; }
  double MeanSigma() const { return n ? sigma / n : 0.0; }
  double MeanDataSigma() const { return n ? data_sigma / n : 0.0; }
  double RmsZ() const { return n ? std::sqrt(z2 / n) : 0.0; }
  double OwnRms() const { return n ? std::sqrt(own_error2 / n) : 0.0; }
};

// Every wall line the scanners' runs extracted, at its true time, with its residual at the
// true mount (observed − predicted from the measured pose and surveyed wall).
std::vector<CrbObservation> ObservationsAtTruth(const pipeline::SeveralScannersResult& result,
                                                const std::vector<sim::SimulationConfig>& own,
                                                const std::vector<solvers::Mount>& truth) {
  std::vector<CrbObservation> out;
  for (size_t k = 0; k < result.scanners.size(); ++k) {
    const pipeline::CalibrationResult& run = result.scanners[k].own;
    for (const calib::WallObservation& o : run.solve.observations) {
      if (o.wall_index < 0 || o.wall_index >= static_cast<int>(run.survey.walls.size())) continue;
      CrbObservation c;
      // The logger stamps a scan its latency (and the session's clock offset) after it was taken.
      c.t_s = o.pose.stamp_s - own[k].start_time_s + own[k].scanner_time_offset_s -
              own[k].scanner_latency_s;
      c.surveyed_wall = o.wall_index;
      c.scanner = static_cast<int>(k);
      const calib::WallGeometry& wall = run.survey.walls[o.wall_index];
      c.residual = Eigen::Vector2d(
          o.rho_m - calib::PredictRho(o, wall, truth[k]),
          std::remainder(o.theta_rad - calib::PredictTheta(o, wall, truth[k]), 2.0 * kPi));
      c.has_residual = true;
      out.push_back(c);
    }
  }
  return out;
}

void RunScenario(const Scenario& scenario, const Args& args, std::FILE* csv) {
  const sim::SimulationConfig config =
      sim::WithDefaultWalls(sim::ReadSimulationConfig(scenario.sim_file));
  const io::ScannerPreset preset =
      io::LoadScannerPreset(config.scanner_model, pipeline::PresetDirs());
  const size_t scanners = config.scanners.size();
  std::vector<sim::SimulationConfig> own;
  std::vector<solvers::Mount> truth;
  for (size_t k = 0; k < scanners; ++k) {
    own.push_back(sim::ForScanner(config, k));
    truth.push_back({own.back().mount_x_m, own.back().mount_y_m, own.back().mount_yaw_rad});
  }

  // The joint all-data bound: every scan of every scanner, a flat prior on each scanner's clock
  // offset, the GNSS and heading delays at 0.05 s (as accuracy_bench).
  std::vector<CrbObservation> all_obs;
  for (size_t k = 0; k < scanners; ++k) {
    for (CrbObservation o : AllSessionObservations(own[k], preset, 2)) {
      o.scanner = static_cast<int>(k);
      all_obs.push_back(o);
    }
  }
  CrbDelays delays;
  delays.scanner_offset_prior_sigma_s = kFlatDelayPriorS;
  delays.gnss_delay_prior_sigma_s = 0.05;
  delays.heading_delay_prior_sigma_s = 0.05;
  // Each unit's own range model, when the simulation draws one per scanner.
  const unsigned sources = kAllSources | (config.draw_unit_range_models ? kUnitRange : 0u);
  const CrbResult crb = ComputeJointCrb(own, preset, all_obs, sources, delays, args.max_all_obs);
  if (!crb.ok) {
    std::fprintf(stderr, "%s: joint CRB: %s\n", scenario.name.c_str(), crb.message.c_str());
    return;
  }
  // The relative transform's bound: its Jacobian at the truth through the joint bound.
  const solvers::RelativeMount relative_truth = solvers::RelativeMountOf(
      truth[0], truth[1], Eigen::Matrix<double, 6, 6>(crb.joint_crb.topLeftCorner(6, 6)));
  // The same through the bound an estimator that carries the units' terms in its covariance
  // reaches (CrbResult::joint_consider); the plain bound without them.
  const bool has_consider = crb.joint_consider.rows() >= 6;
  const Eigen::MatrixXd& consider = has_consider ? crb.joint_consider : crb.joint_crb;
  const Eigen::Matrix3d relative_consider =
      solvers::RelativeMountOf(truth[0], truth[1],
                               Eigen::Matrix<double, 6, 6>(consider.topLeftCorner(6, 6)))
          .covariance;

  std::vector<AxisStats> mount_stats(3 * scanners);
  AxisStats relative_stats[3];
  AxisStats oracle_stats[3];
  AxisStats oracle_relative_stats[3];
  int failures = 0;
  double seconds = 0.0;
  const fs::path root = fs::temp_directory_path() /
                        ("wallcal_multibench_" + std::to_string(::getpid()) + "_" + scenario.name);
  for (int r = 0; r < args.runs; ++r) {
    const uint64_t seed = static_cast<uint64_t>(args.first_seed + r);
    const fs::path dir = root / ("seed" + std::to_string(seed));
    sim::WriteSimulatedSession(config, seed, dir.string());
    pipeline::CalibrateRequest request;
    request.session_path = dir.string();
    request.config_path = args.options.empty() ? scenario.options_file : args.options;
    pipeline::SeveralScannersResult result;
    try {
      result = pipeline::RunSeveralScanners(request, false);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s seed %llu: %s\n", scenario.name.c_str(),
                   static_cast<unsigned long long>(seed), e.what());
      ++failures;
      continue;
    }
    std::error_code ignored;
    fs::remove_all(dir, ignored);
    if (result.outcome != pipeline::SeveralOutcome::kAll) {
      std::fprintf(stderr, "%s seed %llu: %s\n", scenario.name.c_str(),
                   static_cast<unsigned long long>(seed), result.message.c_str());
      ++failures;
      continue;
    }
    seconds += result.seconds;
    if (args.oracle) {
      const CrbResult at_truth =
          ComputeJointCrb(own, preset, ObservationsAtTruth(result, own, truth), sources,
                          delays, args.max_all_obs);
      if (at_truth.has_oracle) {
        for (int axis = 0; axis < 3; ++axis) oracle_stats[axis].Add(at_truth.oracle_error[axis], 1.0);
        // The relative transform of the oracle's two mounts.
        const Eigen::VectorXd& e = at_truth.oracle_joint_error;
        const auto moved = [&e](const solvers::Mount& m, int k) {
          return solvers::Mount{m.x_m + e[3 * k], m.y_m + e[3 * k + 1], m.yaw_rad + e[3 * k + 2]};
        };
        const solvers::Mount oracle_relative =
            solvers::RelativeMountOf(moved(truth[0], 0), moved(truth[1], 1),
                                     Eigen::Matrix<double, 6, 6>::Zero())
                .from_T_to;
        for (int axis = 0; axis < 3; ++axis) {
          oracle_relative_stats[axis].Add(
              Axis(oracle_relative, axis) - Axis(relative_truth.from_T_to, axis), 1.0);
        }
      }
    }
    for (size_t k = 0; k < scanners; ++k) {
      const pipeline::JointScannerResult& joint = *result.scanners[k].joint;
      for (int axis = 0; axis < 3; ++axis) {
        const double error = axis == 2 ? WrapAngle(Axis(joint.mount, axis) - Axis(truth[k], axis))
                                       : Axis(joint.mount, axis) - Axis(truth[k], axis);
        mount_stats[3 * k + axis].Add(
            error, std::sqrt(joint.covariance(axis, axis)),
            std::sqrt(joint.covariance(axis, axis) - joint.range_model_covariance(axis, axis)));
        const double own_error =
            Axis(result.scanners[k].own.solve.estimate.mount, axis) - Axis(truth[k], axis);
        mount_stats[3 * k + axis].own_error2 += own_error * own_error;
      }
    }
    const solvers::RelativeMount& rel = result.relative.front().mount;
    const solvers::RelativeMount differenced = solvers::RelativeMountOf(
        result.scanners[0].own.solve.estimate.mount, result.scanners[1].own.solve.estimate.mount,
        Eigen::Matrix<double, 6, 6>::Zero());
    for (int axis = 0; axis < 3; ++axis) {
      const double error = Axis(rel.from_T_to, axis) - Axis(relative_truth.from_T_to, axis);
      const double own_error =
          Axis(differenced.from_T_to, axis) - Axis(relative_truth.from_T_to, axis);
      relative_stats[axis].Add(error, std::sqrt(rel.covariance(axis, axis)),
                               std::sqrt(rel.covariance(axis, axis) -
                                         result.relative.front().range_model_covariance(axis, axis)));
      relative_stats[axis].own_error2 += own_error * own_error;
    }
    if (csv != nullptr) {
      std::fprintf(csv, "%s,%llu", scenario.name.c_str(), static_cast<unsigned long long>(seed));
      for (size_t k = 0; k < scanners; ++k) {
        const pipeline::JointScannerResult& joint = *result.scanners[k].joint;
        for (int axis = 0; axis < 3; ++axis) {
          std::fprintf(csv, ",%.9g,%.9g", Axis(joint.mount, axis) - Axis(truth[k], axis),
                       std::sqrt(joint.covariance(axis, axis)));
        }
      }
      for (int axis = 0; axis < 3; ++axis) {
        std::fprintf(csv, ",%.9g,%.9g",
                     Axis(rel.from_T_to, axis) - Axis(relative_truth.from_T_to, axis),
                     std::sqrt(rel.covariance(axis, axis)));
      }
      std::fprintf(csv, "\n");
    }
  }

  const int runs = mount_stats[0].n;
  std::printf("\n### %s (%s), %d runs (%d failed), joint CRB on %d of %d wall lines\n\n",
              scenario.name.c_str(), scenario.label.c_str(), runs, failures,
              crb.observations_used, crb.observations_given);
  std::printf("| what | axis | RMS error | mean σ | mean σ without unit terms | RMS(error/σ) | CRB | "
              "RMS/CRB | bound, units carried | own-run RMS |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (size_t k = 0; k < scanners; ++k) {
    for (int axis = 0; axis < 3; ++axis) {
      const AxisStats& s = mount_stats[3 * k + axis];
      const double bound = std::sqrt(crb.joint_crb(3 * k + axis, 3 * k + axis));
      const double carried = std::sqrt(consider(3 * k + axis, 3 * k + axis));
      std::printf("| %s | %s | %.3f %s | %.3f | %.3f | %.2f | %.3f | %.2f | %.3f | %.3f |\n",
                  config.scanners[k].id.c_str(), kAxisName[axis], Show(axis, s.Rms()), Unit(axis),
                  Show(axis, s.MeanSigma()), Show(axis, s.MeanDataSigma()), s.RmsZ(),
                  Show(axis, bound), s.Rms() / bound, Show(axis, carried), Show(axis, s.OwnRms()));
    }
  }
  // The relative yaw in millidegrees (its errors are a few of them).
  const auto show_relative = [](int axis, double value) {
    return axis < 2 ? Show(axis, value) : 1000.0 * Show(axis, value);
  };
  for (int axis = 0; axis < 3; ++axis) {
    const AxisStats& s = relative_stats[axis];
    const double bound = std::sqrt(relative_truth.covariance(axis, axis));
    const double carried = std::sqrt(relative_consider(axis, axis));
    std::printf("| relative | %s | %.3f %s | %.3f | %.3f | %.2f | %.3f | %.2f | %.3f | %.3f "
                "(differenced) |\n",
                kAxisName[axis], show_relative(axis, s.Rms()), axis < 2 ? "mm" : "mdeg",
                show_relative(axis, s.MeanSigma()), show_relative(axis, s.MeanDataSigma()),
                s.RmsZ(), show_relative(axis, bound), s.Rms() / bound,
                show_relative(axis, carried), show_relative(axis, s.OwnRms()));
  }
  if (oracle_stats[0].n > 0) {
    std::printf("\n%s oracle (GLS with the true covariance, %d runs): RMS x %.3f mm, y %.3f mm, "
                "yaw %.4f deg; calibrate RMS / oracle RMS: x %.2f, y %.2f, yaw %.2f; oracle RMS "
                "/ CRB: x %.2f, y %.2f, yaw %.2f\n",
                config.scanners[0].id.c_str(), oracle_stats[0].n, Show(0, oracle_stats[0].Rms()),
                Show(1, oracle_stats[1].Rms()), Show(2, oracle_stats[2].Rms()),
                mount_stats[0].Rms() / oracle_stats[0].Rms(),
                mount_stats[1].Rms() / oracle_stats[1].Rms(),
                mount_stats[2].Rms() / oracle_stats[2].Rms(),
                oracle_stats[0].Rms() / std::sqrt(crb.joint_crb(0, 0)),
                oracle_stats[1].Rms() / std::sqrt(crb.joint_crb(1, 1)),
                oracle_stats[2].Rms() / std::sqrt(crb.joint_crb(2, 2)));
  }
  if (oracle_relative_stats[0].n > 0) {
    std::printf("relative transform's oracle: RMS x %.3f mm, y %.3f mm, yaw %.3f mdeg; calibrate "
                "RMS / oracle RMS: x %.2f, y %.2f, yaw %.2f\n",
                Show(0, oracle_relative_stats[0].Rms()), Show(1, oracle_relative_stats[1].Rms()),
                1000.0 * Show(2, oracle_relative_stats[2].Rms()),
                relative_stats[0].Rms() / oracle_relative_stats[0].Rms(),
                relative_stats[1].Rms() / oracle_relative_stats[1].Rms(),
                relative_stats[2].Rms() / oracle_relative_stats[2].Rms());
  }
  std::printf("\nmean run time (both scanners and the joint adjustment): %.2f s\n",
              runs ? seconds / runs : 0.0);
  std::fflush(stdout);
}

}  // namespace
}  // namespace wallcal::bench

int main(int argc, char** argv) {
  using namespace wallcal::bench;
  const Args args = ParseArgs(argc, argv);
  std::FILE* csv = nullptr;
  if (!args.csv.empty()) {
    csv = std::fopen(args.csv.c_str(), "w");
    if (csv == nullptr) Usage("cannot write " + args.csv);
    std::fprintf(csv, "scenario,seed,a_err_x,a_sigma_x,a_err_y,a_sigma_y,a_err_yaw,a_sigma_yaw,"
                      "b_err_x,b_sigma_x,b_err_y,b_sigma_y,b_err_yaw,b_sigma_yaw,rel_err_x,"
                      "rel_sigma_x,rel_err_y,rel_sigma_y,rel_err_yaw,rel_sigma_yaw\n");
  }
  bool any = false;
  if (!args.sim.empty()) {
    const std::string matched = std::string(WALLCAL_SOURCE_DIR) + "/bench/calibrate_matched.yaml";
    const Scenario own{fs::path(args.sim).stem().string(), args.sim, args.sim, matched};
    try {
      RunScenario(own, args, csv);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "multi_scanner_bench: %s: %s\n", args.sim.c_str(), e.what());
    }
    if (csv != nullptr) std::fclose(csv);
    return 0;
  }
  for (const Scenario& s : Scenarios()) {
    if (!args.scenario.empty() && args.scenario != s.name) continue;
    any = true;
    try {
      RunScenario(s, args, csv);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "multi_scanner_bench: %s: %s\n", s.name.c_str(), e.what());
    }
  }
  if (csv != nullptr) std::fclose(csv);
  if (!any) Usage("unknown scenario '" + args.scenario + "'");
  return 0;
}
