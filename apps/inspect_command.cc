// SPDX-License-Identifier: Apache-2.0
// wallcal inspect: the pre-flight check of a session or a log file, and CSV dumps of decoded records.
// Argument parsing and error reporting only; the work is in preflight/.

#include <exception>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "io/config/session_reader.h"
#include "io/output_file.h"
#include "io/survey/survey_reader.h"
#include "io/types.h"
#include "preflight/inspect.h"
#include "recording/recording.h"

namespace wallcal::apps {

const CommandHelp& InspectHelp() {
  static const CommandHelp help{
      "inspect",
      "check a session, a log or a recording before leaving the site; dump decoded records",
      {"PATH [--dump gnss|heading|attitude|scans|survey] [--topic NAME] [--scanner ID] "
       "[--config FILE]",
       "RECORDING --suggest-session"},
      "The pre-flight check of a wall session: run it before leaving the site.\n",
      {
          {"PATH", "", "", ValueKind::kPath, {},
           "a session (session.yaml or its folder), one log file: NMEA (GNSS,\n"
           "heading) or CARMEN (scans, plain or gzip), a robot recording (ROS 1 .bag,\n"
           "MCAP, rosbag2 .db3 or folder), or a survey file (CSV with a header, or\n"
           "Leica GSI); recognised by content"},
          {"--dump", "", "KIND", ValueKind::kChoice,
           {"gnss", "heading", "attitude", "scans", "survey"},
           "write the decoded records as CSV on stdout instead of the report:\n"
           "  gnss     time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,\n"
           "           sigma_lat_m,sigma_lon_m,line\n"
           "  heading  time_s,heading_deg,line\n"
           "  attitude time_s,roll_deg,pitch_deg,roll_sigma_deg,pitch_sigma_deg,line\n"
           "           (roll + right side down, pitch + nose up)\n"
           "  scans    time_s,beams,valid,min_range_m,max_range_m,line\n"
           "  survey   id,x_m,y_m,z_m,code (one row per observation; x east, y north)\n"
           "(on a session: that log or survey file of the session, a scanners:\n"
           "session's scans those of --scanner; on a recording: --topic's)"},
          {"--topic", "", "NAME", ValueKind::kWord, {},
           "the recording topic to dump (needed when several topics fit)"},
          {"--scanner", "", "ID", ValueKind::kWord, {},
           "the scanner of a session with scanners: whose scans --dump scans\n"
           "writes"},
          {"--suggest-session", "", "", ValueKind::kNone, {},
           "print a ready-to-edit session.yaml for the recording, the topics chosen\n"
           "by type (and why, when several fit)"},
          {"--config", "", "FILE", ValueKind::kFile, {},
           "calibrate options used for the detection and the checks (as calibrate)"},
          HelpOption(),
          VersionOption(),
      },
      "On a session: each log's time span, rate, gaps and their overlap; GNSS fix qualities and time\n"
      "RTK fixed; survey control residuals; stations and how well the wall was detected at each; the\n"
      "headings at which the wall was seen; and a verdict: enough data for a calibration, or what is\n"
      "missing. On one log: its time span, rate, gaps, counts and skipped lines. On a recording: every\n"
      "topic's type, count, rate, span and gaps, and the statistics of the types wallcal reads. On a\n"
      "survey file: its format, observations and points, codes and extents.\n",
      "0 report or dump written (whatever the verdict); 2 unusable input or bad usage\n"
      "(one line on stderr naming the file, the line and what was expected).\n"};
  return help;
}

}  // namespace wallcal::apps

namespace {

int Usage(const std::string& message, std::ostream& err) {
  return wallcal::apps::UsageError(wallcal::apps::InspectHelp(), message, err);
}

int Run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  std::string path, dump, config, topic, scanner;
  bool suggest = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (wallcal::apps::PrintHelpOrVersion(arg, wallcal::apps::InspectHelp(), out)) {
      return 0;
    } else if (arg == "--suggest-session") {
      suggest = true;
    } else if (arg == "--dump" || arg == "--config" || arg == "--topic" || arg == "--scanner") {
      if (i + 1 >= args.size()) return Usage(arg + " needs a value", err);
      (arg == "--dump"      ? dump
       : arg == "--topic"   ? topic
       : arg == "--scanner" ? scanner
                            : config) = args[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      return Usage("unknown option '" + arg + "'", err);
    } else if (path.empty()) {
      path = arg;
    } else {
      return Usage("more than one PATH given ('" + path + "' and '" + arg + "')", err);
    }
  }
  if (path.empty()) return Usage("no PATH given", err);
  return wallcal::apps::ExitStatusOf(wallcal::apps::InspectHelp(), [&] {
    const bool recording = wallcal::recording::IsRecording(path);
    if (suggest) {
      if (!recording) {
        err << "inspect: --suggest-session needs a robot recording (ROS 1 .bag, MCAP, rosbag2); '"
            << path << "' is not one\n";
        return 2;
      }
      out << wallcal::preflight::SuggestSession(path);
      return 0;
    }
    if (!topic.empty() && !recording) {
      err << "inspect: --topic applies to a robot recording; '" << path << "' is not one\n";
      return 2;
    }
    if (!scanner.empty() && recording) {
      return Usage("--scanner names a scanner of a session; on a recording give --topic", err);
    }
    if (!scanner.empty() && dump != "scans") {
      return Usage("--scanner applies to --dump scans (the GNSS, heading and survey files are "
                   "the session's)", err);
    }
    if (dump == "survey") {
      // Every observation as read (not combined): docs/survey-files.md. On a session: its
      // survey file, read with its survey.columns.
      if (wallcal::preflight::IsSessionPath(path)) {
        const wallcal::io::SessionSpec session = wallcal::io::ReadSession(path);
        out << wallcal::io::FormatSurveyDumpCsv(
            wallcal::io::ReadSurvey(session.survey_points, session.survey_columns));
      } else {
        out << wallcal::io::FormatSurveyDumpCsv(wallcal::io::ReadSurvey(path));
      }
      return 0;
    }
    if (!dump.empty()) {
      wallcal::preflight::DumpKind kind;
      if (dump == "gnss") {
        kind = wallcal::preflight::DumpKind::kGnss;
      } else if (dump == "heading") {
        kind = wallcal::preflight::DumpKind::kHeading;
      } else if (dump == "attitude") {
        kind = wallcal::preflight::DumpKind::kAttitude;
      } else if (dump == "scans") {
        kind = wallcal::preflight::DumpKind::kScans;
      } else {
        err << "inspect: --dump: unknown kind '" << dump
            << "'; expected gnss, heading, attitude, scans or survey\n";
        return 2;
      }
      // Build the whole dump first: an error half-way leaves stdout without half a table.
      std::ostringstream table;
      if (recording) {
        wallcal::preflight::DumpRecording(path, kind, topic, table);
      } else {
        wallcal::preflight::Dump(path, kind, table, scanner);
      }
      out << table.str();
      return 0;
    }
    if (recording) {
      out << wallcal::preflight::InspectRecording(path);
    } else if (wallcal::preflight::IsSessionPath(path)) {
      out << wallcal::preflight::InspectSession(path, config).report;
    } else if (wallcal::io::SniffSurveyFile(path).format != wallcal::io::SurveyFormat::kNone) {
      out << wallcal::preflight::InspectSurveyFile(path);
    } else {
      out << wallcal::preflight::InspectLogFile(path);
    }
    return 0;
  }, err);
}

}  // namespace

int wallcal::apps::RunInspect(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  // Names and text from the files never reach the terminal raw (control characters escaped).
  wallcal::io::ControlEscapingStreamBuf out_buffer(std::cout.rdbuf());
  wallcal::io::ControlEscapingStreamBuf err_buffer(std::cerr.rdbuf());
  std::ostream out(&out_buffer);
  std::ostream err(&err_buffer);
  const int status = Run(args, out, err);
  out.flush();
  err.flush();
  return status;
}
