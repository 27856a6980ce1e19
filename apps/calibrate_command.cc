// SPDX-License-Identifier: Apache-2.0
// wallcal calibrate: estimate the scanner mount from a logged wall session and write offsets.yaml.

#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "io/input_file.h"
#include "io/output_file.h"
#include "io/config/session_reader.h"
#include "io/config/config_writer.h"
#include "io/output_file.h"
#include "outputs/emit.h"
#include "outputs/multi_offsets.h"
#include "outputs/multi_report.h"
#include "outputs/offsets_document.h"
#include "outputs/report.h"
#include "outputs/summary.h"
#include "pipeline/calibration.h"
#include "pipeline/config_dirs.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::apps {

const CommandHelp& CalibrateHelp() {
  static const CommandHelp help{
      "calibrate",
      "estimate the scanner mount from a wall session and write offsets.yaml",
      {"SESSION [--output FILE] [--method ceres|barawid] [--config FILE] [--report DIR] "
       "[--emit ros2-static-tf|urdf|json] [--parent-frame NAME] [--child-frame NAME] "
       "[--base-frame NAME] [--compare PREVIOUS.yaml] [--force] [--quiet] [--threads N] "
       "[--allow-partial]"},
      "Estimates where a 2-D laser scanner sits on a vehicle (x, y, yaw of the scanner in the GNSS\n"
      "antenna's frame: x forward, y left, yaw counter-clockwise) from a logged session in front of a\n"
      "surveyed wall, and writes offsets.yaml.\n",
      {
          SessionArgument(),
          {"--output", "-o", "FILE", ValueKind::kFile, {},
           "where to write the offsets (default: offsets.yaml beside session.yaml);\n"
           "- writes them to stdout (the summary then goes to stderr). Only a regular\n"
           "file or a new path is replaced (a link is followed), never an input"},
          {"--method", "", "M", ValueKind::kChoice, {"ceres", "barawid"},
           "ceres   (default) joint least squares with a robust loss; the sigma includes\n"
           "        the survey, control-point and correlated GNSS errors\n"
           "barawid the closed form of Barawid et al. 2007 (Eq. 8-16), for\n"
           "        comparison; its sigma treats every scan as independent"},
          CalibrationConfigOption(),
          {"--report", "", "DIR", ValueKind::kFolder, {},
           "also write DIR/report.html: one self-contained page (inline SVG plots, no\n"
           "script, nothing fetched) showing the mount and its uncertainty, the site,\n"
           "scans, the Hough accumulator, residuals, heading coverage and the counts\n"
           "(docs/report.md). Written even when the mount is not determined. With\n"
           "scanners: in session.yaml, DIR/ID/report.html for each scanner and\n"
           "DIR/index.html: every scanner, the relative transforms, one site map"},
          {"--emit", "", "FORMAT", ValueKind::kChoice, {"ros2-static-tf", "urdf", "json"},
           "print the mount for a navigation stack: ros2-static-tf (a\n"
           "`ros2 run tf2_ros static_transform_publisher ...` line), urdf (a fixed\n"
           "<joint>), json (mount, sigma, covariance, frames, verdict). With\n"
           "--emit, stdout carries ONLY the emitted text (pipe it); the summary goes\n"
           "to stderr. Emitted only when the mount is determined. One tree: when\n"
           "session.yaml gives antenna_in_base, base frame -> antenna frame is\n"
           "emitted too, then antenna frame -> scanner frame. The scanner's height\n"
           "relative to the antenna is session.yaml's scanner.z_m (the calibration\n"
           "cannot see it); without it z = 0 and the emitted text says so."},
          {"--parent-frame", "", "NAME", ValueKind::kWord, {},
           "the antenna frame's name (default gnss_antenna)"},
          {"--child-frame", "", "NAME", ValueKind::kWord, {},
           "the scanner frame's name (default laser). Refused (exit 2) with scanners:\n"
           "in session.yaml: each scanner's frame is its frame: (default: its id)"},
          {"--base-frame", "", "NAME", ValueKind::kWord, {},
           "the vehicle frame's name (default base_link). Frame names as tf2 takes\n"
           "them: letters, digits, '_', '.', '/', '-', no leading '/'. The names are\n"
           "written into offsets.yaml."},
          {"--compare", "", "FILE", ValueKind::kFile, {},
           "an earlier offsets.yaml: the change since then (mm, degrees and combined\n"
           "sigma) in the summary, offsets.yaml and the report; the verdict says\n"
           "REVIEW when it is beyond the acceptance tolerances. With scanners: in\n"
           "session.yaml, each scanner is compared by id (with a one-scanner file,\n"
           "the scanner whose frame is its child_frame) and each relative transform\n"
           "by (from, to), or by (to, from) inverted when the earlier session listed\n"
           "the two scanners the other way round; a scanner found in one file only\n"
           "is named"},
          {"--allow-partial", "", "", ValueKind::kNone, {},
           "with several scanners (session.yaml scanners:), write the others when\n"
           "one is refused (by default the run fails, exit 1)"},
          {"--force", "", "", ValueKind::kNone, {},
           "write an estimate a check refuses (observability, scanner preset against\n"
           "the data, scanner.mount_guess tolerance), with a warning"},
          {"--quiet", "-q", "", ValueKind::kNone, {},
           "no progress on stderr, only the summary, warnings and errors"},
          {"--threads", "", "N", ValueKind::kWord, {},
           "threads for wall detection and the solve (default: every core); the\n"
           "result does not depend on N"},
          HelpOption(),
          VersionOption(),
      },
      "On a terminal (stderr is a tty) progress is shown on stderr: scans read / total, rate and time\n"
      "left, updated in place. When stderr is not a terminal, nothing but the summary and warnings.\n"
      "\n"
      "The summary starts with the verdict: ACCEPT (within the acceptance tolerances of the options'\n"
      "`acceptance:` section), REVIEW (usable, but look first: the reasons follow) or REJECT.\n",
      "0 offsets written; 1 the data cannot determine the mount, or the estimate is refused\n"
      "(outside scanner.mount_guess's tolerance; nothing written but the report); 2 bad input or usage,\n"
      "including a scanner preset that does not fit the data or a survey that is not where the GNSS\n"
      "track is (nothing written); 3 an internal error (a bug: please report it; never the answer to\n"
      "any input). The reason is one line on stderr.\n"};
  return help;
}

}  // namespace wallcal::apps

namespace {

int Usage(const std::string& message) {
  return wallcal::apps::UsageError(wallcal::apps::CalibrateHelp(), message);
}

// offsets.yaml to `output` ("-": stdout, else replaced atomically), and where it went in the
// summary.
void WriteOffsets(const std::string& output, const std::string& offsets_yaml,
                  std::ostream& summary_out) {
  if (wallcal::io::IsStdoutPath(output)) {
    std::cout << offsets_yaml << std::flush;
    return;
  }
  wallcal::io::WriteFileAtomically(output, offsets_yaml);
  summary_out << "  wrote      " << wallcal::io::EscapeControl(output) << "\n";
}

// Progress on a terminal: a stage announcement (done == 0, total == 0) gets its own line; counted
// progress within a stage is rewritten in place with '\r' at most five times a second.
class ProgressLine {
 public:
  void Update(const wallcal::pipeline::Progress& p) {
    const auto now = Clock::now();
    if (!p.counted) {
      Close();
      std::cerr << "calibrate: " << p.text << "\n";
      counting_ = false;
      return;
    }
    const bool new_stage = !counting_ || p.stage != stage_;
    if (new_stage) {
      Close();
      counting_ = true;
      stage_ = p.stage;
      stage_start_ = now;
      stage_start_done_ = p.done;
    } else if (now - last_draw_ < std::chrono::milliseconds(200) &&
               !(p.total > 0 && p.done >= p.total)) {  // the last count is always drawn
      return;
    }
    last_draw_ = now;
    const double elapsed_s = std::chrono::duration<double>(now - stage_start_).count();
    const double rate = elapsed_s > 0.05 ? (p.done - stage_start_done_) / elapsed_s : 0.0;
    char line[256];
    int n = std::snprintf(line, sizeof(line), "\rcalibrate:   %s: %lld", p.text.c_str(),
                          static_cast<long long>(p.done));
    if (p.total > 0 && n > 0 && n < static_cast<int>(sizeof(line))) {
      n += std::snprintf(line + n, sizeof(line) - n, " / %lld scans",
                         static_cast<long long>(p.total));
    } else if (n > 0 && n < static_cast<int>(sizeof(line))) {
      n += std::snprintf(line + n, sizeof(line) - n, " scans");
    }
    if (rate > 0 && n > 0 && n < static_cast<int>(sizeof(line))) {
      n += std::snprintf(line + n, sizeof(line) - n, ", %.0f scans/s", rate);
      if (p.total > p.done) {
        const double left_s = (p.total - p.done) / rate;
        if (n > 0 && n < static_cast<int>(sizeof(line))) {
          n += std::snprintf(line + n, sizeof(line) - n, ", %.0f s left", left_s + 0.5);
        }
      }
    }
    std::cerr << line << "\x1b[K" << std::flush;  // clear what a longer previous line left
    open_ = true;
  }
  // Ends an in-place line so the next output starts on a fresh line.
  void Close() {
    if (open_) std::cerr << "\n";
    open_ = false;
  }

 private:
  using Clock = std::chrono::steady_clock;
  wallcal::pipeline::Stage stage_ = wallcal::pipeline::Stage::kReadingInputs;
  bool counting_ = false;
  Clock::time_point stage_start_{}, last_draw_{};
  long long stage_start_done_ = 0;
  bool open_ = false;
};


// A session with `scanners:`: every scanner's run, the joint adjustment, offsets.yaml with
// scanner_mounts and relative_mounts, --emit as one tree. Exit 1 when a scanner is refused
// (without --allow-partial) or none is calibrated.
int CalibrateSeveral(wallcal::pipeline::CalibrateRequest request, bool allow_partial,
                     const std::string& output, const std::string& report_dir,
                     const std::optional<wallcal::outputs::EmitFormat>& emit,
                     const wallcal::outputs::EmitFrames& frames, std::ostream& summary_out,
                     const wallcal::pipeline::ProgressFn& progress, ProgressLine* progress_line) {
  namespace pipeline = wallcal::pipeline;
  namespace outputs = wallcal::outputs;
  if (request.method != wallcal::solvers::Method::kCeres) {
    return Usage("--method barawid calibrates one scanner; a session with scanners: needs ceres");
  }
  // Each scanner's frame is a child frame in the emitted tree and in offsets.yaml.
  const wallcal::io::SessionSpec session = wallcal::io::ReadSession(request.session_path);
  for (const wallcal::io::ScannerSpec& scanner : session.scanners) {
    std::string problem = outputs::FrameNameProblem(scanner.frame);
    if (problem.empty() && (scanner.frame == frames.parent || scanner.frame == frames.base)) {
      problem = "it is the name of the antenna or base frame";
    }
    if (!problem.empty()) {
      throw wallcal::io::InputError(wallcal::io::Where(
          session.file, scanner.line,
          "scanner '" + scanner.id + "': frame '" + scanner.frame + "' is not usable: " +
              problem + "; expected a tf2 frame id of letters, digits, '_', '.', '/', '-' (give "
              "frame: when the id is not one)"));
    }
  }
  request.collect_report_data = !report_dir.empty();
  const pipeline::SeveralScannersResult several =
      pipeline::RunSeveralScanners(request, allow_partial, progress);
  progress_line->Close();
  summary_out << wallcal::io::EscapeControl(outputs::FormatSeveralSummary(several), true);
  // One report per scanner, in REPORT/ID/ (its own run, with the joint mount and σ).
  for (const pipeline::ScannerRun& run : several.scanners) {
    if (report_dir.empty()) break;
    try {
      const std::string path =
          outputs::WriteReport(run.own, (std::filesystem::path(report_dir) / run.spec.id).string(),
                               run.joint ? &*run.joint : nullptr);
      summary_out << "  report     " << wallcal::io::EscapeControl(path) << "\n";
    } catch (const std::exception& error) {
      std::cerr << "calibrate: warning: report of scanner '" << run.spec.id
                << "' not written: " << wallcal::io::EscapeControl(error.what()) << "\n";
    }
  }
  // The run's page, REPORT/index.html: every scanner, the relative transforms, one site map.
  if (!report_dir.empty()) {
    try {
      const std::string path = outputs::WriteSeveralReport(several, report_dir);
      summary_out << "  report     " << wallcal::io::EscapeControl(path) << "\n";
    } catch (const std::exception& error) {
      std::cerr << "calibrate: warning: report index not written: "
                << wallcal::io::EscapeControl(error.what()) << "\n";
    }
  }
  if (several.outcome == pipeline::SeveralOutcome::kFailed) {
    std::cerr << "calibrate: "
              << wallcal::io::EscapeControl(several.session.file + ": " + several.message) << "\n";
    return 1;
  }
  WriteOffsets(output, outputs::FormatSeveralOffsetsYaml(several, frames), summary_out);
  if (emit) {
    summary_out << std::flush;
    std::cout << outputs::FormatSeveralEmit(*emit, several, frames) << std::flush;
  }
  return 0;
}

}  // namespace

int wallcal::apps::RunCalibrate(int argc, char** argv) {
  namespace pipeline = wallcal::pipeline;
  namespace outputs = wallcal::outputs;
  pipeline::CalibrateRequest request;
  std::string output, report_dir;
  std::optional<outputs::EmitFormat> emit;
  outputs::EmitFrames frames;
  bool quiet = false;
  bool child_frame_given = false;
  bool allow_partial = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto value = [&]() -> const char* {
      if (i + 1 >= argc) return nullptr;
      return argv[++i];
    };
    auto frame = [&](const char* option, std::string* name) -> int {
      const char* v = value();
      if (v == nullptr) return Usage(std::string(option) + " needs a frame name");
      if (const std::string problem = outputs::FrameNameProblem(v); !problem.empty()) {
        return Usage(std::string(option) + ": invalid frame name '" + v + "': " + problem +
                     "; expected a tf2 frame id of letters, digits, '_', '.', '/', '-'");
      }
      *name = v;
      return 0;
    };
    if (PrintHelpOrVersion(arg, CalibrateHelp(), std::cout)) {
      return 0;
    } else if (arg == "--output" || arg == "-o") {
      const char* v = value();
      if (v == nullptr) return Usage("--output needs a file name");
      if (*v == '\0') return Usage("--output: empty file name (an unset variable?); expected a path or -");
      output = v;
    } else if (arg == "--method") {
      const char* v = value();
      if (v == nullptr) return Usage("--method needs ceres or barawid");
      const std::string method = v;
      if (method == "ceres") {
        request.method = wallcal::solvers::Method::kCeres;
      } else if (method == "barawid") {
        request.method = wallcal::solvers::Method::kBarawid;
      } else {
        return Usage("--method: unknown method '" + method + "'; expected ceres or barawid");
      }
    } else if (arg == "--config") {
      const char* v = value();
      if (v == nullptr) return Usage("--config needs a file name");
      if (*v == '\0') return Usage("--config: empty file name (an unset variable?); expected a YAML file");
      request.config_path = v;
    } else if (arg == "--report") {
      const char* v = value();
      if (v == nullptr || *v == '\0') return Usage("--report needs a folder");
      report_dir = v;
    } else if (arg == "--emit") {
      const char* v = value();
      outputs::EmitFormat format;
      if (v == nullptr || !outputs::ParseEmitFormat(v, &format)) {
        return Usage(std::string("--emit: ") + (v ? "unknown format '" + std::string(v) + "'" : "no format") +
                     "; expected ros2-static-tf, urdf or json");
      }
      emit = format;
    } else if (arg == "--parent-frame") {
      if (const int status = frame("--parent-frame", &frames.parent); status != 0) return status;
    } else if (arg == "--child-frame") {
      if (const int status = frame("--child-frame", &frames.child); status != 0) return status;
      child_frame_given = true;
    } else if (arg == "--base-frame") {
      if (const int status = frame("--base-frame", &frames.base); status != 0) return status;
    } else if (arg == "--compare") {
      const char* v = value();
      if (v == nullptr || *v == '\0') return Usage("--compare needs an earlier offsets.yaml");
      request.compare_path = v;
    } else if (arg == "--threads") {
      const char* v = value();
      char* end = nullptr;
      const long n = v == nullptr ? 0 : std::strtol(v, &end, 10);
      if (v == nullptr || *v == '\0' || *end != '\0' || n < 1 || n > 256) {
        return Usage("--threads needs a whole number from 1 to 256");
      }
      request.threads = static_cast<int>(n);
    } else if (arg == "--force") {
      request.force = true;
    } else if (arg == "--allow-partial") {
      allow_partial = true;
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
  if (emit && wallcal::io::IsStdoutPath(output)) {
    return Usage("--output - and --emit both want standard output; expected one of them");
  }
  if (frames.parent == frames.child || frames.parent == frames.base || frames.child == frames.base) {
    return Usage("--parent-frame, --child-frame and --base-frame must be three different names");
  }
  request.command_line = {"wallcal"};
  request.command_line.insert(request.command_line.end(), argv, argv + argc);

  // With --emit or --output -, stdout is reserved for that text so it can be piped.
  std::ostream& summary_out = emit || wallcal::io::IsStdoutPath(output) ? std::cerr : std::cout;
  ProgressLine progress_line;
  bool several = false;
  try {
    const bool show_progress = !quiet && isatty(STDERR_FILENO);
    pipeline::ProgressFn progress;
    if (show_progress) {
      progress = [&progress_line](const pipeline::Progress& p) { progress_line.Update(p); };
    }
    // Fail early: the outputs are checked before the work (a missing folder, a device, an
    // input of the run named as the output: io/output_file.h).
    {
      const wallcal::io::SessionSpec session = wallcal::io::ReadSession(request.session_path);
      if (output.empty()) output = pipeline::DefaultOutputPath(session);
      // Every file the run reads: the session's logs and survey, --config, --compare and the
      // scanner preset calibrate resolves (in SESSION/scanners/ or the shipped folders); with
      // scanners:, each scanner's log and preset.
      std::vector<std::string> inputs = {
          session.file, session.scanner_log, session.gnss_log, session.heading_log,
          session.survey_points, request.config_path, request.compare_path,
          pipeline::SessionPresetPath(session.scanner_model, session.dir)};
      for (const wallcal::io::ScannerSpec& scanner : session.scanners) {
        inputs.push_back(scanner.log);
        inputs.push_back(pipeline::SessionPresetPath(scanner.model, session.dir));
      }
      wallcal::io::CheckOutputPath("--output", output, inputs);
      if (!report_dir.empty()) wallcal::io::CheckOutputFolder("--report", report_dir);
      several = !session.scanners.empty();
    }
    if (several && child_frame_given) {
      return Usage("--child-frame names the one scanner's frame; a session with scanners: takes "
                   "each scanner's frame: (default: its id) from session.yaml");
    }
    if (several) {
      return CalibrateSeveral(request, allow_partial, output, report_dir, emit, frames, summary_out,
                              progress, &progress_line);
    }
    request.collect_report_data = !report_dir.empty();
    const pipeline::CalibrationResult result = pipeline::RunCalibration(request, progress);
    progress_line.Close();
    summary_out << wallcal::io::EscapeControl(outputs::FormatSummary(result), true);
    if (!report_dir.empty()) {
      if (show_progress) std::cerr << "calibrate: writing the report\n";
      // A report that cannot be written costs the report, never a good calibration.
      try {
        const std::string path = outputs::WriteReport(result, report_dir);
        summary_out << "  report     " << wallcal::io::EscapeControl(path) << "\n";
      } catch (const std::exception& error) {
        std::cerr << "calibrate: warning: report not written: "
                  << wallcal::io::EscapeControl(error.what()) << "\n";
      }
    }
    if (!result.solve.estimate.usable) {
      std::cerr << "calibrate: "
                << wallcal::io::EscapeControl(result.loaded.session.file +
                                              ": mount not determined: " + result.Why())
                << "\n";
      return 1;
    }
    WriteOffsets(output,
                 wallcal::io::FormatOffsetsYaml(outputs::MakeOffsetsDocument(result, frames)),
                 summary_out);
    if (emit) {
      summary_out << std::flush;
      std::cout << outputs::FormatEmit(*emit, result.solve.estimate,
                                       result.loaded.session.antenna_in_base, frames,
                                       result.loaded.session.scanner_z_m, &result.decided.decision,
                                       result.loaded.session.scanner_tilt)
                << std::flush;
    }
    return 0;
  } catch (const wallcal::io::InputError& error) {
    progress_line.Close();
    std::cerr << "calibrate: " << wallcal::io::EscapeControl(error.what()) << "\n";
    return 2;
  } catch (const std::exception& error) {
    progress_line.Close();
    std::cerr << "calibrate: internal error: " << wallcal::io::EscapeControl(error.what()) << "\n";
    return 3;
  }
}
