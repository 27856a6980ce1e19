// SPDX-License-Identifier: Apache-2.0
#pragma once
// accuracy_bench's scenarios (docs/results.md, (a) ...) and its command line.

#include <string>
#include <vector>

namespace wallcal::bench {

struct Scenario {
  std::string name;
  std::string label;         // (a) ... (h) of docs/results.md
  std::string sim_file;      // configs/simulate/...
  std::string options_file;  // bench/...
  bool moving = false;       // uses moving scans: the CRB gets a clock-offset unknown too
  // A variant of another scenario's session with some of its data left out on purpose (to show
  // what they add): not held to the all-data bound, and run only when named or asked for.
  bool variant = false;
};

// Every scenario, in the order of docs/results.md.
std::vector<Scenario> Scenarios();

struct Args {
  int runs = 50;
  int first_seed = 1;
  std::string scenario;  // empty: all
  std::string csv;
  bool breakdown = false;
  bool keep = false;
  int max_crb_obs = 1600;
  // The all-data bound: at most this many scans' wall lines (an even subsample by time beyond),
  // and the priors of the GNSS and heading delays (the scanner offset's is flat).
  int max_all_obs = 2400;
  double delay_prior_s = 0.05;
  // A scan's line on a surveyed wall enters the all-data bound when at least this many
  // unoccluded beams return from it (2: every line that has a direction).
  int all_min_beams = 2;
  std::string options;  // calibrate options for every scenario instead of bench/calibrate_*.yaml
  std::string sim;      // --sim FILE: one scenario from this simulate config instead
  bool crb_only = false;  // --crb-only: the all-data bound (and on half the scans), no runs
  bool variants = false;  // --with-variants: the variants too when no scenario is named
};

// Prints why and the usage line, exits with status 2.
[[noreturn]] void Usage(const std::string& why);
// Exits with status 2 and the usage line on a bad argument; --list prints the scenarios and
// exits 0.
Args ParseArgs(int argc, char** argv);

}  // namespace wallcal::bench
