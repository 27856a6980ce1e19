// SPDX-License-Identifier: Apache-2.0
#include "guide/run_guide.h"

#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <thread>

#include "guide/guide.h"
#include "guide/guide_text.h"
#include "io/config/session_reader.h"
#include "io/input_file.h"
#include "io/version.h"

namespace wallcal::guide {
namespace {

namespace fs = std::filesystem;

constexpr const char* kUsage = R"(usage: guide SESSION [--json] [--follow] [--config FILE] [--next N]
       guide SESSION --plan MINUTES [--json] [--config FILE]

At the wall, while the logs are being recorded: the stations so far, the σ of the mount if it
were calibrated now (calibrate's own model: the correlated GNSS error and the control points
included), whether the acceptance tolerances are met (enough: yes/no), and the next stops
that would lower the largest σ most.

  SESSION         session.yaml or its folder; its logs may still be growing (a text log's
                  unfinished last line, a ROS 1 bag without its index, an MCAP file without
                  its summary: the complete part is read)
  --json          one JSON object: {"stations": N, "predicted_sigma": {"x_m", "y_m",
                  "yaw_deg"}, "enough": true|false, "next": [{"vehicle_to_wall_deg",
                  "distance_m", "dwell_s", "wait_s"}, ...]} (σ not yet known: null)
  --follow        check the logs once a second and print again when they grew, until
                  enough or Ctrl-C (with --json: one object per line)
  --max-seconds S with --follow: stop after S seconds (default: no limit)
  --plan MINUTES  before any log exists (session.yaml, survey and control only): the best
                  plan for that time budget and its predicted σ
  --config FILE   calibrate options (acceptance tolerances, noise model), as calibrate's
  --next N        how many stops to advise, 1..3 (default 3)
  --threads N     threads (default 0: every core)
  --help          this text;  --version  the tool version

Exit status: 0 printed (with --follow: enough, or stopped); 2 bad input or usage; 3 an
internal error (a bug: please report it).
)";

int Usage(std::ostream& err, const std::string& message) {
  err << "guide: " << message << "\n(run 'wallcal guide --help' for usage)\n";
  return 2;
}

bool ParseNumber(const std::string& text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text.c_str(), &end);
  return !text.empty() && *end == '\0' && std::isfinite(*value);
}

// What the session's logs look like now: their sizes and modification times.
std::string LogSignature(const std::string& session_path) {
  const io::SessionSpec session = io::ReadSession(session_path);
  std::string signature;
  for (const std::string& path : {session.scanner_log, session.gnss_log, session.heading_log}) {
    std::error_code ec;
    const auto size = fs::file_size(path, ec);
    const auto time = fs::last_write_time(path, ec);
    signature += path + ":" + std::to_string(ec ? 0 : size) + ":" +
                 std::to_string(time.time_since_epoch().count()) + ";";
  }
  return signature;
}

}  // namespace

int RunGuide(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  GuideRequest request;
  bool json = false, follow = false;
  double plan_minutes = -1.0, max_seconds = -1.0;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out << kUsage;
      return 0;
    } else if (arg == "--version") {
      out << "wallcal guide " << io::kToolVersion << "\n";
      return 0;
    } else if (arg == "--json") {
      json = true;
    } else if (arg == "--follow") {
      follow = true;
    } else if (arg == "--plan" || arg == "--config" || arg == "--next" || arg == "--threads" ||
               arg == "--max-seconds") {
      if (i + 1 >= args.size()) return Usage(err, arg + " needs a value");
      const std::string& v = args[++i];
      double number = 0.0;
      if (arg == "--config") {
        request.config_path = v;
      } else if (!ParseNumber(v, &number) || number < 0.0) {
        return Usage(err, arg + ": '" + v + "' is not a non-negative number");
      } else if (arg == "--plan") {
        if (number <= 0.0) return Usage(err, "--plan: the budget must be more than 0 minutes");
        plan_minutes = number;
      } else if (arg == "--next") {
        if (number < 1.0 || number > 3.0) return Usage(err, "--next: expected 1, 2 or 3");
        request.max_next = static_cast<int>(number);
      } else if (arg == "--threads") {
        request.threads = static_cast<int>(number);
      } else {
        max_seconds = number;
      }
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage(err, "unknown option '" + arg + "'");
    } else if (request.session_path.empty()) {
      request.session_path = arg;
    } else {
      return Usage(err, "one session only ('" + arg + "' is extra)");
    }
  }
  if (request.session_path.empty()) return Usage(err, "no session given");
  if (follow && plan_minutes > 0.0) return Usage(err, "--follow and --plan do not go together");
  try {
    if (plan_minutes > 0.0) {
      const GuideReport report = PlanSession(request, plan_minutes * 60.0);
      out << (json ? GuideJson(report) : GuideText(report));
      return 0;
    }
    if (!follow) {
      const GuideReport report = AssessSession(request);
      out << (json ? GuideJson(report) : GuideText(report));
      return 0;
    }
    const bool terminal = !json && &out == &std::cout && isatty(STDOUT_FILENO);
    const auto start = std::chrono::steady_clock::now();
    std::string seen;
    while (true) {
      const std::string now = LogSignature(request.session_path);
      if (now != seen) {
        seen = now;
        try {
          const GuideReport report = AssessSession(request);
          if (terminal) out << "\033[H\033[2J";
          out << (json ? GuideJson(report) : GuideText(report)) << std::flush;
          if (report.enough) return 0;
        } catch (const io::InputError& e) {
          // Logs that hold too little yet (no fix, no scan) say so until they grow.
          if (!json) out << "guide: waiting for the logs: " << e.what() << "\n" << std::flush;
        }
      }
      const double elapsed = std::chrono::duration<double>(
                                 std::chrono::steady_clock::now() - start).count();
      if (max_seconds >= 0.0 && elapsed >= max_seconds) return 0;
      std::this_thread::sleep_for(std::chrono::seconds(1));
    }
  } catch (const io::InputError& e) {
    err << "guide: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "guide: internal error: " << e.what() << "\n";
    return 3;
  }
}

int RunGuide(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return RunGuide(args, std::cout, std::cerr);
}

}  // namespace wallcal::guide
