// SPDX-License-Identifier: Apache-2.0
// Hostile and mistaken input, at the program level: `calibrate` and `inspect` run as
// subprocesses (each under `timeout 60`, so a hang fails the test instead of the suite) on a copy
// of samples/lms291-sapporo broken one way per test. Checked: the exit code (never 3, never a
// signal), the message (file, line, what was found in words) and which files were written or
// left alone. One test per finding of the hostile-input run, and for what held.

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "io/input_file.h"
#include "io/writers/writers.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "test/support/expect_text.h"
#include "test/support/program_runner.h"
#include "test/support/sample_session.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using namespace testing_support;  // NOLINT: the test helpers of test/support

// The program under test (test/support/program_runner.h: WALLCAL_PROGRAMS_DIR runs the same
// tests against another build, e.g. an older main, to see each test fail there).
const std::string kWallcal = testing_support::WallcalPath();

std::string Quote(const std::string& text) { return testing_support::ShellQuote(text); }

struct Outcome {
  int status = -1;  // exit code; 137 when `timeout` killed it (a hang)
  std::string out, err;
};

// Runs `program args` (args already shell-quoted) in `dir` with a 60 s limit; ENV is a shell
// prefix of assignments ("LC_ALL=C").
Outcome RunIn(const fs::path& dir, const std::string& program, const std::string& args,
              const std::string& env = "") {
  testing_support::RunOptions options;
  options.cwd = dir.string();
  options.timeout_s = 60;
  const testing_support::ProgramRun run =
      testing_support::RunShell(env + " exec " + Quote(program) + " " + args, options);
  Outcome outcome;
  outcome.status = run.timed_out ? 137 : run.exit_code;
  outcome.out = run.out;
  outcome.err = run.err;
  return outcome;
}

class HostileInputTest : public testing_support::SampleSessionTest {
 protected:
  Outcome Calibrate(const std::string& args, const std::string& env = "") {
    return RunIn(session_, kWallcal, "calibrate " + args, env);
  }
  Outcome Inspect(const std::string& args) { return RunIn(session_, kWallcal, "inspect " + args); }
  // No temporary file of an atomic write is left in the session folder.
  void ExpectNoTempFiles() {
    for (const auto& entry : fs::directory_iterator(session_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
          << entry.path();
    }
  }
  // A GGA line with new fields 7 (satellites) and 8 (HDOP), checksum recomputed.
  static std::string Gga(const std::string& line, const std::string& satellites,
                         const std::string& hdop) {
    const size_t dollar = line.find('$');
    const size_t star = line.find('*');
    std::vector<std::string> fields;
    std::stringstream body(line.substr(dollar + 1, star - dollar - 1));
    for (std::string f; std::getline(body, f, ',');) fields.push_back(f);
    fields[7] = satellites;
    fields[8] = hdop;
    std::string text;
    for (size_t i = 0; i < fields.size(); ++i) text += (i ? "," : "") + fields[i];
    if (line.back() == ',') text += ",";
    return line.substr(0, dollar) + "$" + text + "*" + io::NmeaChecksum(text);
  }

};

// ---- 1. outputs that are devices, FIFOs or inputs ---------------------------------------

TEST_F(HostileInputTest, OutputOnAFifoIsRefusedAndTheFifoKept) {
  const fs::path fifo = root_ / "pipe";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0644), 0);
  const Outcome run = Calibrate(". --output " + Quote(fifo.string()));
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"FIFO"});
  EXPECT_TRUE(fs::is_fifo(fifo));
}

TEST_F(HostileInputTest, OutputOnADeviceNodeIsRefused) {
  // Our own node for /dev/null's device (never the real one): needs CAP_MKNOD.
  const fs::path node = root_ / "null";
  if (::mknod(node.c_str(), S_IFCHR | 0666, makedev(1, 3)) != 0) {
    GTEST_SKIP() << "cannot create a device node here (no CAP_MKNOD)";
  }
  const Outcome run = Calibrate(". --output " + Quote(node.string()));
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"character device"});
  EXPECT_TRUE(fs::is_character_file(node));
}

TEST_F(HostileInputTest, OutputNamingAnInputIsRefusedAndTheInputKept) {
  const std::string scans = ReadFile(session_ / "scans.clf");
  for (const char* input : {"scans.clf", "session.yaml", "survey.csv"}) {
    const Outcome run = Calibrate(std::string(". --output ") + input);
    testing_support::ExpectExitSaying(run.status, 2, run.err, {"input of this run"});
  }
  // Through a link to the input: compared by device and inode.
  fs::create_symlink(session_ / "gnss.nmea", root_ / "link.yaml");
  EXPECT_EQ(Calibrate(". --output " + Quote((root_ / "link.yaml").string())).status, 2);
  WriteFile(root_ / "options.yaml", "solver:\n  max_iterations: 50\n");
  const Outcome config = Calibrate(". --config ../options.yaml --output ../options.yaml");
  EXPECT_EQ(config.status, 2) << config.err;
  EXPECT_EQ(ReadFile(session_ / "scans.clf"), scans);
  EXPECT_EQ(ReadFile(root_ / "options.yaml"), "solver:\n  max_iterations: 50\n");
  EXPECT_FALSE(fs::exists(session_ / "offsets.yaml"));
}

// ---- 2. devices, FIFOs and bombs as inputs ----------------------------------------------

TEST_F(HostileInputTest, FifoAsScanLogIsRefusedWithoutHanging) {
  fs::remove(session_ / "scans.clf");
  ASSERT_EQ(::mkfifo((session_ / "scans.clf").c_str(), 0644), 0);
  const Outcome run = Calibrate(".");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"scans.clf: the scan log is a FIFO"});
  const Outcome inspect = Inspect(".");
  EXPECT_NE(inspect.status, 137);
  EXPECT_NE(inspect.status, 3);
  EXPECT_NE(inspect.out.find("FIFO"), std::string::npos) << inspect.out;
}

TEST_F(HostileInputTest, DevZeroAsGnssLogIsRefused) {
  ReplaceInFile(session_ / "session.yaml", "log: gnss.nmea", "log: /dev/zero");
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("/dev/zero: the NMEA log is a character device"), std::string::npos)
      << run.err;
  EXPECT_EQ(Inspect("/dev/urandom").status, 2);
}

TEST_F(HostileInputTest, GzipBombLineIsAnInputErrorNotACrash) {
  // A line longer than the line budget (lowered for the test: 1 MB) in a small .gz.
  gzFile gz = gzopen((session_ / "scans.clf").c_str(), "wb9");
  ASSERT_NE(gz, nullptr);
  const std::string block(1 << 20, 'x');
  for (int i = 0; i < 3; ++i) gzwrite(gz, block.data(), static_cast<unsigned>(block.size()));
  gzclose(gz);
  const Outcome run = Calibrate(".", "WALLCAL_MAX_LINE_BYTES=1000000");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("scans.clf:1: line longer than 1000000 bytes"), std::string::npos)
      << run.err;
}

// ---- 3. duplicate keys --------------------------------------------------------------------

TEST_F(HostileInputTest, DuplicateKeysAreRejectedWithBothLines) {
  std::string yaml = ReadFile(session_ / "session.yaml");
  WriteFile(session_ / "session.yaml", yaml + "scanner:\n  model: hokuyo_urg04lx\n  log: scans.clf\n");
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("session.yaml:19: key 'scanner' given twice in the same map (first at "
                         "line 2)"),
            std::string::npos)
      << run.err;
  WriteFile(session_ / "session.yaml", yaml);
  WriteFile(root_ / "options.yaml", "detector:\n  min_inliers: 10\ndetector:\n  min_inliers: 5\n");
  const Outcome config = Calibrate(". --config ../options.yaml");
  EXPECT_EQ(config.status, 2) << config.err;
  EXPECT_NE(config.err.find("options.yaml:3: key 'detector' given twice"), std::string::npos)
      << config.err;
}

// ---- 4. options that crashed ---------------------------------------------------------------

TEST_F(HostileInputTest, TinyHoughStepsAreRefusedWithKeyAndLine) {
  WriteFile(root_ / "rho.yaml", "detector:\n  hough_rho_step_m: 1e-9\n");
  const Outcome rho = Calibrate(". --config ../rho.yaml");
  EXPECT_EQ(rho.status, 2) << rho.err;
  EXPECT_NE(rho.err.find("rho.yaml:2: detector.hough_rho_step_m must be"), std::string::npos)
      << rho.err;
  WriteFile(root_ / "theta.yaml", "detector:\n  min_inliers: 10\n  hough_theta_step_deg: 1e-9\n");
  const Outcome theta = Calibrate(". --config ../theta.yaml");
  testing_support::ExpectExitSaying(theta.status, 2, theta.err, {
      "theta.yaml:3: detector.hough_theta_step_deg must be in [0.001, 10]"
  });
}

TEST_F(HostileInputTest, ConfigNamingAFolderIsAnInputError) {
  const Outcome run = Calibrate(". --config ..");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {
      "is a folder; expected a regular file"
  });
}

// ---- 5. file contents never leak into messages ----------------------------------------------

TEST_F(HostileInputTest, MessagesDescribeForeignFilesWithoutQuotingThem) {
  const std::string secret = "root:$6$SeCrEtHaSh:19000:0:99999:7:::\ndaemon:*:19000:0:99999:7:::\n";
  WriteFile(root_ / "shadow", secret);
  ReplaceInFile(session_ / "session.yaml", "points: survey.csv", "points: ../shadow");
  const Outcome survey = Calibrate(".");
  EXPECT_EQ(survey.status, 2) << survey.err;
  testing_support::ExpectLacks(survey.err, {"SeCrEt", "root"});
  const Outcome inspect = Inspect("../shadow");
  EXPECT_EQ(inspect.status, 2) << inspect.err;
  EXPECT_EQ((inspect.out + inspect.err).find("root"), std::string::npos) << inspect.err;
  EXPECT_NE(inspect.err.find("a line of"), std::string::npos) << inspect.err;
  // A scan log holding something else: its words are not listed.
  WriteFile(session_ / "scans.clf", "password hunter2\nRAWLASER1 broken\n");
  const Outcome scans = Inspect("scans.clf");
  EXPECT_EQ((scans.out + scans.err).find("password"), std::string::npos) << scans.out;
}

// ---- 6. a NUL byte in a scan line ----------------------------------------------------------

TEST_F(HostileInputTest, NulByteSkipsOnlyItsOwnLine) {
  std::string scans = ReadFile(session_ / "scans.clf");
  const Outcome before = Inspect("scans.clf");
  size_t line_start = 0;
  for (int line = 1; line < 5; ++line) line_start = scans.find('\n', line_start) + 1;
  scans.insert(line_start + 20, 1, '\0');  // inside line 5
  WriteFile(session_ / "scans.clf", scans);
  const Outcome run = Inspect("scans.clf");
  testing_support::ExpectExitSaying(run.status, 0, run.out, {
      "line with a NUL byte: 1, first at line 5"
  });
  // The same number of lines as the run without the NUL byte: nothing was swallowed.
  const auto lines = [](const std::string& text) {
    const size_t at = text.find(" lines)");
    const size_t open = text.rfind(", ", at);
    return text.substr(open + 2, at - open - 2);
  };
  EXPECT_EQ(lines(run.out), lines(before.out)) << run.out;
}

// ---- 7. a BOM at the top of an NMEA log ------------------------------------------------------

TEST_F(HostileInputTest, BomAtTopOfNmeaLogKeepsTheFirstFixTime) {
  const Outcome before = Inspect("gnss.nmea");
  WriteFile(session_ / "gnss.nmea", "\xEF\xBB\xBF" + ReadFile(session_ / "gnss.nmea"));
  const Outcome run = Inspect("gnss.nmea");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out.substr(run.out.find('\n')), before.out.substr(before.out.find('\n')));
  EXPECT_EQ(run.out.find("1970"), std::string::npos) << run.out;
  EXPECT_EQ(Calibrate(".").status, 0);
}

// ---- 8. a folder name that is not UTF-8 ------------------------------------------------------

TEST_F(HostileInputTest, NonUtf8FolderNameGivesValidUtf8Offsets) {
  const fs::path latin1 = root_ / "caf\xE9";
  fs::rename(session_, latin1);
  session_ = latin1;
  ReplaceInFile(session_ / "session.yaml", "name: lms291-sapporo\n", "");
  const Outcome run = Calibrate(Quote(session_.string()));  // the path goes into offsets.yaml
  EXPECT_TRUE(io::IsPrintableUtf8(run.out.substr(0, run.out.find('\n')))) << run.out;
  ASSERT_EQ(run.status, 0) << run.err;
  const std::string yaml = ReadFile(session_ / "offsets.yaml");
  std::string without_tabs = yaml;
  for (char& c : without_tabs) c = c == '\n' ? ' ' : c;
  EXPECT_TRUE(io::IsPrintableUtf8(without_tabs));
  EXPECT_NE(yaml.find("\\xE9"), std::string::npos);
}

// ---- 9. all GGA rejected: the reasons and lines ---------------------------------------------

TEST_F(HostileInputTest, AllRejectedGgaSaysWhyAndWhere) {
  std::istringstream in(ReadFile(session_ / "gnss.nmea"));
  std::string no_checksum, lat91, gggga;
  for (std::string line; std::getline(in, line);) {
    if (line.find("GGA") == std::string::npos) continue;
    no_checksum += line.substr(0, line.find('*')) + "\n";
    std::string body = line.substr(line.find('$') + 1, line.find('*') - line.find('$') - 1);
    std::string lat = body;
    lat.replace(lat.find(",4304."), 6, ",9104.");
    lat91 += line.substr(0, line.find('$')) + "$" + lat + "*" + io::NmeaChecksum(lat) + "\n";
    std::string g = "GGGA" + body.substr(5);  // not a sentence type wallcal reads
    gggga += line.substr(0, line.find('$')) + "$" + g + "*" + io::NmeaChecksum(g) + "\n";
  }
  const std::pair<std::string, std::string> cases[] = {
      {no_checksum, "no checksum: "}, {lat91, "lat/lon out of range: "},
      {gggga, "other sentence (GGGA): "}};
  for (const auto& [text, reason] : cases) {
    WriteFile(session_ / "gnss.nmea", text);
    const Outcome run = Calibrate(".");
    testing_support::ExpectExitSaying(run.status, 2, run.err, {reason, "first at line 1"});
  }
}

// ---- 10. empty paths -------------------------------------------------------------------------

TEST_F(HostileInputTest, EmptyOutputOrConfigIsAUsageError) {
  const Outcome output = Calibrate(". --output ''");
  testing_support::ExpectExitSaying(output.status, 2, output.err, {"--output: empty file name"});
  EXPECT_EQ(Calibrate(". --config ''").status, 2);
  EXPECT_FALSE(fs::exists(session_ / "offsets.yaml"));
}

TEST_F(HostileInputTest, DashWritesOffsetsToStdout) {
  const Outcome run = Calibrate(". --output -");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_EQ(run.out.rfind("# Mount of the scanner", 0), 0u) << run.out;
  EXPECT_FALSE(fs::exists(session_ / "-"));
  EXPECT_FALSE(fs::exists(session_ / "offsets.yaml"));
}

// ---- 11. links, modes and interrupted writes ------------------------------------------------

TEST_F(HostileInputTest, ExistingLinkIsFollowedAndModeKept) {
  WriteFile(root_ / "target.yaml", "old\n");
  ASSERT_EQ(::chmod((root_ / "target.yaml").c_str(), 0600), 0);
  fs::create_symlink("../target.yaml", session_ / "offsets.yaml");
  const Outcome run = Calibrate(".");
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::is_symlink(session_ / "offsets.yaml"));
  EXPECT_NE(ReadFile(root_ / "target.yaml").find("scanner_mount"), std::string::npos);
  struct stat info {};
  ASSERT_EQ(::stat((root_ / "target.yaml").c_str(), &info), 0);
  EXPECT_EQ(info.st_mode & 07777, 0600u);
  ExpectNoTempFiles();
  // A link to nowhere is refused, not replaced.
  fs::remove(session_ / "offsets.yaml");
  fs::create_symlink("../missing/x.yaml", session_ / "offsets.yaml");
  EXPECT_EQ(Calibrate(".").status, 2);
  EXPECT_TRUE(fs::is_symlink(session_ / "offsets.yaml"));
}

TEST_F(HostileInputTest, SigintDuringAWriteRemovesTheTemporaryFile) {
  // A child writes a large file; the parent interrupts it while its temporary file exists.
  for (size_t megabytes = 64; megabytes <= 1024; megabytes *= 2) {
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      const std::string content(megabytes << 20, 'x');
      try {
        io::WriteFileAtomically((root_ / "big.yaml").string(), content);
      } catch (...) {
        ::_exit(7);
      }
      ::_exit(0);
    }
    bool seen = false;
    for (int i = 0; i < 200000 && !seen; ++i) {
      for (const auto& entry : fs::directory_iterator(root_)) {
        if (entry.path().filename().string().rfind("big.yaml.tmp-", 0) == 0) seen = true;
      }
      if (!seen) ::usleep(50);
      int status = 0;
      if (!seen && ::waitpid(child, &status, WNOHANG) == child) break;
    }
    if (seen) ::kill(child, SIGINT);
    int status = 0;
    ::waitpid(child, &status, 0);
    if (!seen || !WIFSIGNALED(status)) {
      fs::remove(root_ / "big.yaml");
      continue;  // the write was faster than the look: try a larger one
    }
    EXPECT_EQ(WTERMSIG(status), SIGINT);
    for (const auto& entry : fs::directory_iterator(root_)) {
      EXPECT_EQ(entry.path().filename().string().find(".tmp-"), std::string::npos)
          << entry.path();
    }
    return;
  }
  GTEST_SKIP() << "every write finished before it could be interrupted";
}

// ---- 12. control characters in names ---------------------------------------------------------

TEST_F(HostileInputTest, ControlCharactersInNameNeverReachTheTerminal) {
  ReplaceInFile(session_ / "session.yaml", "name: lms291-sapporo", "name: \"x\\e[2J\\nfake line\"");
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("session.yaml:1: name: expected text without control characters"),
            std::string::npos)
      << run.err;
  EXPECT_EQ((run.out + run.err).find('\x1b'), std::string::npos);
  const Outcome inspect = Inspect(".");
  EXPECT_EQ((inspect.out + inspect.err).find('\x1b'), std::string::npos);
}

// ---- 13. fixes that contradict themselves ----------------------------------------------------

TEST_F(HostileInputTest, GgaWithTooFewSatellitesIsCountedAndWarned) {
  std::istringstream in(ReadFile(session_ / "gnss.nmea"));
  std::string text;
  int changed = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.find("GGA") != std::string::npos && changed < 5) {
      line = Gga(line, changed % 2 ? "-3" : "0", "0.7");
      ++changed;
    }
    text += line + "\n";
  }
  WriteFile(session_ / "gnss.nmea", text);
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_NE(run.out.find("GGA fix with fewer than 4 satellites: 3, first at line 1"),
            std::string::npos)
      << run.out;
  EXPECT_NE(run.out.find("bad field: 2"), std::string::npos) << run.out;
}

// ---- 14. messages with file and line --------------------------------------------------------

TEST_F(HostileInputTest, SessionMistakesNameFileAndLine) {
  const std::string yaml = ReadFile(session_ / "session.yaml");
  const std::pair<std::string, std::string> cases[] = {
      {"name: lms291-sapporo\nutm_zone: 1N", "session.yaml:16: survey.control[0] / utm_zone:"},
      {"lat: 43.07129002690411", "session.yaml:15: survey.control[0].lat: expected a latitude"},
      {"time_offset_s: 0", "session.yaml:5: scanner.time_offset_s: expected seconds"},
      {"log: gnss.nmea", "the NMEA log is a folder"},
  };
  const std::string replacements[] = {"name: lms291-sapporo\nutm_zone: 1N", "lat: 90",
                                      "time_offset_s: 1e308", "log: ."};
  for (size_t i = 0; i < 4; ++i) {
    std::string broken = yaml;
    const std::string& from = i == 0 ? std::string("name: lms291-sapporo") : cases[i].first;
    broken.replace(broken.find(from), from.size(), replacements[i]);
    WriteFile(session_ / "session.yaml", broken);
    const Outcome run = Calibrate(".");
    testing_support::ExpectExitSaying(run.status, 2, run.err, {cases[i].second});
  }
}

TEST_F(HostileInputTest, DeepNestingAndNulInYamlNameTheLine) {
  const std::string yaml = ReadFile(session_ / "session.yaml");
  WriteFile(session_ / "session.yaml",
            yaml + "antenna_in_base: " + std::string(200000, '[') + std::string(200000, ']') + "\n");
  const Outcome deep = Calibrate(".");
  EXPECT_EQ(deep.status, 2) << deep.err;
  EXPECT_NE(deep.err.find("session.yaml:19: maps and lists nested more than"), std::string::npos)
      << deep.err;
  std::string nul = yaml;
  nul.insert(nul.find("gnss:"), std::string("# \0\n", 4));
  WriteFile(session_ / "session.yaml", nul);
  const Outcome run = Calibrate(".");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"session.yaml:6: a NUL byte"});
}

// ---- Fail early, and a report failure is only a warning ----------------------------------------

TEST_F(HostileInputTest, OutputsAreCheckedBeforeTheWork) {
  const Outcome folder = Calibrate(". --output ../missing/offsets.yaml");
  testing_support::ExpectExitSaying(folder.status, 2, folder.err, {"does not exist"});
  EXPECT_EQ(folder.out.find("scanner_mount"), std::string::npos);  // no summary: no work done
  WriteFile(root_ / "report", "a file\n");
  const Outcome report = Calibrate(". --report ../report");
  EXPECT_EQ(report.status, 2) << report.err;
  EXPECT_NE(report.err.find("--report: this is not a regular file"), std::string::npos)
      << report.err;
  EXPECT_FALSE(fs::exists(session_ / "offsets.yaml"));
}

TEST_F(HostileInputTest, ReportThatCannotBeWrittenKeepsTheCalibration) {
  fs::create_directories(root_ / "report" / "report.html");  // a folder where the page goes
  const Outcome run = Calibrate(". --report ../report");
  testing_support::ExpectExitSaying(run.status, 0, run.err, {"warning: report not written"});
  EXPECT_TRUE(fs::exists(session_ / "offsets.yaml"));
}

// ---- what held, and must keep holding --------------------------------------------------------

TEST_F(HostileInputTest, CrlfBomUnicodeAndSpacesStillWork) {
  for (const char* name : {"session.yaml", "survey.csv", "scans.clf"}) {
    std::string text = ReadFile(session_ / name);
    std::string crlf = "\xEF\xBB\xBF";
    for (char c : text) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
    WriteFile(session_ / name, crlf);
  }
  const fs::path unicode = root_ / "séance d'essai 測試";
  fs::rename(session_, unicode);
  session_ = unicode;
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::exists(session_ / "offsets.yaml"));
}

// As root a mode does not stop a write; a folder in the way of the rename does.
TEST_F(HostileInputTest, ReadOnlyTargetLeavesTheOldFile) {
  fs::create_directories(session_ / "ro");
  WriteFile(session_ / "ro" / "offsets.yaml", "old\n");
  EXPECT_EQ(Calibrate(". --output ro/offsets.yaml/x").status, 2);
  EXPECT_EQ(ReadFile(session_ / "ro" / "offsets.yaml"), "old\n");
  ExpectNoTempFiles();
}

TEST_F(HostileInputTest, FiftyMegabyteLineIsSkippedNotFatal) {
  std::ofstream out(session_ / "scans.clf", std::ios::binary | std::ios::app);
  out << "RAWLASER1 " << std::string(50 << 20, '7') << "\n";
  out.close();
  const Outcome run = Calibrate(".");
  testing_support::ExpectExitSaying(run.status, 0, run.out, {"RAWLASER1: too few fields: 1"});
}

TEST_F(HostileInputTest, TwoGigabyteSparseLogEndsWithAMessage) {
  // All zero bytes and no newline (it held: exit 2; now: a line past the line budget).
  fs::remove(session_ / "scans.clf");
  { std::ofstream create(session_ / "scans.clf"); }
  fs::resize_file(session_ / "scans.clf", uintmax_t{2} << 30);
  const Outcome run = Calibrate(".");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"scans.clf:"});
}

TEST_F(HostileInputTest, ConcurrentRunsLeaveOneWholeFile) {
  const std::string calibrate = Quote(kWallcal) + " calibrate .";
  const Outcome run =
      RunIn(session_, "/bin/sh", "-c " + Quote(calibrate + " & " + calibrate + " & wait"));
  EXPECT_EQ(run.status, 0) << run.err;
  const std::string yaml = ReadFile(session_ / "offsets.yaml");
  EXPECT_EQ(yaml.rfind("# Mount of the scanner", 0), 0u);
  EXPECT_NE(yaml.find("source:\n  session:"), std::string::npos);
  ExpectNoTempFiles();
}

TEST_F(HostileInputTest, PresetNameCannotTraversePaths) {
  ReplaceInFile(session_ / "session.yaml", "model: sick_lms291", "model: ../../etc/passwd");
  const Outcome run = Calibrate(".");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"unknown scanner model"});
}

TEST_F(HostileInputTest, BillionLaughsYamlIsBounded) {
  std::string yaml = ReadFile(session_ / "session.yaml");
  yaml += "x0: &a [\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\",\"lol\"]\n";
  for (int i = 1; i < 9; ++i) {
    yaml += "x" + std::to_string(i) + ": &" + std::string(1, static_cast<char>('a' + i)) + " [";
    for (int k = 0; k < 9; ++k) yaml += std::string(k ? "," : "") + "*" + static_cast<char>('a' + i - 1);
    yaml += "]\n";
  }
  WriteFile(session_ / "session.yaml", yaml);
  const Outcome run = Calibrate(".");
  EXPECT_EQ(run.status, 2) << run.err;
  EXPECT_NE(run.err.find("session.yaml:"), std::string::npos) << run.err;  // file and line
}

}  // namespace
}  // namespace wallcal
