// SPDX-License-Identifier: Apache-2.0
// wallcal guide: at the wall, the σ the session's logs hold now and the next stops
// (guide/run_guide.h parses the rest of the command line and runs it).

#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "guide/run_guide.h"

namespace wallcal::apps {

const CommandHelp& GuideHelp() {
  static const CommandHelp help{
      "guide",
      "at the wall, while recording: the σ if calibrated now, enough yes/no, the next stops",
      {"SESSION [--json] [--follow [--max-seconds S]] [--next N] [--config FILE] [--threads N]",
       "SESSION --plan MINUTES [--json] [--config FILE]"},
      "At the wall, while the logs are being recorded: the stations so far, the σ of the mount if it\n"
      "were calibrated now (calibrate's own model: the correlated GNSS error and the control points\n"
      "included), whether the acceptance tolerances are met (enough: yes/no), and the next stops\n"
      "that would lower the largest σ most.\n",
      {
          {"SESSION", "", "", ValueKind::kPath, {},
           "session.yaml or its folder; its logs may still be growing (a text log's\n"
           "unfinished last line, a ROS 1 bag without its index, an MCAP file without\n"
           "its summary: the complete part is read)"},
          {"--json", "", "", ValueKind::kNone, {},
           "one JSON object: {\"stations\": N, \"predicted_sigma\": {\"x_m\", \"y_m\",\n"
           "\"yaw_deg\"}, \"enough\": true|false, \"next\": [{\"vehicle_to_wall_deg\",\n"
           "\"distance_m\", \"dwell_s\", \"wait_s\"}, ...]} (σ not yet known: null)"},
          {"--follow", "", "", ValueKind::kNone, {},
           "check the logs once a second and print again when they grew, until\n"
           "enough or Ctrl-C (with --json: one object per line)"},
          {"--max-seconds", "", "S", ValueKind::kWord, {},
           "with --follow: stop after S seconds (default: no limit)"},
          {"--plan", "", "MINUTES", ValueKind::kWord, {},
           "before any log exists (session.yaml, survey and control only): the best\n"
           "plan for that time budget and its predicted σ"},
          {"--config", "", "FILE", ValueKind::kFile, {},
           "calibrate options (acceptance tolerances, noise model), as calibrate's"},
          {"--next", "", "N", ValueKind::kWord, {}, "how many stops to advise, 1..3 (default 3)"},
          {"--threads", "", "N", ValueKind::kWord, {}, "threads (default 0: every core)"},
          {"--help", "-h", "", ValueKind::kNone, {}, "this text"},
          {"--version", "", "", ValueKind::kNone, {}, "the tool version"},
      },
      "",
      "0 printed (with --follow: enough, or stopped); 2 bad input or usage; 3 an\n"
      "internal error (a bug: please report it).\n"};
  return help;
}

int RunGuideCommand(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& arg : args) {
    if (arg == "--help" || arg == "-h") {
      std::cout << FormatHelp(GuideHelp());
      return 0;
    }
  }
  return guide::RunGuide(args, std::cout, std::cerr);
}

}  // namespace wallcal::apps
