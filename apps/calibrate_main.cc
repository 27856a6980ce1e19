// calibrate: estimate the scanner mount from a logged wall session and write offsets.yaml.
// The one place (with simulate_main) that catches io::InputError and turns it into an exit code.

#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include "apps/pipeline.h"
#include "io/version.h"
#include "io/writers.h"

namespace {

constexpr const char* kUsage = R"(usage: calibrate SESSION [--output FILE] [--method ceres|barawid] [--config FILE] [--quiet]

Estimates where a 2-D laser scanner sits on a vehicle (x, y, yaw of the scanner in the GNSS
antenna's frame: x forward, y left, yaw counter-clockwise) from a logged session in front of a
surveyed wall, and writes offsets.yaml.

  SESSION            a session.yaml, or the folder holding one (format: docs/session-format.md)
  --output FILE      where to write the offsets (default: offsets.yaml beside session.yaml)
  --method M         ceres   (default) joint least squares with a robust loss; the sigma includes
                             the survey, control-point and correlated GNSS errors
                     barawid the closed form of Barawid et al. 2007 (seed 002, Eq. 8-16), for
                             comparison; its sigma treats every scan as independent
  --config FILE      calibration options (YAML; defaults: configs/calibrate.yaml)
  --quiet            no progress lines on stderr, only warnings and errors
  --help             this text;  --version  the tool version

Exit status: 0 offsets written; 1 the data cannot determine the mount (nothing written);
2 bad input or usage (nothing written). The reason is one line on stderr.
)";

int Usage(const std::string& message) {
  std::cerr << "calibrate: " << message << "\n(run 'calibrate --help' for usage)\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  wallcal::app::CalibrateRequest request;
  std::string output;
  bool quiet = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&](const char* name) -> const char* {
      if (i + 1 >= argc) return nullptr;
      (void)name;
      return argv[++i];
    };
    if (arg == "--help" || arg == "-h") {
      std::cout << kUsage;
      return 0;
    } else if (arg == "--version") {
      std::cout << "wallcal calibrate " << wallcal::io::kToolVersion << "\n";
      return 0;
    } else if (arg == "--output" || arg == "-o") {
      const char* v = value("--output");
      if (v == nullptr) return Usage("--output needs a file name");
      output = v;
    } else if (arg == "--method") {
      const char* v = value("--method");
      if (v == nullptr) return Usage("--method needs ceres or barawid");
      request.method = v;
      if (request.method != "ceres" && request.method != "barawid") {
        return Usage("--method: unknown method '" + request.method + "'; expected ceres or barawid");
      }
    } else if (arg == "--config") {
      const char* v = value("--config");
      if (v == nullptr) return Usage("--config needs a file name");
      request.config_path = v;
    } else if (arg == "--quiet" || arg == "-q") {
      quiet = true;
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage("unknown option '" + arg + "'");
    } else if (request.session_path.empty()) {
      request.session_path = arg;
    } else {
      return Usage("more than one SESSION given ('" + request.session_path + "' and '" + arg + "')");
    }
  }
  if (request.session_path.empty()) return Usage("no SESSION given");

  try {
    const bool show_progress = !quiet && isatty(STDERR_FILENO);
    wallcal::app::ProgressFn progress;
    if (show_progress) {
      progress = [](const wallcal::app::Progress& p) {
        if (p.done == 0) std::cerr << "calibrate: " << p.stage << "\n";
      };
    }
    const wallcal::app::CalibrationResult result = wallcal::app::RunCalibration(request, progress);
    std::cout << wallcal::app::FormatSummary(result);
    if (!result.estimate.usable) {
      std::cerr << "calibrate: " << result.session.file
                << ": mount not determined: " << result.estimate.message << "\n";
      return 1;
    }
    if (output.empty()) output = wallcal::app::DefaultOutputPath(result.session);
    wallcal::io::WriteFileAtomically(
        output, wallcal::io::FormatOffsetsYaml(wallcal::app::MakeOffsetsDocument(result)));
    std::cout << "  wrote      " << output << "\n";
    return 0;
  } catch (const wallcal::io::InputError& error) {
    std::cerr << "calibrate: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    std::cerr << "calibrate: internal error: " << error.what() << "\n";
    return 3;
  }
}
