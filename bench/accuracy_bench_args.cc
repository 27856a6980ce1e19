// SPDX-License-Identifier: Apache-2.0
#include "bench/accuracy_bench_args.h"

#include <cstdio>
#include <cstdlib>

#ifndef WALLCAL_SOURCE_DIR
#define WALLCAL_SOURCE_DIR "."
#endif

namespace wallcal::bench {
namespace {
constexpr const char* kUsage =
    "usage: accuracy_bench [--runs N] [--scenario NAME] [--first-seed S] [--csv FILE]\n"
    "                      [--breakdown] [--max-crb-obs M] [--max-all-obs M] [--delay-prior S]\n"
    "                      [--all-min-beams N] [--options FILE] [--sim FILE] [--crb-only]\n"
    "                      [--keep] [--with-variants] [--list] [--help]\n";

constexpr const char* kHelp =
    "Simulates sessions of each benchmark scenario (configs/simulate/bench_*.yaml), calibrates\n"
    "them with --method ceres and --method barawid, and compares the RMS error with the reported\n"
    "sigma and with the Cramer-Rao bound over all the data each session holds\n"
    "(docs/results.md explains every line of the output).\n"
    "\n"
    "  --runs N            sessions per scenario, seeds S..S+N-1 (default 50)\n"
    "  --first-seed S      the first seed (default 1)\n"
    "  --scenario NAME     one scenario (names: --list); default every scenario but the variants\n"
    "  --with-variants     also the variants (i), (j): standing scans only\n"
    "  --csv FILE          one row per run and method: usable, observations, errors and sigmas\n"
    "                      (m, rad), the scanner clock offset (s), seconds\n"
    "  --breakdown         the bound's breakdown by noise source\n"
    "  --max-crb-obs M     the bound over the scans calibrate used: at most M observations a run,\n"
    "                      an even subsample beyond (default 1600)\n"
    "  --max-all-obs M     the all-data bound: at most M scans' wall lines a run (default 2400)\n"
    "  --all-min-beams N   a wall line counts in the all-data bound from N beams (default 2)\n"
    "  --delay-prior S     the all-data bound's prior sigma on the GNSS and heading delays,\n"
    "                      seconds (default 0.05; the scanner offset's is flat)\n"
    "  --options FILE      calibrate options instead of the scenario's matched file\n"
    "  --sim FILE          any simulate config instead of the scenarios\n"
    "  --crb-only          the bounds alone, no calibration\n"
    "  --keep              keep the simulated sessions (in "
    "$TMPDIR/wallcal_bench_<pid>_<scenario>)\n"
    "  --list              the scenarios, their labels and files\n";
}  // namespace

[[noreturn]] void Usage(const std::string& why) {
  std::fprintf(stderr, "accuracy_bench: %s\n%s", why.c_str(), kUsage);
  std::exit(2);
}

std::vector<Scenario> Scenarios() {
  const std::string src = WALLCAL_SOURCE_DIR;
  const std::string sim = src + "/configs/simulate/";
  const std::string matched = src + "/bench/calibrate_matched.yaml";
  const std::string moving = src + "/bench/calibrate_matched_moving.yaml";
  const std::string standing = src + "/bench/calibrate_matched_standing.yaml";
  return {
      {"lms291_stopgo", "(a) LMS 291 stop-and-go", sim + "bench_lms291_stopgo.yaml", matched,
       false},
      {"lms291_continuous", "(b) LMS 291 continuous driving", sim + "bench_lms291_continuous.yaml",
       moving, true},
      {"urg04lx", "(c) URG-04LX", sim + "bench_urg04lx.yaml", matched, false},
      {"high_latitude", "(d) convergence 2.7 deg", sim + "bench_lms291_high_latitude.yaml", matched,
       false},
      {"clutter", "(e) clutter", sim + "bench_lms291_clutter.yaml", matched, false},
      {"two_walls", "(f) second perpendicular surveyed wall", sim + "bench_lms291_two_walls.yaml",
       matched, false},
      {"continuous_clock", "(g) (b) with the scanner clock 150 ms behind",
       sim + "bench_lms291_continuous_clock.yaml", moving, true},
      {"stopgo_moving_clock", "(h) (a) with moving scans and the scanner clock 150 ms behind",
       sim + "bench_lms291_stopgo_moving_clock.yaml", moving, true},
      {"stopgo_standing", "(i) (a) with standing scans only (the drives left out)",
       sim + "bench_lms291_stopgo.yaml", standing, false, true},
      {"two_walls_standing", "(j) (f) with standing scans only (the drives left out)",
       sim + "bench_lms291_two_walls.yaml", standing, false, true},
      {"delays_stopgo",
       "(d1) stop-and-go (5 s stops), car-like drives, the logger's delays 35+U(0,10)/4/13 ms",
       sim + "bench_lms291_delays_stopgo.yaml", moving, true},
      {"delays_short_stops",
       "(d2) 0.3 s stops, car-like drives (turns to 12 deg/s), the logger's delays",
       sim + "bench_lms291_delays_short_stops.yaml", moving, true},
      {"delays_continuous",
       "(d3) continuous driving, a car's weave (turns to 12.5 deg/s), the logger's delays",
       sim + "bench_lms291_delays_continuous.yaml", moving, true},
      {"rover", "(k) (a) with the wall surveyed by an RTK rover (no total station, no control)",
       sim + "bench_lms291_rover.yaml", matched, false},
  };
}

Args ParseArgs(int argc, char** argv) {
  Args args;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) Usage(a + " needs a value");
      return argv[++i];
    };
    if (a == "--runs") {
      args.runs = std::atoi(value().c_str());
      if (args.runs < 1) Usage("--runs must be >= 1");
    } else if (a == "--first-seed") {
      args.first_seed = std::atoi(value().c_str());
    } else if (a == "--scenario") {
      args.scenario = value();
    } else if (a == "--csv") {
      args.csv = value();
    } else if (a == "--max-crb-obs") {
      args.max_crb_obs = std::atoi(value().c_str());
    } else if (a == "--max-all-obs") {
      args.max_all_obs = std::atoi(value().c_str());
    } else if (a == "--all-min-beams") {
      args.all_min_beams = std::atoi(value().c_str());
      if (args.all_min_beams < 2) Usage("--all-min-beams must be >= 2");
    } else if (a == "--delay-prior") {
      args.delay_prior_s = std::atof(value().c_str());
    } else if (a == "--crb-only") {
      args.crb_only = true;
    } else if (a == "--sim") {
      args.sim = value();
    } else if (a == "--options") {
      args.options = value();
    } else if (a == "--breakdown") {
      args.breakdown = true;
    } else if (a == "--with-variants") {
      args.variants = true;
    } else if (a == "--keep") {
      args.keep = true;
    } else if (a == "--help" || a == "-h") {
      std::printf("%s\n%s", kUsage, kHelp);
      std::exit(0);
    } else if (a == "--list") {
      for (const Scenario& s : Scenarios()) {
        std::printf("%-18s %s%s  (%s)\n", s.name.c_str(), s.label.c_str(),
                    s.variant ? " [variant: run when named or with --with-variants]" : "",
                    s.sim_file.c_str());
      }
      std::exit(0);
    } else {
      Usage("unknown argument " + a);
    }
  }
  return args;
}

}  // namespace wallcal::bench
