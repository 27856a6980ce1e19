// SPDX-License-Identifier: Apache-2.0
// Bad input never crashes and never half-writes.
//
// Each case starts from a good simulated session (generated once per run with the shipped
// configs/simulate/lms291_sapporo.yaml, seed 3), breaks it (files stored under
// test/bad_sessions/<case>/ are copied over the session; a mutation edits it), puts a known
// offsets.yaml beside session.yaml, and runs the real `calibrate` program on it. Checked:
//   - the exit status (2 bad input, 1 the data cannot determine the mount, 0 a counted warning),
//     never a signal and never a sanitizer report;
//   - the message: every expected fragment (file name, line, what was expected) on stderr for a
//     failure, on stdout and in offsets.yaml's warnings for a counted warning;
//   - on failure the old offsets.yaml is byte-for-byte unchanged and no temporary file is left;
//   - `inspect` on the same session exits 0, 1 or 2, never by a signal.

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "pipeline/calibration.h"
#include "pipeline/config_dirs.h"
#include "calib/pose_samples.h"
#include "outputs/offsets_document.h"
#include "outputs/summary.h"
#include "sim/simulated_session.h"
#include "sim/simulator.h"
#include "io/config/session_reader.h"
#include "io/writers/writers.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using namespace testing_support;  // NOLINT: the test helpers of test/support

const std::string kSourceDir = WALLCAL_SOURCE_DIR;
const std::string kSentinel = "# an offsets.yaml from an earlier, good run: must survive\nx: 1\n";

std::vector<std::string> ReadLines(const fs::path& path) {
  std::vector<std::string> lines;
  std::istringstream in(ReadFile(path));
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void WriteLines(const fs::path& path, const std::vector<std::string>& lines) {
  std::string text;
  for (const std::string& line : lines) text += line + "\n";
  WriteFile(path, text);
}

// "<prefix> $<body>*<checksum>": a sentence with a correct checksum.
std::string Sentence(const std::string& prefix, const std::string& body) {
  return prefix + " $" + body + "*" + io::NmeaChecksum(body);
}

// Adds `shift_s` to the logger-time prefix of every line of an NMEA log.
void ShiftNmeaTimes(const fs::path& path, double shift_s) {
  std::vector<std::string> lines = ReadLines(path);
  for (std::string& line : lines) {
    const size_t space = line.find(' ');
    if (space == std::string::npos) continue;
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.3f", std::stod(line.substr(0, space)) + shift_s);
    line = stamp + line.substr(space);
  }
  WriteLines(path, lines);
}

// Line index (0-based) of the n-th (0-based) line that starts with `start`.
size_t NthLine(const std::vector<std::string>& lines, const std::string& start, int n) {
  for (size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].rfind(start, 0) == 0 && n-- == 0) return i;
  }
  ADD_FAILURE() << "no line " << n << " starting with " << start;
  return 0;
}

// The range tokens of a RAWLASER1 line: tokens 9 .. 9 + n - 1.
std::string EditRange(const std::string& line, int beam, const std::string& value) {
  std::vector<std::string> tokens;
  std::istringstream in(line);
  for (std::string token; in >> token;) tokens.push_back(token);
  tokens[9 + static_cast<size_t>(beam)] = value;
  std::string out;
  for (const std::string& token : tokens) out += (out.empty() ? "" : " ") + token;
  return out;
}

using RunResult = testing_support::ProgramRun;

// A sanitizer report anywhere in the output is a failure even when the exit status looks right.
void ExpectNoSanitizerReport(const RunResult& run, const std::string& what) {
  for (const char* marker : {"AddressSanitizer", "LeakSanitizer", "runtime error:",
                             "UndefinedBehaviorSanitizer"}) {
    EXPECT_EQ(run.err.find(marker), std::string::npos) << what << ": " << run.err;
  }
}

struct BadCase {
  BadCase(std::string name_, std::function<void(const std::filesystem::path&)> mutate_,
          int exit_code_, std::vector<std::string> fragments_, bool one_heading_base_ = false,
          std::string extra_args_ = "")
      : name(std::move(name_)),
        mutate(std::move(mutate_)),
        exit_code(exit_code_),
        fragments(std::move(fragments_)),
        one_heading_base(one_heading_base_),
        extra_args(std::move(extra_args_)) {}
  std::string name;
  // Breaks the session in `dir` (after the stored files of test/bad_sessions/<name>/ are copied).
  std::function<void(const fs::path& dir)> mutate;
  int exit_code;                       // 2 bad input, 1 geometry, 0 counted warning
  std::vector<std::string> fragments;  // all must appear in the message (or warnings)
  bool one_heading_base = false;       // start from the session driven at one heading only
  std::string extra_args;              // more calibrate arguments; "{dir}" is the session folder
};

std::ostream& operator<<(std::ostream& os, const BadCase& c) { return os << c.name; }

// The good sessions every case starts from, generated once per process.
class BadSessionsTest : public ::testing::TestWithParam<BadCase> {
 protected:
  static void SetUpTestSuite() {
    char pattern[] = "/tmp/wallcal-bad-sessions-XXXXXX";
    ASSERT_NE(::mkdtemp(pattern), nullptr);
    root_ = pattern;
    sim::SimulationConfig config =
        sim::ReadSimulationConfig(kSourceDir + "/configs/simulate/lms291_sapporo.yaml");
    sim::WriteSimulatedSession(config, 3, (root_ / "base").string());
    // One heading only: every station faces the wall square on.
    config.heading_spread_rad = 0.0;
    config.num_stations = 4;
    sim::WriteSimulatedSession(config, 3, (root_ / "one_heading").string());
  }
  static void TearDownTestSuite() {
    std::error_code ignored;
    fs::remove_all(root_, ignored);
  }
  static fs::path root_;
};
fs::path BadSessionsTest::root_;

TEST_P(BadSessionsTest, FailsCleanlyOrWarns) {
  const BadCase& bad = GetParam();
  const fs::path dir = root_ / bad.name;
  fs::remove_all(dir);
  fs::copy(root_ / (bad.one_heading_base ? "one_heading" : "base"), dir,
           fs::copy_options::recursive);
  const fs::path stored = fs::path(kSourceDir) / "test" / "bad_sessions" / bad.name;
  if (fs::is_directory(stored)) {
    for (const auto& entry : fs::directory_iterator(stored)) {
      fs::copy_file(entry.path(), dir / entry.path().filename(),
                    fs::copy_options::overwrite_existing);
    }
  }
  if (bad.mutate) bad.mutate(dir);
  const fs::path offsets = dir / "offsets.yaml";
  WriteFile(offsets, kSentinel);

  std::string args = dir.string() + " --quiet " + bad.extra_args;
  for (size_t at; (at = args.find("{dir}")) != std::string::npos;) args.replace(at, 5, dir.string());
  const RunResult run = testing_support::RunWallcalLine("calibrate", args);
  ASSERT_TRUE(run.exited()) << bad.name << ": calibrate killed by signal " << run.signal << "\n"
                          << run.err;
  ExpectNoSanitizerReport(run, bad.name + ": calibrate");
  EXPECT_EQ(run.exit_code, bad.exit_code) << "stdout:\n" << run.out << "stderr:\n" << run.err;

  if (bad.exit_code == 0) {
    const std::string written = ReadFile(offsets);
    EXPECT_NE(written, kSentinel) << "offsets.yaml not written";
    for (const std::string& fragment : bad.fragments) {
      EXPECT_NE(run.out.find(fragment), std::string::npos)
          << "'" << fragment << "' not in the summary:\n" << run.out;
      EXPECT_NE(written.find(fragment), std::string::npos)
          << "'" << fragment << "' not in offsets.yaml:\n" << written;
    }
  } else {
    // One line on stderr naming what is wrong.
    for (const std::string& fragment : bad.fragments) {
      EXPECT_NE(run.err.find(fragment), std::string::npos)
          << "'" << fragment << "' not in stderr:\n" << run.err;
    }
    EXPECT_EQ(ReadFile(offsets), kSentinel) << "an existing offsets.yaml was replaced";
  }
  for (const auto& entry : fs::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos)
        << "temporary file left behind: " << entry.path();
  }

  // The pre-flight check must survive the same session.
  const RunResult inspect = testing_support::RunWallcal({"inspect", dir.string()});
  ASSERT_TRUE(inspect.exited()) << bad.name << ": inspect killed by signal " << inspect.signal
                              << "\n" << inspect.err;
  ExpectNoSanitizerReport(inspect, bad.name + ": inspect");
  EXPECT_GE(inspect.exit_code, 0);
  EXPECT_LE(inspect.exit_code, 2) << inspect.err;
  fs::remove_all(dir);
}

// Appends `lines` to a file.
void Append(const fs::path& path, const std::vector<std::string>& lines) {
  std::vector<std::string> all = ReadLines(path);
  all.insert(all.end(), lines.begin(), lines.end());
  WriteLines(path, all);
}

const std::vector<BadCase> kCases = {
    // --- missing files and keys, YAML ------------------------------------------------------
    {"session_missing", [](const fs::path& d) { fs::remove(d / "session.yaml"); }, 2,
     {"no session.yaml here", "expected a session.yaml or a folder holding one"}},
    {"session_truncated", nullptr, 2, {"session.yaml:", "YAML syntax error"}},
    {"session_yaml_syntax", nullptr, 2, {"session.yaml:4:", "YAML syntax error"}},
    {"session_missing_key",
     [](const fs::path& d) {
       ReplaceInFile(d / "session.yaml", "gnss:\n  log: gnss.nmea\n  min_fix_quality: 4\n", "");
     },
     2, {"session.yaml:1:", "gnss is missing", "expected a map with log"}},
    {"session_unknown_key",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "  time_offset_s: 0", "  time_ofset_s: 0"); },
     2, {"session.yaml:5:", "unknown key 'scanner.time_ofset_s'", "time_offset_s"}},
    {"session_missing_control_key",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "{id: C2, lat:", "{id: C2, lag:"); },
     2, {"session.yaml:16:", "unknown key 'survey.control[1].lag'"}},
    {"unknown_scanner_preset",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "sick_lms291", "sick_lms999"); }, 2,
     {"unknown scanner model 'sick_lms999'", "available presets:", "sick_lms291"}},
    {"missing_scan_log", [](const fs::path& d) { fs::remove(d / "scans.clf"); }, 2,
     {"scans.clf: cannot open the scan log"}},
    {"missing_gnss_log", [](const fs::path& d) { fs::remove(d / "gnss.nmea"); }, 2,
     {"gnss.nmea: cannot open the NMEA log"}},
    {"missing_heading_log", [](const fs::path& d) { fs::remove(d / "heading.nmea"); }, 2,
     {"heading.nmea: cannot open the NMEA log"}},
    {"missing_survey", [](const fs::path& d) { fs::remove(d / "survey.csv"); }, 2,
     {"survey.csv: cannot open the survey file"}},
    {"options_unknown_key",
     [](const fs::path& d) { WriteFile(d / "options.yaml", "detector:\n  min_inlers: 5\n"); }, 2,
     {"options.yaml:2:", "unknown key 'detector.min_inlers'", "min_inliers"}, false,
     "--config {dir}/options.yaml"},
    {"options_bad_value",
     [](const fs::path& d) { WriteFile(d / "options.yaml", "solver:\n  max_iterations: many\n"); },
     2, {"options.yaml:2:", "solver.max_iterations: expected an integer, got 'many'"}, false,
     "--config {dir}/options.yaml"},

    // --- survey CSV ---------------------------------------------------------------------------
    {"survey_non_numeric", nullptr, 2,
     {"survey.csv:4:", "column 2 (easting) is not a finite number", "expected a number in metres"}},
    {"survey_nan", nullptr, 2,
     {"survey.csv:4:", "column 3 (northing) is not a finite number", "expected a number in metres"}},
    {"survey_truncated", nullptr, 2, {"survey.csv:4:", "3 fields; expected 5 as in the header"}},
    {"survey_no_header", nullptr, 2, {"survey.csv:", "no header"}},
    {"control_id_not_in_survey",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "{id: C2,", "{id: C9,"); }, 2,
     {"session.yaml:16:", "control point C9 is not in", "expected a survey point with id C9"}},
    {"wall_without_survey_points",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "code: WALL1}", "code: WALL9}"); }, 2,
     {"survey.csv: wall north_wall: no survey points with code WALL9",
      "the survey's codes are CTRL (2), WALL1 (62); expected at least 2"}},

    // --- NMEA logs: nothing usable -------------------------------------------------------------
    {"gnss_all_bad", nullptr, 2,
     {"gnss.nmea: fewer than 2 GGA fixes of accepted quality"}},
    {"gnss_empty", [](const fs::path& d) { WriteFile(d / "gnss.nmea", ""); }, 2,
     {"gnss.nmea: fewer than 2 GGA fixes", "found none"}},
    {"gnss_float_only",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "gnss.nmea");
       for (std::string& line : lines) {
         const size_t dollar = line.find('$');
         const size_t star = line.find('*');
         std::string body = line.substr(dollar + 1, star - dollar - 1);
         if (body.rfind("GNGGA", 0) == 0) {
           const size_t quality = body.find(",E,") + 3;
           body[quality] = '5';
         }
         line = Sentence(line.substr(0, dollar - 1), body);
       }
       WriteLines(d / "gnss.nmea", lines);
     },
     2, {"gnss.nmea: fewer than 2 GGA fixes", "min_fix_quality 4", "quality 5: 461"}},
    {"heading_all_bad", nullptr, 2, {"heading.nmea: fewer than 2 usable HDT/THS headings"}},
    {"logs_do_not_overlap",
     [](const fs::path& d) { ShiftNmeaTimes(d / "heading.nmea", 3600.0); }, 2,
     {"gnss.nmea", "heading.nmea", "do not overlap in time"}},

    // --- CARMEN scan log: nothing usable ---------------------------------------------------
    {"scans_all_bad", nullptr, 2,
     {"scans.clf: no scan records",
      "RAWLASER1: beam count disagrees with the line: 1, first at line 2",
      "RAWLASER1: negative or non-finite range: 2, first at line 3",
      "RAWLASER1: non-numeric field: 1, first at line 5",
      "RAWLASER1: non-finite timestamp: 1, first at line 6",
      "RAWLASER1: line cut off at end of file: 1, first at line 7",
      "expected CARMEN RAWLASER1/ROBOTLASER1/FLASER lines"}},
    {"scans_truncated_file",
     [](const fs::path& d) {
       std::string text = ReadFile(d / "scans.clf");
       WriteFile(d / "scans.clf", text.substr(0, 1000));  // cut inside the first scan
     },
     2, {"scans.clf: no scan records", "line cut off at end of file: 1, first at line 2"}},
    {"scans_empty", [](const fs::path& d) { WriteFile(d / "scans.clf", ""); }, 2,
     {"scans.clf: no scan records"}},

    {"scans_outside_log_time",
     [](const fs::path& d) { ReplaceInFile(d / "session.yaml", "time_offset_s: 0", "time_offset_s: 7200"); },
     2, {"scans.clf", "do not overlap the GNSS and heading logs", "scanner.time_offset_s"}},

    // --- geometry the data cannot determine ------------------------------------------------
    {"wall_never_seen",
     [](const fs::path& d) {
       // The wall the session names is surveyed 300 m away, out of the scanner's 80 m reach:
       // a survey mistake, said before any scan is read.
       Append(d / "survey.csv", {"F1,300.0,400.0,0.5,FAR", "F2,310.0,400.0,0.5,FAR",
                                 "F3,320.0,400.0,0.5,FAR"});
       ReplaceInFile(d / "session.yaml", "code: WALL1}", "code: FAR}");
     },
     2, {"session.yaml", "the GNSS track passes no closer than", "control points"}},
    {"one_heading_only", nullptr, 1,
     {"mount not determined", "add stations turned"}, /*one_heading_base=*/true},

    // --- a few bad lines in otherwise good logs: counted warnings, offsets written --------------
    {"gnss_few_bad_lines",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "gnss.nmea");
       // Line 11: bad checksum; line 21: a GGA whose latitude is not a number; line 31: empty
       // field; line 41: cut off without its checksum.
       std::string& bad_sum = lines[10];
       bad_sum.replace(bad_sum.size() - 2, 2, bad_sum.substr(bad_sum.size() - 2) == "00" ? "01" : "00");
       const std::string prefix = lines[20].substr(0, lines[20].find(' '));
       lines[20] = Sentence(prefix, "GNGGA,063203.00,43O4.2741527,N,14120.3918034,E,4,14,0.7,72.0,M,0.000,M,,");
       lines[30] = Sentence(lines[30].substr(0, lines[30].find(' ')),
                            "GNGGA,063203.50,,N,14120.3918034,E,4,14,0.7,72.0,M,0.000,M,,");
       lines[40] = lines[40].substr(0, 40);
       WriteLines(d / "gnss.nmea", lines);
     },
     0,
     // The GST lines of the four dropped GGA are counted too.
     {"gnss.nmea: 8 lines skipped", "GST without its GGA: 4", "bad checksum: 1, first at line 11",
      "bad field: 1, first at line 21", "empty field: 1, first at line 31",
      "no checksum: 1, first at line 41"}},
    {"heading_times_backwards_and_repeated",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "heading.nmea");
       lines[100] = lines[99];   // repeated
       std::swap(lines[200], lines[201]);  // goes backwards at line 202
       WriteLines(d / "heading.nmea", lines);
     },
     0, {"heading.nmea: 2 lines skipped", "time not increasing: 2, first at line 101"}},
    {"scans_times_backwards_and_repeated",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "scans.clf");  // line 1 is a comment
       std::swap(lines[30], lines[31]);  // goes backwards at line 32
       lines[50] = lines[49];             // repeated at line 51
       WriteLines(d / "scans.clf", lines);
     },
     0, {"scans.clf: 2 scans not later than the scan before them (first at line 32)"}},
    {"heading_nan_and_empty",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "heading.nmea");
       auto prefix = [&](size_t i) { return lines[i].substr(0, lines[i].find(' ')); };
       lines[50] = Sentence(prefix(50), "HEHDT,nan,T");
       lines[60] = Sentence(prefix(60), "HEHDT,,T");
       lines[70] = Sentence(prefix(70), "HEHDT,-12.0,T");
       WriteLines(d / "heading.nmea", lines);
     },
     0,
     {"heading.nmea: 3 lines skipped", "bad field: 1, first at line 51",
      "empty field: 1, first at line 61", "heading out of range: 1, first at line 71"}},
    {"scans_few_bad_lines",
     [](const fs::path& d) {
       std::vector<std::string> lines = ReadLines(d / "scans.clf");
       const size_t a = NthLine(lines, "RAWLASER1", 10);
       const size_t b = NthLine(lines, "RAWLASER1", 20);
       const size_t c = NthLine(lines, "RAWLASER1", 30);
       const size_t e = NthLine(lines, "RAWLASER1", 40);
       lines[a] = EditRange(lines[a], 90, "nan");
       lines[b] = EditRange(lines[b], 10, "-0.500");
       lines[c] = EditRange(lines[c], 100, "1O.000");
       lines[e].replace(lines[e].find(" 181 "), 5, " 180 ");  // beam count disagrees
       std::string text;
       for (const std::string& line : lines) text += line + "\n";
       text.resize(text.size() - 500);  // the logger was killed mid-line
       WriteFile(d / "scans.clf", text);
     },
     0,
     {"scans.clf: 5 lines skipped", "RAWLASER1: negative or non-finite range: 2, first at line 12",
      "RAWLASER1: non-numeric field: 1, first at line 32",
      "RAWLASER1: beam count disagrees with the line: 1, first at line 42",
      "RAWLASER1: line cut off at end of file: 1"}},
};

INSTANTIATE_TEST_SUITE_P(Corpus, BadSessionsTest, ::testing::ValuesIn(kCases),
                         [](const ::testing::TestParamInfo<BadCase>& param_info) {
                           return param_info.param.name;
                         });

}  // namespace
}  // namespace wallcal
