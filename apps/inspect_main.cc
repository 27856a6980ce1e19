// inspect: the pre-flight check of a session or a log file, and CSV dumps of decoded records.
// Argument parsing and error reporting only; the work is in preflight/.

#include <exception>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "io/types.h"
#include "io/version.h"
#include "preflight/inspect.h"

namespace {

int Run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  static const char* kUsage =
      R"(usage: inspect PATH [--dump gnss|heading|scans] [--config FILE]

The pre-flight check of a wall session: run it before leaving the site.

  PATH            a session (session.yaml or its folder), or one log file: NMEA (GNSS,
                  heading) or CARMEN (scans, plain or gzip), recognised by content
  --dump KIND     write the decoded records as CSV on stdout instead of the report:
                    gnss     time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,
                             sigma_lat_m,sigma_lon_m,line
                    heading  time_s,heading_deg,line
                    scans    time_s,beams,valid,min_range_m,max_range_m,line
                  (on a session: that log of the session)
  --config FILE   calibrate options used for the detection and the checks (as calibrate)
  --help          this text
  --version       the version

On a session: each log's time span, rate, gaps and their overlap; GNSS fix qualities and time
RTK fixed; survey control residuals; stations and how well the wall was detected at each; the
headings at which the wall was seen; and a verdict: enough data for a calibration, or what is
missing. On one log: its time span, rate, gaps, counts and skipped lines.
Exit status: 0 report or dump written (whatever the verdict); 2 unusable input or bad usage
(one line on stderr naming the file, the line and what was expected).
)";
  std::string path, dump, config;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& arg = args[i];
    if (arg == "--help" || arg == "-h") {
      out << kUsage;
      return 0;
    } else if (arg == "--version") {
      out << "wallcal inspect " << wallcal::io::kToolVersion << "\n";
      return 0;
    } else if (arg == "--dump" || arg == "--config") {
      if (i + 1 >= args.size()) {
        err << "inspect: " << arg << " needs a value (run 'inspect --help' for usage)\n";
        return 2;
      }
      (arg == "--dump" ? dump : config) = args[++i];
    } else if (!arg.empty() && arg[0] == '-') {
      err << "inspect: unknown option '" << arg << "' (run 'inspect --help' for usage)\n";
      return 2;
    } else if (path.empty()) {
      path = arg;
    } else {
      err << "inspect: more than one PATH given ('" << path << "' and '" << arg << "')\n";
      return 2;
    }
  }
  if (path.empty()) {
    err << "inspect: no PATH given (run 'inspect --help' for usage)\n";
    return 2;
  }
  try {
    if (!dump.empty()) {
      wallcal::preflight::DumpKind kind;
      if (dump == "gnss") {
        kind = wallcal::preflight::DumpKind::kGnss;
      } else if (dump == "heading") {
        kind = wallcal::preflight::DumpKind::kHeading;
      } else if (dump == "scans") {
        kind = wallcal::preflight::DumpKind::kScans;
      } else {
        err << "inspect: --dump: unknown kind '" << dump << "'; expected gnss, heading or scans\n";
        return 2;
      }
      // Build the whole dump first: an error half-way leaves stdout without half a table.
      std::ostringstream table;
      wallcal::preflight::Dump(path, kind, table);
      out << table.str();
      return 0;
    }
    if (wallcal::preflight::IsSessionPath(path)) {
      out << wallcal::preflight::InspectSession(path, config).report;
    } else {
      out << wallcal::preflight::InspectLogFile(path);
    }
    return 0;
  } catch (const wallcal::io::InputError& error) {
    err << "inspect: " << error.what() << "\n";
    return 2;
  } catch (const std::exception& error) {
    err << "inspect: internal error: " << error.what() << "\n";
    return 3;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return Run(args, std::cout, std::cerr);
}
