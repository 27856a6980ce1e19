// SPDX-License-Identifier: Apache-2.0
// accuracy_bench: accuracy and σ honesty against the Cramér–Rao bound. For each scenario, simulates N sessions (seeds first..
// first+N−1), calibrates each with --method ceres and --method barawid through the public
// pipeline (apps::WriteSimulatedSession, apps::RunCalibration), and compares per axis (x, y,
// yaw): the RMS error, the mean reported σ, RMS(error/σ) and the Cramér–Rao bound of the
// simulator's noise model (bench/crb.h). Prints Markdown tables (docs/results.md) and, with
// --csv, one line per run and method.
//
//   accuracy_bench [--runs N] [--scenario NAME] [--first-seed S] [--csv FILE] [--breakdown]
//                  [--max-crb-obs M] [--max-all-obs M] [--delay-prior S] [--all-min-beams N]
//                  [--options FILE] [--sim FILE] [--crb-only] [--keep] [--with-variants] [--list]
//                  [--help]
//
// Variants ((i), (j): a scenario's session with its drives left out, to show what they add) run
// only when named or with --with-variants; they are not held to the all-data bound.
//
// --crb-only: only the all-data bound per scenario (on --max-all-obs wall lines and on half as
// many), no simulated runs: how the bound and its cost scale with the subsample.
//
// --sim FILE: one scenario simulated from FILE (a configs/simulate/ style config) with
// bench/calibrate_matched.yaml, for experiments.
//
// Two bounds per scenario: over the scans calibrate used in each run (mean over the runs), and
// over ALL the data the session holds (bench/crb.h AllSessionObservations: every logged scan,
// standing and moving, from the truth; the same for every seed, so computed once), with the
// scanner clock offset (flat prior) and the GNSS and heading delays (prior --delay-prior S,
// default 0.05 s) as marginalised unknowns. RMS/CRB and the targets are against the all-data
// bound. Beyond --max-all-obs wall lines (default 2400) an even subsample by time is used, and
// the bound of half as many is printed beside it to show what subsampling costs.
//
// --options FILE: calibrate options for every scenario (default: bench/calibrate_matched.yaml,
// bench/calibrate_matched_moving.yaml for continuous driving, bench/calibrate_matched_standing.yaml
// for (i) and (j), the drives left out); for experiments.
// Not a test: no assertions, no ctest registration. Its numbers go into docs/results.md.

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "pipeline/calibration.h"
#include "calib/wall_geometry.h"
#include "pipeline/config_dirs.h"
#include "calib/pose_samples.h"
#include "outputs/offsets_document.h"
#include "outputs/summary.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"
#include "bench/accuracy_bench_args.h"
#include "bench/crb.h"
#include "bench/crb_site.h"
#include "sim/simulator.h"
#include "io/config/session_reader.h"
#include "solvers/mount_solver.h"
#include "common/angles.h"

#ifndef WALLCAL_SOURCE_DIR
#define WALLCAL_SOURCE_DIR "."
#endif

namespace wallcal::bench {
namespace {

namespace fs = std::filesystem;
// Per method and axis: errors and reported σ of the usable runs.
struct AxisStats {
  std::vector<double> errors, sigmas;
};
struct MethodStats {
  int runs = 0, usable = 0;
  AxisStats axis[3];
  std::map<std::string, int> failures;  // message -> count
  double seconds = 0.0;
  std::vector<double> time_offsets_s, time_offset_sigmas_s;
  std::vector<double> mapped_s;  // where each run put its GNSS epochs (logger − UTC; 0: arrival)
  std::vector<double> heading_delay_errors_s, heading_delay_sigmas_s;  // estimated (determined or not)
  // The moving scans' turning timing dt + δh (what turns in front of a wall need): its error
  // against the truth and its σ from the time block's covariance.
  std::vector<double> turn_timing_errors_s, turn_timing_sigmas_s;
  int heading_delay_determined = 0;
  std::vector<double> gnss_latencies_s, gnss_jitters_s;
  double observations = 0.0;
  // Clutter diagnostics: observations whose line-fit σ was raised by the
  // fit's residual RMS (σ = max(preset σ, RMS), calib/wall_detector.cc) and by how much, and
  // observations beyond the solver's rejection threshold.
  double lines = 0.0, lines_raised = 0.0, raise_factor_sum = 0.0, rejected = 0.0;
  double moving_scans = 0.0, standing_scans = 0.0;
};

// The delays calibrate should find (docs/time-alignment.md): the GGA epochs land on the logger
// clock at the mean GNSS delay L = latency + jitter/2 (the logger clock is the simulator's UTC);
// the scanner offset dt = true − stamped scan time on the clock the fixes were placed on (at the
// fitted L̂: `mapped_s`, 0 when the epochs were not mapped); the heading's delay after it.
struct DelayTruth {
  double gnss_s, scanner_offset_s, heading_delay_s;
};
DelayTruth TrueDelays(const sim::SimulationConfig& config, double mapped_s) {
  const double gnss_s = config.gnss_latency_s + 0.5 * config.gnss_jitter_s;
  return {gnss_s, config.scanner_time_offset_s + mapped_s - config.scanner_latency_s,
          config.heading_latency_s - mapped_s};
}

double Rms(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x * x;
  return std::sqrt(s / v.size());
}
double Mean(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double s = 0.0;
  for (double x : v) s += x;
  return s / v.size();
}

// χ²_ν quantile by Wilson–Hilferty (good to < 1 % for ν ≥ 20).
double ChiSquareQuantile(double nu, double z) {
  const double a = 2.0 / (9.0 * nu);
  return nu * std::pow(1.0 - a + z * std::sqrt(a), 3);
}

std::vector<CrbObservation> CrbObservationsOf(const pipeline::CalibrationResult& result,
                                              const sim::SimulationConfig& config) {
  solvers::Mount truth;
  truth.x_m = config.mount_x_m;
  truth.y_m = config.mount_y_m;
  truth.yaw_rad = config.mount_yaw_rad;
  std::vector<CrbObservation> out;
  for (const calib::WallObservation& o : result.solve.observations) {
    CrbObservation c;
    // pose.stamp_s = logged scan stamp + session time offset (0 in simulated sessions); the
    // logger stamps a scan scanner_time_offset_s early.
    c.t_s = o.pose.stamp_s - config.start_time_s + config.scanner_time_offset_s -
            config.scanner_latency_s;
    c.surveyed_wall = o.wall_index;
    if (o.wall_index >= 0 && o.wall_index < static_cast<int>(result.survey.walls.size())) {
      const calib::WallGeometry& wall = result.survey.walls[o.wall_index];
      c.residual = Eigen::Vector2d(
          o.rho_m - calib::PredictRho(o, wall, truth),
          std::remainder(o.theta_rad - calib::PredictTheta(o, wall, truth), 2.0 * kPi));
      c.has_residual = true;
    }
    out.push_back(c);
  }
  return out;
}

const char* kAxisName[3] = {"x", "y", "yaw"};
// Display units: mm for x, y; degrees for yaw.
double Show(int axis, double value) { return axis < 2 ? value * 1000.0 : value * kRadToDeg; }
const char* Unit(int axis) { return axis < 2 ? "mm" : "deg"; }

void RunScenario(const Scenario& scenario, const Args& args, std::FILE* csv) {
  const sim::SimulationConfig config =
      sim::WithDefaultWalls(sim::ReadSimulationConfig(scenario.sim_file));
  const io::ScannerPreset preset =
      io::LoadScannerPreset(config.scanner_model, pipeline::PresetDirs());
  const double truth[3] = {config.mount_x_m, config.mount_y_m, config.mount_yaw_rad};
  const fs::path root = fs::temp_directory_path() /
                        ("wallcal_bench_" + std::to_string(::getpid()) + "_" + scenario.name);

  // The all-data bound (deterministic: from the truth), and the same on half the wall lines.
  CrbDelays all_delays;
  all_delays.scanner_offset_prior_sigma_s = kFlatDelayPriorS;
  all_delays.gnss_delay_prior_sigma_s = args.delay_prior_s;
  all_delays.heading_delay_prior_sigma_s = args.delay_prior_s;
  const std::vector<CrbObservation> all_obs = AllSessionObservations(config, preset, args.all_min_beams);
  const auto all_t0 = std::chrono::steady_clock::now();
  const CrbResult all_crb =
      ComputeCrb(config, preset, all_obs, kAllSources, all_delays, args.max_all_obs);
  const double all_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - all_t0).count();
  const int half = std::max(3, all_crb.observations_used / 2);
  const CrbResult all_half = ComputeCrb(config, preset, all_obs, kAllSources, all_delays, half);
  if (!all_crb.ok) throw std::runtime_error(scenario.name + ": all-data CRB: " + all_crb.message);
  if (args.crb_only) {
    std::printf("%s: all-data CRB on %d of %d wall lines (%.1f s): x %.2f mm, y %.2f mm, yaw %.4f "
                "deg; on %d: x %.2f mm, y %.2f mm, yaw %.4f deg\n",
                scenario.name.c_str(), all_crb.observations_used, all_crb.observations_given,
                all_seconds, 1000.0 * std::sqrt(all_crb.crb(0, 0)),
                1000.0 * std::sqrt(all_crb.crb(1, 1)), kRadToDeg * std::sqrt(all_crb.crb(2, 2)),
                all_half.observations_used, 1000.0 * std::sqrt(all_half.crb(0, 0)),
                1000.0 * std::sqrt(all_half.crb(1, 1)), kRadToDeg * std::sqrt(all_half.crb(2, 2)));
    if (all_crb.has_delay_bound) {
      std::printf("%s: all-data bound on the timing: scanner clock offset %.2f ms, heading delay "
                  "after the GNSS epochs %.2f ms, their sum %.2f ms\n",
                  scenario.name.c_str(), 1000.0 * all_crb.delay_bound_dt_s,
                  1000.0 * all_crb.delay_bound_dh_s, 1000.0 * all_crb.delay_bound_sum_s);
    }
    if (config.IsThreeDSite()) {  // the site's share: the bound without it, the grade's σ
      const CrbResult level =
          ComputeCrb(config, preset, all_obs, kAllSources & ~kSite, all_delays, args.max_all_obs);
      const Eigen::Matrix2d grade = YardGradeCovariance(config);
      std::printf("%s: without the site's terms x %.2f mm, y %.2f mm, yaw %.4f deg; the yard's "
                  "grade from the antenna heights: sigma %.3f %% east, %.3f %% north%s\n",
                  scenario.name.c_str(), 1000.0 * std::sqrt(level.crb(0, 0)),
                  1000.0 * std::sqrt(level.crb(1, 1)), kRadToDeg * std::sqrt(level.crb(2, 2)),
                  100.0 * std::sqrt(grade(0, 0)), 100.0 * std::sqrt(grade(1, 1)),
                  config.attitude_rate_hz > 0.0 ? " (not used: an attitude stream)" : "");
    }
    return;
  }

  MethodStats stats[2];
  const char* methods[2] = {"ceres", "barawid"};
  CrbDelays offset_unknown;
  offset_unknown.scanner_offset_prior_sigma_s = kFlatDelayPriorS;
  std::vector<Eigen::Matrix3d> crbs, crbs_offset;
  AxisStats oracle[3];
  int crb_failures = 0, crb_subsampled = 0;
  double crb_obs = 0.0;
  const auto t0 = std::chrono::steady_clock::now();
  for (int r = 0; r < args.runs; ++r) {
    const uint64_t seed = static_cast<uint64_t>(args.first_seed + r);
    const fs::path dir = root / ("seed" + std::to_string(seed));
    sim::WriteSimulatedSession(config, seed, dir.string());
    for (int m = 0; m < 2; ++m) {
      pipeline::CalibrateRequest request;
      request.session_path = dir.string();
      request.config_path = args.options.empty() ? scenario.options_file : args.options;
      request.method = m == 1 ? solvers::Method::kBarawid : solvers::Method::kCeres;
      MethodStats& s = stats[m];
      ++s.runs;
      pipeline::CalibrationResult result;
      try {
        result = pipeline::RunCalibration(request);
      } catch (const std::exception& e) {
        ++s.failures[std::string("threw: ") + e.what()];
        continue;
      }
      s.seconds += result.seconds;
      s.observations += static_cast<double>(result.solve.observations.size());
      for (const calib::WallObservation& o : result.solve.observations) {
        s.lines += 1.0;
        if (o.residual_rms_m > preset.range_sigma_m) {
          s.lines_raised += 1.0;
          s.raise_factor_sum += o.residual_rms_m / preset.range_sigma_m;
        }
      }
      s.rejected += result.solve.estimate.observations_rejected;
      s.moving_scans += static_cast<double>(result.finish.coverage.scans_used_moving);
      s.standing_scans += static_cast<double>(result.finish.coverage.scans_used -
                                              result.finish.coverage.scans_used_moving);
      const solvers::MountEstimate& e = result.solve.estimate;
      const double est[3] = {e.mount.x_m, e.mount.y_m, e.mount.yaw_rad};
      double err[3], sig[3];
      for (int a = 0; a < 3; ++a) {
        err[a] = est[a] - truth[a];
        if (a == 2) err[a] = std::remainder(err[a], 2.0 * kPi);
        sig[a] = std::sqrt(std::max(0.0, e.covariance(a, a)));
      }
      if (csv != nullptr) {
        std::fprintf(csv, "%s,%llu,%s,%d,%d,%.6f,%.6f,%.8f,%.6f,%.6f,%.8f,%.6f,%.3f\n",
                     scenario.name.c_str(), static_cast<unsigned long long>(seed), methods[m],
                     e.usable ? 1 : 0, static_cast<int>(result.solve.observations.size()), err[0],
                     err[1], err[2], sig[0], sig[1], sig[2], result.solve.scanner_offset.value_s,
                     result.seconds);
      }
      if (!e.usable) {
        ++s.failures[e.message.substr(0, 160)];
        continue;
      }
      ++s.usable;
      for (int a = 0; a < 3; ++a) {
        s.axis[a].errors.push_back(err[a]);
        s.axis[a].sigmas.push_back(sig[a]);
      }
      const double mapped_s = result.poses.gnss_epochs.status == calib::EpochMappingStatus::kMapped
                                  ? result.poses.gnss_epochs.offset_s
                                  : 0.0;
      if (result.solve.scanner_offset.sigma_s > 0.0) {
        s.mapped_s.push_back(mapped_s);
        s.time_offsets_s.push_back(result.solve.scanner_offset.value_s);
        s.time_offset_sigmas_s.push_back(result.solve.scanner_offset.sigma_s);
      }
      if (result.solve.heading_delay.status != pipeline::DelayStatus::kNotEstimated) {
        s.heading_delay_errors_s.push_back(
            result.solve.heading_delay.value_s - config.heading_latency_s +
            mapped_s);  // its error, as a delay after the true epochs
        s.heading_delay_sigmas_s.push_back(result.solve.heading_delay.sigma_s);
        if (result.solve.heading_delay.status == pipeline::DelayStatus::kDetermined) {
          ++s.heading_delay_determined;
        }
        if (result.solve.scanner_offset.sigma_s > 0.0) {
          const DelayTruth true_delays = TrueDelays(config, mapped_s);
          const Eigen::Matrix2d& tc = result.solve.estimate.time_covariance;
          s.turn_timing_errors_s.push_back(
              result.solve.scanner_offset.value_s + result.solve.heading_delay.value_s -
              true_delays.scanner_offset_s - true_delays.heading_delay_s);
          s.turn_timing_sigmas_s.push_back(
              std::sqrt(std::max(0.0, tc(0, 0) + tc(1, 1) + 2.0 * tc(0, 1))));
        }
      }
      if (result.poses.gnss_epochs.status == calib::EpochMappingStatus::kMapped) {
        s.gnss_latencies_s.push_back(result.poses.gnss_epochs.offset_s);
        s.gnss_jitters_s.push_back(result.poses.gnss_epochs.jitter_s);
      }
      if (m == 0) {
        // The bound for the observations calibrate extracted in this run, at the truth.
        const std::vector<CrbObservation> obs = CrbObservationsOf(result, config);
        const CrbResult crb = ComputeCrb(config, preset, obs, kAllSources, CrbDelays{}, args.max_crb_obs);
        if (!crb.ok) {
          ++crb_failures;
        } else {
          crbs.push_back(crb.crb);
          if (crb.has_oracle) {
            for (int a = 0; a < 3; ++a) oracle[a].errors.push_back(crb.oracle_error[a]);
          }
          crb_obs += crb.observations_used;
          crb_subsampled += crb.subsampled;
          const bool any_moving =
              std::any_of(result.solve.observations.begin(), result.solve.observations.end(),
                          [](const calib::WallObservation& o) { return !o.pose.stationary; });
          if (scenario.moving || any_moving) {
            const CrbResult with_offset =
                ComputeCrb(config, preset, obs, kAllSources, offset_unknown, args.max_crb_obs);
            if (with_offset.ok) crbs_offset.push_back(with_offset.crb);
          }
        }
        if (args.breakdown && r == 0) {
          // The observations at the truth, by kind: a mean far from 0 (against RMS/√n) is a
          // biased wall line, which no estimator can undo.
          std::map<std::pair<int, int>, std::vector<Eigen::Vector2d>> groups;  // (moving, wall)
          for (size_t k = 0; k < obs.size(); ++k) {
            if (!obs[k].has_residual) continue;
            groups[{result.solve.observations[k].pose.stationary ? 0 : 1, obs[k].surveyed_wall}]
                .push_back(obs[k].residual);
          }
          std::printf("\nResiduals at the true mount, %s seed %llu (observed − predicted):\n",
                      scenario.name.c_str(), static_cast<unsigned long long>(seed));
          for (const auto& [key, list] : groups) {
            Eigen::Vector2d mean = Eigen::Vector2d::Zero(), sq = Eigen::Vector2d::Zero();
            for (const auto& v : list) {
              mean += v / static_cast<double>(list.size());
              sq += v.cwiseProduct(v) / static_cast<double>(list.size());
            }
            std::printf("  %-8s wall %d: %4zu lines, rho mean %+.2f mm RMS %.2f mm, theta mean "
                        "%+.4f deg RMS %.4f deg\n",
                        key.first ? "moving" : "standing", key.second, list.size(),
                        1000.0 * mean.x(), 1000.0 * std::sqrt(sq.x()), kRadToDeg * mean.y(),
                        kRadToDeg * std::sqrt(sq.y()));
          }
          std::printf("\nCRB breakdown, %s, seed %llu (%zu observations; sources on top of the "
                      "line fit):\n",
                      scenario.name.c_str(), static_cast<unsigned long long>(seed), obs.size());
          const std::pair<const char*, unsigned> parts[] = {
              {"line fit only", kLineFit},
              {"+ GNSS bias", kLineFit | kGnssBias},
              {"+ GNSS white", kLineFit | kGnssWhite},
              {"+ heading white", kLineFit | kHeadingWhite},
              {"+ heading drift", kLineFit | kHeadingDrift},
              {"+ survey (TS + control RTK)", kLineFit | kSurvey},
              {"all sources", kAllSources},
          };
          for (const auto& [label, mask] : parts) {
            const CrbResult b = ComputeCrb(config, preset, obs, mask, CrbDelays{}, args.max_crb_obs);
            if (!b.ok) {
              std::printf("  %-30s %s\n", label, b.message.c_str());
              continue;
            }
            std::printf("  %-30s x %7.2f mm   y %7.2f mm   yaw %.4f deg\n", label,
                        1000.0 * std::sqrt(b.crb(0, 0)), 1000.0 * std::sqrt(b.crb(1, 1)),
                        kRadToDeg * std::sqrt(b.crb(2, 2)));
          }
        }
      }
    }
    if (!args.keep) {
      std::error_code ignored;
      fs::remove_all(dir, ignored);
    }
    std::fprintf(stderr, "\r%s: %d/%d runs", scenario.name.c_str(), r + 1, args.runs);
  }
  std::fprintf(stderr, "\n");
  if (!args.keep) {
    std::error_code ignored;
    fs::remove_all(root, ignored);
  }
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();

  // CRB: the mean bound variance over the runs (the observation sets differ a little).
  Eigen::Matrix3d crb = Eigen::Matrix3d::Zero(), crb_offset = Eigen::Matrix3d::Zero();
  for (const auto& c : crbs) crb += c / static_cast<double>(crbs.size());
  for (const auto& c : crbs_offset) crb_offset += c / static_cast<double>(crbs_offset.size());

  // Sampling spread of an RMS over n runs if the errors were N(0, bound²): 90 % interval.
  const MethodStats& c = stats[0];
  const MethodStats& b = stats[1];
  const double n = c.usable;
  const double lo = n > 0 ? std::sqrt(ChiSquareQuantile(n, -1.6449) / n) : 0.0;
  const double hi = n > 0 ? std::sqrt(ChiSquareQuantile(n, 1.6449) / n) : 0.0;

  std::printf("\n### %s  (`--scenario %s --runs %d --first-seed %d`)\n\n", scenario.label.c_str(),
              scenario.name.c_str(), args.runs, args.first_seed);
  std::printf("ceres usable %d/%d, barawid usable %d/%d; mean observations per run %.0f "
              "(ceres); CRB from %zu runs (mean %.0f observations%s); %.0f s\n\n",
              c.usable, c.runs, b.usable, b.runs, c.runs ? c.observations / c.runs : 0.0,
              crbs.size(), crbs.empty() ? 0.0 : crb_obs / crbs.size(),
              crb_subsampled ? ", subsampled evenly" : "", elapsed_s);
  std::printf("All-data CRB: %d of the %d wall lines in the scans the session holds%s (%.1f s to "
              "compute); on about half as many (%d): x %.2f mm, y %.2f mm, yaw %.4f deg; on %d: "
              "x %.2f mm, y %.2f mm, yaw %.4f deg.\n\n",
              all_crb.observations_used, all_crb.observations_given,
              all_crb.subsampled ? ", subsampled evenly by scan" : "", all_seconds,
              all_half.observations_used, 1000.0 * std::sqrt(all_half.crb(0, 0)),
              1000.0 * std::sqrt(all_half.crb(1, 1)), kRadToDeg * std::sqrt(all_half.crb(2, 2)),
              all_crb.observations_used, 1000.0 * std::sqrt(all_crb.crb(0, 0)),
              1000.0 * std::sqrt(all_crb.crb(1, 1)), kRadToDeg * std::sqrt(all_crb.crb(2, 2)));
  std::printf("| axis | RMS err ceres | mean σ ceres | RMS(err/σ) | CRB used scans | CRB all "
              "data | RMS/CRB all | RMS err barawid | barawid/CRB all | RMS ≤ 1.1 CRB all | "
              "0.8 ≤ RMS(err/σ) ≤ 1.25 |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|\n");
  for (int a = 0; a < 3; ++a) {
    const double rms = Rms(c.axis[a].errors);
    const double mean_sigma = Mean(c.axis[a].sigmas);
    std::vector<double> z;
    for (size_t i = 0; i < c.axis[a].errors.size(); ++i) {
      if (c.axis[a].sigmas[i] > 0.0) z.push_back(c.axis[a].errors[i] / c.axis[a].sigmas[i]);
    }
    const double rms_z = Rms(z);
    // The used-scans bound: with the scanner clock offset unknown when moving scans are used.
    const double used_bound =
        std::sqrt(crbs_offset.empty() ? crb(a, a) : crb_offset(a, a));
    const double bound = std::sqrt(all_crb.crb(a, a));
    const double rms_b = Rms(b.axis[a].errors);
    const int prec = a < 2 ? 2 : 4;
    std::printf("| %s (%s) | %.*f | %.*f | %.2f | %.*f | %.*f | %.2f | %.*f | %.2f | %s | %s |\n",
                kAxisName[a], Unit(a), prec, Show(a, rms), prec, Show(a, mean_sigma), rms_z, prec,
                Show(a, used_bound), prec, Show(a, bound), rms / bound, prec, Show(a, rms_b), rms_b / bound,
                rms <= 1.1 * bound ? "met" : "NOT met",
                (rms_z >= 0.8 && rms_z <= 1.25) ? "met" : "NOT met");
  }
  if (!oracle[0].errors.empty()) {
    std::printf("\nCheck of the bound: the linear GLS estimate with the bound's own C from the "
                "same observations (truth known): RMS x %.2f mm, y %.2f mm, yaw %.4f deg over "
                "%zu runs.\n",
                1000.0 * Rms(oracle[0].errors), 1000.0 * Rms(oracle[1].errors),
                kRadToDeg * Rms(oracle[2].errors), oracle[0].errors.size());
    // Both are the errors of the same runs: the seeds' luck (the survey tie's draw, the GNSS
    // error's) is common to the two, so this ratio is about 1 for an efficient estimator
    // whatever the seeds, where RMS/CRB scatters over 0.83-1.16 with 50 runs.
    std::printf("ceres RMS over the GLS check's on the same runs: x %.2f, y %.2f, yaw %.2f.\n",
                Rms(c.axis[0].errors) / Rms(oracle[0].errors),
                Rms(c.axis[1].errors) / Rms(oracle[1].errors),
                Rms(c.axis[2].errors) / Rms(oracle[2].errors));
    // Means: a bias shows here (its own 1σ is RMS/√runs).
    std::printf("Mean error: ceres x %+.2f mm, y %+.2f mm, yaw %+.4f deg; barawid x %+.2f mm, "
                "y %+.2f mm, yaw %+.4f deg; the GLS check x %+.2f mm, y %+.2f mm, yaw %+.4f deg.\n",
                1000.0 * Mean(c.axis[0].errors), 1000.0 * Mean(c.axis[1].errors),
                kRadToDeg * Mean(c.axis[2].errors), 1000.0 * Mean(stats[1].axis[0].errors),
                1000.0 * Mean(stats[1].axis[1].errors), kRadToDeg * Mean(stats[1].axis[2].errors),
                1000.0 * Mean(oracle[0].errors), 1000.0 * Mean(oracle[1].errors),
                kRadToDeg * Mean(oracle[2].errors));
  }
  std::printf("\n90 %% sampling interval of RMS/CRB for an efficient estimator over %d runs: "
              "%.2f–%.2f (same for RMS(err/σ) with an exact σ).\n",
              c.usable, lo, hi);
  if (!crbs_offset.empty()) {
    std::printf("CRB with the scanner clock offset estimated too: x %.2f mm, y %.2f mm, yaw "
                "%.4f deg.\n",
                1000.0 * std::sqrt(crb_offset(0, 0)), 1000.0 * std::sqrt(crb_offset(1, 1)),
                kRadToDeg * std::sqrt(crb_offset(2, 2)));
  }
  const DelayTruth delays = TrueDelays(config, 0.0);
  if (!c.time_offsets_s.empty()) {
    // The scanner stamps its scans scanner_time_offset_s early and scanner_latency_s late, on a
    // clock the GNSS epochs reach L late: dt = offset + L − latency is the offset to find.
    std::vector<double> errors, normalised;
    for (size_t k = 0; k < c.time_offsets_s.size(); ++k) {
      errors.push_back(c.time_offsets_s[k] - TrueDelays(config, c.mapped_s[k]).scanner_offset_s);
      normalised.push_back(errors.back() / c.time_offset_sigmas_s[k]);
    }
    std::printf("ceres scanner clock offset (truth %.1f ms + the fitted GNSS delay): mean %.2f ms, RMS error %.2f ms, "
                "mean σ %.2f ms, RMS(error/σ) %.2f over %zu runs; all-data bound %.2f ms.\n",
                1000.0 * delays.scanner_offset_s, 1000.0 * Mean(c.time_offsets_s),
                1000.0 * Rms(errors), 1000.0 * Mean(c.time_offset_sigmas_s), Rms(normalised),
                c.time_offsets_s.size(), 1000.0 * all_crb.delay_bound_dt_s);
  }
  if (!c.heading_delay_errors_s.empty()) {
    std::vector<double> errors, normalised;
    for (size_t k = 0; k < c.heading_delay_errors_s.size(); ++k) {
      errors.push_back(c.heading_delay_errors_s[k]);
      normalised.push_back(errors.back() / c.heading_delay_sigmas_s[k]);
    }
    std::printf("ceres heading delay after the GNSS epochs (truth %.1f ms − the fitted GNSS delay "
                "%.1f ms): mean error %.2f ms, RMS error %.2f ms, mean σ %.2f ms, RMS(error/σ) %.2f over %zu runs (determined in "
                "%d); all-data bound %.2f ms.\n",
                1000.0 * config.heading_latency_s, 1000.0 * delays.gnss_s,
                1000.0 * Mean(c.heading_delay_errors_s),
                1000.0 * Rms(errors), 1000.0 * Mean(c.heading_delay_sigmas_s), Rms(normalised),
                c.heading_delay_errors_s.size(), c.heading_delay_determined,
                1000.0 * all_crb.delay_bound_dh_s);
  }
  if (!c.turn_timing_errors_s.empty()) {
    std::vector<double> normalised;
    for (size_t k = 0; k < c.turn_timing_errors_s.size(); ++k) {
      normalised.push_back(c.turn_timing_errors_s[k] / c.turn_timing_sigmas_s[k]);
    }
    std::printf("ceres clock offset + heading delay (what turns need): mean error %.2f ms, RMS "
                "error %.2f ms, mean σ %.2f ms, RMS(error/σ) %.2f over %zu runs; all-data bound "
                "%.2f ms.\n",
                1000.0 * Mean(c.turn_timing_errors_s), 1000.0 * Rms(c.turn_timing_errors_s),
                1000.0 * Mean(c.turn_timing_sigmas_s), Rms(normalised),
                c.turn_timing_errors_s.size(), 1000.0 * all_crb.delay_bound_sum_s);
  }
  if (!c.gnss_latencies_s.empty()) {
    std::vector<double> errors;
    for (double l : c.gnss_latencies_s) errors.push_back(l - delays.gnss_s);
    std::printf("GNSS epoch mapping (truth latency + mean jitter %.1f ms): mean %.2f ms, RMS "
                "error %.2f ms, mean jitter σ %.2f ms over %zu runs.\n",
                1000.0 * delays.gnss_s, 1000.0 * Mean(c.gnss_latencies_s), 1000.0 * Rms(errors),
                1000.0 * Mean(c.gnss_jitters_s), c.gnss_latencies_s.size());
  }
  for (int m = 0; m < 2; ++m) {
    for (const auto& [message, count] : stats[m].failures) {
      std::printf("%s not usable in %d run(s): %s\n", methods[m], count, message.c_str());
    }
  }
  if (c.lines > 0.0) {
    std::printf("ceres per run: %.0f standing and %.0f moving scans used; %.1f %% of the wall "
                "lines had their fit σ raised by the fit's RMS (mean factor %.2f); %.2f "
                "observations rejected (whitened residual beyond the threshold).\n",
                c.standing_scans / c.runs, c.moving_scans / c.runs, 100.0 * c.lines_raised / c.lines,
                c.lines_raised > 0.0 ? c.raise_factor_sum / c.lines_raised : 1.0,
                c.rejected / c.runs);
  }
  if (crb_failures > 0) std::printf("CRB failed in %d run(s)\n", crb_failures);
  std::printf("mean calibrate time: ceres %.2f s, barawid %.2f s\n",
              c.runs ? c.seconds / c.runs : 0.0, b.runs ? b.seconds / b.runs : 0.0);
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
    std::fprintf(csv, "scenario,seed,method,usable,observations,err_x_m,err_y_m,err_yaw_rad,"
                      "sigma_x_m,sigma_y_m,sigma_yaw_rad,time_offset_s,seconds\n");
  }
  bool any = false;
  try {
    if (!args.sim.empty()) {
      any = true;
      const Scenario custom{"custom", "custom: " + args.sim, args.sim,
                            std::string(WALLCAL_SOURCE_DIR) + "/bench/calibrate_matched.yaml",
                            false};
      RunScenario(custom, args, csv);
    }
    for (const Scenario& s : Scenarios()) {
      if (!args.sim.empty()) break;
      if (!args.scenario.empty() && args.scenario != s.name) continue;
      if (args.scenario.empty() && s.variant && !args.variants) continue;
      any = true;
      RunScenario(s, args, csv);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "accuracy_bench: %s\n", e.what());
    if (csv != nullptr) std::fclose(csv);
    return 1;
  }
  if (csv != nullptr) std::fclose(csv);
  if (!any) Usage("unknown scenario '" + args.scenario + "' (see --list)");
  return 0;
}
