// SPDX-License-Identifier: Apache-2.0
// wallcal guide: at the wall, the σ the session's logs hold now and the next stops.
// Argument parsing and error reporting only; the work is in guide/.

#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <iostream>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "apps/commands.h"
#include "guide/follow.h"
#include "guide/guide.h"
#include "guide/guide_session.h"
#include "guide/guide_text.h"
#include "io/types.h"
#include "serve/guide_server.h"
#include "serve/listen_address.h"
#include "serve/live_board.h"

namespace wallcal::apps {

const CommandHelp& GuideHelp() {
  static const CommandHelp help{
      "guide",
      "at the wall, while recording: the σ if calibrated now, enough yes/no, the next stops",
      {"SESSION [--scanner ID] [--json] [--follow [--max-seconds S] [--serve [ADDR:]PORT]] "
       "[--next N] [--config FILE] [--threads N]",
       "SESSION [--scanner ID] --plan MINUTES [--json] [--serve [ADDR:]PORT [--max-seconds S]] "
       "[--config FILE]"},
      "At the wall, while the logs are being recorded: the stations so far, the σ of the mount if it\n"
      "were calibrated now (calibrate's own model: the correlated GNSS error and the control points\n"
      "included), whether the acceptance tolerances are met (enough: yes/no), and the next stops\n"
      "that would lower the largest σ most. One scanner: a session with scanners: is guided one\n"
      "scanner at a time (--scanner ID).\n",
      {
          {"SESSION", "", "", ValueKind::kPath, {},
           "session.yaml or its folder; its logs may still be growing (a text log's\n"
           "unfinished last line, a ROS 1 bag without its index, an MCAP file without\n"
           "its summary: the complete part is read)"},
          {"--scanner", "", "ID", ValueKind::kWord, {},
           "a session with scanners: the scanner to guide (its σ is its mount's in\n"
           "calibrate's joint adjustment, to within a few per cent)"},
          {"--json", "", "", ValueKind::kNone, {},
           "one JSON object: {\"stations\": N, \"predicted_sigma\": {\"x_m\", \"y_m\",\n"
           "\"yaw_deg\"}, \"enough\": true|false, \"next\": [{\"vehicle_to_wall_deg\",\n"
           "\"distance_m\", \"dwell_s\", \"wait_s\", ...}, ...], ...} (σ not yet known:\n"
           "null), with what --serve's page draws: the walls, the stations' poses,\n"
           "the vehicle's, each next stop's target pose and instruction, why not\n"
           "enough, the warnings (positions in the local frame, m; yaws in deg)"},
          {"--follow", "", "", ValueKind::kNone, {},
           "check the logs once a second and print again when they grew, until\n"
           "enough or Ctrl-C (with --json: one object per line); the logs (text logs,\n"
           "recordings, rosbag2 folders) are read on from where the last read stopped;\n"
           "logs not yet holding two fixes and a scan are waited for"},
          {"--max-seconds", "", "S", ValueKind::kWord, {},
           "with --follow: stop after S seconds (default: no limit); with --plan\n"
           "--serve: serve the plan that long"},
          {"--serve", "", "[ADDR:]PORT", ValueKind::kWord, {},
           "with --follow or --plan: also serve a page that draws the report and\n"
           "updates itself (the site's walls, the stations, the vehicle, the next\n"
           "stops and the moves to them, the σ against the tolerances and over time,\n"
           "enough or not yet and why, the warnings) at http://ADDR:PORT/ (PORT 0:\n"
           "any free one; ADDR default 127.0.0.1). Any address but loopback (e.g.\n"
           "0.0.0.0 for a tablet on the vehicle's network) needs the access token\n"
           "in the URL printed on stderr. The page is served until the guide ends\n"
           "and a page has fetched the last report (at most " +
           std::to_string(static_cast<int>(serve::kLastReportLingerS)) + " s more)"},
          {"--plan", "", "MINUTES", ValueKind::kWord, {},
           "before any log exists (session.yaml, survey and control only): the best\n"
           "plan for that time budget and its predicted σ"},
          {"--config", "", "FILE", ValueKind::kFile, {},
           "calibrate options (acceptance tolerances, noise model), as calibrate's"},
          {"--next", "", "N", ValueKind::kWord, {}, "how many stops to advise, 1..3 (default 3)"},
          {"--threads", "", "N", ValueKind::kWord, {}, "threads (default 0: every core)"},
          HelpOption(),
          VersionOption(),
      },
      "",
      "0 printed (with --follow: enough, or --max-seconds reached; Ctrl-C ends it as\n"
      "the signal does); 2 bad input or usage; 3 an internal error (a bug: please report it).\n"};
  return help;
}

namespace {

int Usage(const std::string& message) {
  return UsageError(GuideHelp(), message);
}

bool ParseNumber(const std::string& text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(*value);
}

// What the command line asks for.
struct GuideCommandLine {
  guide::GuideOptions options;
  bool json = false;
  bool follow = false;
  double plan_minutes = -1.0;  // > 0: --plan
  guide::FollowOptions follow_options;
  std::optional<serve::ListenAddress> serve;  // --serve
};

// Parses the arguments after `guide` into *line: 0, or the exit status of a usage error (2).
int Parse(const std::vector<std::string>& args, GuideCommandLine* line) {
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--json") {
      line->json = true;
    } else if (arg == "--follow") {
      line->follow = true;
    } else if (arg == "--plan" || arg == "--config" || arg == "--next" || arg == "--threads" ||
               arg == "--max-seconds" || arg == "--scanner" || arg == "--serve") {
      if (i + 1 >= args.size()) return Usage(arg + " needs a value");
      const std::string& v = args[++i];
      double number = 0.0;
      if (arg == "--serve") {
        serve::ListenAddress address;
        std::string message;
        if (serve::ParseListenAddress(v, &address, &message) != serve::AddressError::kNone) {
          return Usage("--serve: " + message);
        }
        line->serve = address;
      } else if (arg == "--config") {
        line->options.config_path = v;
      } else if (arg == "--scanner") {
        if (v.empty()) return Usage("--scanner needs a scanner id");
        line->options.scanner_id = v;
      } else if (!ParseNumber(v, &number) || number < 0.0) {
        return Usage(arg + ": '" + v + "' is not a non-negative number");
      } else if (arg == "--plan") {
        if (number <= 0.0) return Usage("--plan: the budget must be more than 0 minutes");
        line->plan_minutes = number;
      } else if (arg == "--next") {
        if (number != 1.0 && number != 2.0 && number != 3.0) {
          return Usage("--next: expected 1, 2 or 3");
        }
        line->options.max_next = static_cast<int>(number);
      } else if (arg == "--threads") {
        line->options.threads = static_cast<int>(number);
      } else {
        line->follow_options.max_seconds = number;
      }
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage("unknown option '" + arg + "'");
    } else if (line->options.session_path.empty()) {
      line->options.session_path = arg;
    } else {
      return Usage("one session only ('" + arg + "' is extra)");
    }
  }
  if (line->options.session_path.empty()) return Usage("no session given");
  if (line->follow && line->plan_minutes > 0.0) {
    return Usage("--follow and --plan do not go together");
  }
  if (line->serve && !line->follow && line->plan_minutes <= 0.0) {
    return Usage("--serve goes with --follow or --plan");
  }
  return 0;
}

std::string Render(const guide::GuideReport& report, bool json) {
  return json ? guide::GuideJson(report) : guide::GuideText(report);
}

// The page's address, for people (stderr, so that --json's stdout stays one object a line).
void PrintUrls(const serve::GuideServer& server, std::ostream& out) {
  const std::vector<std::string> urls = server.Urls();
  out << "guide: the page is at " << urls.front();
  for (size_t i = 1; i < urls.size(); ++i) out << "\n                      or " << urls[i];
  if (!server.token().empty()) out << "\n       (open it as printed: the token in it is needed)";
  out << "\n" << std::flush;
}

// --serve: the guide as without it, each report also published to the page; the server stops
// once a page has fetched the last report, at most kLastReportLingerS after the guide ends
// (Ctrl-C ends both at once).
int RunServed(const GuideCommandLine& line) {
  serve::LiveBoard board;
  serve::ServeOptions options;
  options.address = *line.serve;
  serve::GuideServer server(&board, options);
  server.Start();
  PrintUrls(server, std::cerr);
  // The page keeps the last report it fetched: serve until it has fetched the last one.
  const auto linger = [&] {
    if (server.WaitUntilServed(board.Live().seq, serve::kLastReportLingerS)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(500));  // its answer on its way
    }
    server.Stop();
  };
  if (line.plan_minutes > 0.0) {
    const guide::GuideReport plan = guide::PlanSession(line.options, line.plan_minutes * 60.0);
    board.PublishReport(plan);
    std::cout << Render(plan, line.json) << std::flush;
    // Served until --max-seconds or Ctrl-C.
    const auto start = std::chrono::steady_clock::now();
    while (line.follow_options.max_seconds < 0.0 ||
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() <
               line.follow_options.max_seconds) {
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
    board.PublishEnd(serve::GuideEnd::kTimeLimit);
    linger();
    return 0;
  }
  guide::GuideSession session(line.options);
  const bool terminal = !line.json && isatty(STDOUT_FILENO);
  const guide::FollowEnd end = guide::Follow(
      &session, line.follow_options,
      [&](const guide::GuideReport& report) {
        board.PublishReport(report, session.last_read().scan_log_bytes);
        if (terminal) std::cout << "\033[H\033[2J";
        std::cout << Render(report, line.json);
        if (terminal) PrintUrls(server, std::cout);  // the screen was cleared
        std::cout << std::flush;
      },
      [&](const std::string& message) {
        board.PublishWaiting(message);
        if (!line.json) std::cout << "guide: waiting for the logs: " << message << "\n" << std::flush;
      });
  board.PublishEnd(end == guide::FollowEnd::kEnough ? serve::GuideEnd::kEnough
                                                    : serve::GuideEnd::kTimeLimit);
  linger();
  return 0;
}

}  // namespace

int RunGuideCommand(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  for (const std::string& arg : args) {
    if (PrintHelpOrVersion(arg, GuideHelp(), std::cout)) return 0;
  }
  GuideCommandLine line;
  if (const int status = Parse(args, &line); status != 0) return status;
  return ExitStatusOf(GuideHelp(), [&] {
    if (line.serve) return RunServed(line);
    if (line.plan_minutes > 0.0) {
      std::cout << Render(guide::PlanSession(line.options, line.plan_minutes * 60.0), line.json);
      return 0;
    }
    guide::GuideSession session(line.options);
    if (!line.follow) {
      std::cout << Render(session.Refresh(), line.json);
      return 0;
    }
    // On a terminal each report replaces the last; with --json, one object a line.
    const bool terminal = !line.json && isatty(STDOUT_FILENO);
    guide::Follow(
        &session, line.follow_options,
        [&](const guide::GuideReport& report) {
          if (terminal) std::cout << "\033[H\033[2J";
          std::cout << Render(report, line.json) << std::flush;
        },
        [&](const std::string& message) {
          // Logs that hold too little yet (no fix, no scan) say so until they grow.
          if (!line.json) std::cout << "guide: waiting for the logs: " << message << "\n" << std::flush;
        });
    return 0;
  });
}

}  // namespace wallcal::apps
