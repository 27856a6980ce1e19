// SPDX-License-Identifier: Apache-2.0
// wallcal characterise: measure the scanner itself (range model, noise, quantum, incidence limit,
// mixed pixels, warm-up drift) on a wall session and write its preset. Argument parsing and
// wiring only; the work is characterise/.

#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "characterise/characterisation.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "io/output_file.h"

namespace wallcal::apps {

const CommandHelp& CharacteriseHelp() {
  static const CommandHelp help{
      "characterise",
      "measure the scanner's range model and noise on a wall session; write its preset",
      {"SESSION [--scanner ID] [--mount OFFSETS.yaml] [--output PRESET.yaml] [--report DIR] "
       "[--config FILE] [--threads N]"},
      "Measures the laser scanner on a wall session (docs/field-guide.md, \"Characterising the\n"
      "scanner\"): every beam that hits the surveyed wall has a true range from the vehicle's pose and\n"
      "the mount, so the session fits the range model z = n*true + c of Ye & Borenstein 2002 and\n"
      "Okubo, Ye & Borenstein 2009, with sigma for every number: the range correction k, b\n"
      "(y = k*z + b), the noise sigma and its growth with range and incidence, the range quantum, the\n"
      "incidence limit, the mixed-pixel rate at the wall's ends and the warm-up drift over time.\n",
      {
          SessionArgument(),
          {"--scanner", "", "ID", ValueKind::kWord, {},
           "a session with scanners: the scanner to characterise (its log, model and\n"
           "mount_guess; --mount then takes an earlier one-scanner offsets.yaml)"},
          {"--mount", "", "FILE", ValueKind::kFile, {},
           "an earlier calibration's offsets.yaml: its scanner_mount (and covariance,\n"
           "when given) is used; without it the mount is estimated jointly"},
          {"--output", "", "FILE", ValueKind::kFile, {},
           "the measured preset (default: SESSION_DIR/scanners/MODEL_measured.yaml,\n"
           "which calibrate finds as scanner.model: MODEL_measured). Only a regular\n"
           "file or a new path is replaced, never an input"},
          {"--report", "", "DIR", ValueKind::kFolder, {},
           "also write SVG plots of the range error against true range, incidence\n"
           "and time into DIR"},
          CalibrationConfigOption(),
          {"--threads", "", "N", ValueKind::kWord, {},
           "threads for the wall detection (default: every core)"},
          HelpOption(),
          VersionOption(),
      },
      "",
      "0 preset written; 1 a parameter not determined (the reason names it and what to\n"
      "collect); 2 bad input or usage; 3 an internal error (a bug: please report it).\n"};
  return help;
}

}  // namespace wallcal::apps

int wallcal::apps::RunCharacterise(int argc, char** argv) {
  namespace fs = std::filesystem;
  wallcal::characterise::CharacteriseRequest request;
  std::string output, report_dir;
  request.command_line.push_back("wallcal");
  for (int i = 0; i < argc; ++i) request.command_line.push_back(argv[i]);
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (wallcal::apps::PrintHelpOrVersion(arg, wallcal::apps::CharacteriseHelp(), std::cout)) {
      return 0;
    } else if (arg == "--mount" || arg == "--output" || arg == "--report" || arg == "--config" ||
               arg == "--threads" || arg == "--scanner") {
      if (i + 1 >= argc) return UsageError(CharacteriseHelp(), arg + " needs a value");
      const std::string v = argv[++i];
      if (v.empty()) return UsageError(CharacteriseHelp(), arg + " needs a non-empty value");
      if (arg == "--mount") request.mount_path = v;
      if (arg == "--scanner") request.scanner_id = v;
      if (arg == "--output") output = v;
      if (arg == "--report") report_dir = v;
      if (arg == "--config") request.config_path = v;
      if (arg == "--threads") {
        char* end = nullptr;
        const long n = std::strtol(v.c_str(), &end, 10);
        if (*end != '\0' || n < 1 || n > 1024) {
          return UsageError(CharacteriseHelp(), "--threads: expected 1..1024, got '" + v + "'");
        }
        request.threads = static_cast<int>(n);
      }
    } else if (!arg.empty() && arg[0] == '-') {
      return UsageError(CharacteriseHelp(), "unknown option '" + arg + "'");
    } else if (request.session_path.empty()) {
      request.session_path = arg;
    } else {
      return UsageError(CharacteriseHelp(), "more than one SESSION given ('" +
                                                request.session_path + "', '" + arg + "')");
    }
  }
  if (request.session_path.empty()) return UsageError(CharacteriseHelp(), "SESSION is required");
  return wallcal::apps::ExitStatusOf(CharacteriseHelp(), [&] {
    const std::vector<std::string> inputs = {request.session_path, request.mount_path,
                                             request.config_path};
    if (!output.empty()) {
      if (wallcal::io::IsStdoutPath(output)) {
        return UsageError(CharacteriseHelp(), "--output: a file is needed, not -");
      }
      wallcal::io::CheckOutputPath("--output", output, inputs);
      request.preset_name = fs::path(output).stem().string();
    }
    if (!report_dir.empty()) wallcal::io::CheckOutputFolder("--report", report_dir);

    const wallcal::characterise::Characterisation result =
        wallcal::characterise::Characterise(request);
    std::cout << wallcal::characterise::Summary(result);
    if (!report_dir.empty()) {
      fs::create_directories(report_dir);
      for (const auto& [name, svg] : wallcal::characterise::Plots(result)) {
        wallcal::io::WriteFileAtomically((fs::path(report_dir) / name).string(), svg);
      }
      std::cout << "characterise: plots written to " << report_dir << "\n";
    }
    if (!result.ok()) return 1;
    if (output.empty()) {
      const fs::path dir = fs::path(result.calibration.loaded.session.dir) / "scanners";
      fs::create_directories(dir);
      output = (dir / (result.preset.name + ".yaml")).string();
      wallcal::io::CheckOutputPath("--output", output, inputs);
    }
    const std::vector<std::string> header = {
        "Measured by wallcal characterise on session '" + result.calibration.loaded.session.name +
            "'.",
        "Use it with scanner.model: " + result.preset.name +
            " (calibrate finds it in the session's scanners/ folder or a preset folder).",
        "sigma of k, b and the noise: see the summary printed with it."};
    wallcal::io::WriteFileAtomically(output,
                                     wallcal::io::FormatScannerPreset(result.preset, header));
    std::cout << "characterise: preset written to " << output << "\n";
    return 0;
  });
}
