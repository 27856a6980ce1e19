// SPDX-License-Identifier: Apache-2.0
#include "preflight/inspect.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>
#include <zlib.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
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
#include "io/text/carmen_reader.h"
#include "io/text/nmea_reader.h"
#include "io/config/session_reader.h"
#include "io/writers/writers.h"
#include "io/output_file.h"
#include "io/config/config_writer.h"
#include "common/angles.h"
#include "test/support/expect_text.h"
#include "test/support/flow_names.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_files.h"

namespace wallcal {


namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchDir;
using testing_support::WriteFile;

const std::string kRealDir = WALLCAL_SOURCE_DIR "/../shared/testdata/real/";

// A simulated session (the bundled sample's scenario), optionally with another heading spread.
std::string Simulate(const std::string& name, double heading_spread_deg = 0.0) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      WALLCAL_SOURCE_DIR "/configs/simulate/lms291_sapporo.yaml");
  if (heading_spread_deg > 0) config.heading_spread_rad = heading_spread_deg / kRadToDeg;
  const fs::path dir = FreshScratchDir(name);
  WriteSimulatedSession(config, 7, dir.string());
  return dir.string();
}

struct ProgramRun {
  int status = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// Runs `wallcal inspect ARGS` (ARGS as the shell splits them); stdout and stderr captured
// separately.
ProgramRun RunInspectProgram(const std::string& args) {
  const testing_support::ProgramRun run = testing_support::RunWallcalLine("inspect", args);
  return {run.exit_code, run.out, run.err};
}

std::vector<std::vector<std::string>> ParseCsv(const std::string& text, std::string* header) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  std::string line;
  std::getline(in, *header);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::string cell;
    std::istringstream fields(line);
    while (std::getline(fields, cell, ',')) cells.push_back(cell);
    if (!line.empty() && line.back() == ',') cells.push_back("");
    rows.push_back(cells);
  }
  return rows;
}

double Num(const std::string& cell) { return cell.empty() ? io::kNaN : std::strtod(cell.c_str(), nullptr); }

TEST(InspectTest, SimulatedSessionHasEnoughData) {
  const std::string dir = Simulate("enough");
  const SessionInspection inspection = InspectSession(dir);
  EXPECT_TRUE(inspection.enough) << inspection.report;
  EXPECT_TRUE(inspection.blockers.empty());
  EXPECT_NE(inspection.report.find("VERDICT: enough data for a calibration"), std::string::npos)
      << inspection.report;
  // Every part of the report is there.
  for (const char* part : {"scans (scans.clf)", "GNSS fixes (GGA)", "headings (HDT/THS)",
                           "overlap", "RTK fixed", "control", "stations", "wall seen", "verdict"}) {
    EXPECT_NE(inspection.report.find(part), std::string::npos) << part << "\n" << inspection.report;
  }
  // The program prints the same and exits 0.
  const ProgramRun run = RunInspectProgram(dir);
  testing_support::ExpectExitSaying(run.status, 0, run.out, {
      "VERDICT: enough data for a calibration"
  });
}

TEST(InspectTest, NarrowHeadingsGetAVerdictNamingTheProblem) {
  const std::string dir = Simulate("narrow", 6.0);
  const SessionInspection inspection = InspectSession(dir);
  EXPECT_FALSE(inspection.enough) << inspection.report;
  EXPECT_NE(inspection.report.find("NOT enough data"), std::string::npos) << inspection.report;
  bool named = false;
  for (const std::string& b : inspection.blockers) named = named || b.find("narrow heading spread") != std::string::npos;
  EXPECT_TRUE(named) << inspection.report;
  EXPECT_EQ(RunInspectProgram(dir).status, 0);  // a report, whatever the verdict
}

TEST(InspectTest, MissingHeadingLogStillReportsGnssAndScans) {
  const std::string dir = Simulate("no_heading");
  fs::remove(fs::path(dir) / "heading.nmea");
  const SessionInspection inspection = InspectSession(dir);
  EXPECT_FALSE(inspection.enough);
  ASSERT_FALSE(inspection.blockers.empty());
  EXPECT_NE(inspection.blockers.front().find("heading.nmea"), std::string::npos)
      << inspection.blockers.front();
  EXPECT_EQ(inspection.report.find("GNSS fixes (GGA) (gnss.nmea): 0 records"), std::string::npos);
  testing_support::ExpectContains(inspection.report, {
      "GNSS fixes (GGA) (gnss.nmea): ",
      "quality   4 (RTK fixed)",
      "scans (scans.clf): ",
      "control   2 points"
  });
}

TEST(InspectTest, LogsThatDoNotOverlapAreNamed) {
  const std::string dir = Simulate("shifted");
  // Move the heading log 1000 s later.
  const fs::path heading = fs::path(dir) / "heading.nmea";
  std::ifstream in(heading);
  std::string line, shifted;
  while (std::getline(in, line)) {
    const size_t space = line.find(' ');
    char stamp[64];
    std::snprintf(stamp, sizeof(stamp), "%.3f", std::strtod(line.c_str(), nullptr) + 1000.0);
    shifted += stamp + line.substr(space) + "\n";
  }
  in.close();
  WriteFile(heading, shifted);
  const SessionInspection inspection = InspectSession(dir);
  EXPECT_FALSE(inspection.enough);
  bool named = false;
  for (const std::string& b : inspection.blockers) named = named || b.find("not overlapping") != std::string::npos;
  EXPECT_TRUE(named) << inspection.report;
}

// What `inspect --dump KIND` writes for the session in `dir`, parsed: rows of fields, the
// header line in *header.
std::vector<std::vector<std::string>> DumpRows(const std::string& dir, DumpKind kind,
                                               std::string* header) {
  std::ostringstream csv;
  Dump(dir, kind, csv);
  return ParseCsv(csv.str(), header);
}

TEST(InspectTest, DumpsParseBackToTheReadersNumbers) {
  const std::string dir = Simulate("dump");
  const io::SessionSpec spec = io::ReadSession(dir);
  std::string header;

  const auto gnss_rows = DumpRows(dir, DumpKind::kGnss, &header);
  EXPECT_EQ(header, "time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,sigma_lat_m,sigma_lon_m,line");
  const io::NmeaLog nmea = io::ReadNmea(spec.gnss_log);
  ASSERT_EQ(gnss_rows.size(), nmea.fixes.size());
  ASSERT_FALSE(gnss_rows.empty());
  for (size_t i = 0; i < gnss_rows.size(); ++i) {
    const io::GnssFix& fix = nmea.fixes[i];
    ASSERT_EQ(gnss_rows[i].size(), 10u);
    EXPECT_NEAR(Num(gnss_rows[i][0]), fix.stamp_s, 1e-6);
    EXPECT_NEAR(Num(gnss_rows[i][1]), fix.lat_deg, 1e-9);
    EXPECT_NEAR(Num(gnss_rows[i][2]), fix.lon_deg, 1e-9);
    EXPECT_NEAR(Num(gnss_rows[i][3]), fix.height_m, 1e-4);
    EXPECT_EQ(std::stoi(gnss_rows[i][4]), fix.quality);
    EXPECT_EQ(std::stoi(gnss_rows[i][5]), fix.satellites);
    EXPECT_NEAR(Num(gnss_rows[i][7]), fix.sigma_lat_m, 1e-9);
    EXPECT_EQ(std::stoi(gnss_rows[i][9]), fix.line);
  }

  const auto heading_rows = DumpRows(dir, DumpKind::kHeading, &header);
  EXPECT_EQ(header, "time_s,heading_deg,line");
  const io::NmeaLog headings = io::ReadNmea(spec.heading_log);
  ASSERT_EQ(heading_rows.size(), headings.headings.size());
  for (size_t i = 0; i < heading_rows.size(); ++i) {
    EXPECT_NEAR(Num(heading_rows[i][0]), headings.headings[i].stamp_s, 1e-6);
    EXPECT_NEAR(Num(heading_rows[i][1]), headings.headings[i].heading_rad * kRadToDeg, 1e-8);
    EXPECT_EQ(std::stoi(heading_rows[i][2]), headings.headings[i].line);
  }

  // Scans through the program, on the log file itself (valid by the log's own maximum).
  const ProgramRun run = RunInspectProgram(spec.scanner_log + " --dump scans");
  ASSERT_EQ(run.status, 0) << run.err;
  const auto scan_rows = ParseCsv(run.out, &header);
  EXPECT_EQ(header, "time_s,beams,valid,min_range_m,max_range_m,line");
  io::CarmenReader reader(spec.scanner_log);
  io::ScanRecord scan;
  size_t i = 0;
  while (reader.Next(&scan)) {
    ASSERT_LT(i, scan_rows.size());
    const auto& row = scan_rows[i++];
    ASSERT_EQ(row.size(), 6u);
    EXPECT_NEAR(Num(row[0]), scan.stamp_s, 1e-6);
    EXPECT_EQ(std::stoul(row[1]), scan.ranges_m.size());
    int valid = 0;
    float lo = 1e30f, hi = 0.0f;
    for (float r : scan.ranges_m) {
      if (std::isfinite(r) && r > 0 && r < scan.max_range_m) {
        ++valid;
        lo = std::min(lo, r);
        hi = std::max(hi, r);
      }
    }
    EXPECT_EQ(std::stoi(row[2]), valid);
    if (valid > 0) {
      EXPECT_FLOAT_EQ(static_cast<float>(Num(row[3])), lo);
      EXPECT_FLOAT_EQ(static_cast<float>(Num(row[4])), hi);
    }
    EXPECT_EQ(std::stoi(row[5]), scan.line);
  }
  EXPECT_EQ(i, scan_rows.size());

  // On the session the preset decides: the LMS 291's 80 m no-returns are not valid either.
  std::ostringstream session_scans;
  Dump(dir, DumpKind::kScans, session_scans);
  const auto session_rows = ParseCsv(session_scans.str(), &header);
  ASSERT_EQ(session_rows.size(), scan_rows.size());
  for (size_t k = 0; k < session_rows.size(); ++k) {
    EXPECT_LE(std::stoi(session_rows[k][2]), std::stoi(scan_rows[k][2]));
  }
}

// gpsd's TPV positions keyed by the UTC time of day (ms) of the GGA/RMC before them (first wins).
std::map<int64_t, std::pair<double, double>> GpsdPositions(const std::string& chk) {
  std::ifstream in(chk);
  std::map<int64_t, std::pair<double, double>> positions;
  std::string line;
  int64_t epoch_ms = -1;
  auto number = [](const std::string& text, const std::string& key, bool* found) {
    const size_t at = text.find("\"" + key + "\":");
    *found = at != std::string::npos;
    return *found ? std::strtod(text.c_str() + at + key.size() + 3, nullptr) : 0.0;
  };
  while (std::getline(in, line)) {
    if (line.rfind("$", 0) == 0) {
      const size_t comma = line.find(',');
      if (comma != std::string::npos && comma >= 6 &&
          (line.compare(comma - 3, 3, "GGA") == 0 || line.compare(comma - 3, 3, "RMC") == 0) &&
          line.size() > comma + 7 && line[comma + 1] != ',') {
        epoch_ms = std::llround((std::stoi(line.substr(comma + 1, 2)) * 3600 +
                                 std::stoi(line.substr(comma + 3, 2)) * 60 +
                                 std::strtod(line.c_str() + comma + 5, nullptr)) *
                                1000.0);
      }
    } else if (epoch_ms >= 0 && line.find("\"class\":\"TPV\"") != std::string::npos) {
      bool has_lat = false, has_lon = false;
      const double lat = number(line, "lat", &has_lat);
      const double lon = number(line, "lon", &has_lon);
      if (has_lat && has_lon) positions.emplace(epoch_ms, std::make_pair(lat, lon));
    }
  }
  return positions;
}

TEST(InspectTest, RealLogDumpMatchesGpsd) {
  for (const std::string name : {"nmea-rtk.log", "skytraq-PX1172RH_DS.log"}) {
    SCOPED_TRACE(name);
    const std::string log = kRealDir + "nmea/" + name;
    if (!fs::exists(log) || !fs::exists(log + ".chk")) {
      GTEST_SKIP() << "real test data not available: " << log;
    }
    const ProgramRun run = RunInspectProgram(log + " --dump gnss");
    ASSERT_EQ(run.status, 0) << run.err;
    std::string header;
    const auto rows = ParseCsv(run.out, &header);
    ASSERT_FALSE(rows.empty());
    const auto gpsd = GpsdPositions(log + ".chk");
    size_t compared = 0;
    for (const auto& row : rows) {
      const int64_t tod_ms = std::llround(std::fmod(Num(row[0]), 86400.0) * 1000.0);
      const auto it = gpsd.find(tod_ms);
      if (it == gpsd.end()) continue;
      EXPECT_NEAR(Num(row[1]), it->second.first, 1e-9) << "line " << row[9];
      EXPECT_NEAR(Num(row[2]), it->second.second, 1e-9) << "line " << row[9];
      ++compared;
    }
    EXPECT_EQ(compared, rows.size());  // gpsd reports every epoch of these two logs
  }
}

TEST(InspectTest, RealHeadingDumpMatchesGpsdAtt) {
  const std::string log = kRealDir + "nmea/skytraq-PX1172RH_DS.log";
  if (!fs::exists(log + ".chk")) GTEST_SKIP() << "real test data not available: " << log;
  std::ostringstream csv;
  Dump(log, DumpKind::kHeading, csv);
  std::string header;
  std::vector<double> dumped;
  for (const auto& row : ParseCsv(csv.str(), &header)) {
    if (dumped.empty() || dumped.back() != Num(row[1])) dumped.push_back(Num(row[1]));
  }
  std::vector<double> att;
  std::ifstream in(log + ".chk");
  std::string line;
  while (std::getline(in, line)) {
    if (line.find("\"class\":\"ATT\"") == std::string::npos) continue;
    const size_t at = line.find("\"heading\":");
    if (at == std::string::npos) continue;
    const double h = std::strtod(line.c_str() + at + 10, nullptr);
    if (att.empty() || att.back() != h) att.push_back(h);
  }
  ASSERT_EQ(dumped.size(), att.size());
  for (size_t i = 0; i < att.size(); ++i) EXPECT_NEAR(dumped[i], att[i], 1e-6) << i;
}

TEST(InspectTest, RealCarmenLogReportCountsItsScans) {
  const std::string log = kRealDir + "carmen/intel-corrected.log.gz";
  if (!fs::exists(log)) GTEST_SKIP() << "real test data not available: " << log;
  EXPECT_EQ(SniffLogKind(log), LogKind::kCarmen);
  const std::string report = InspectLogFile(log);
  testing_support::ExpectContains(report, {
      "scans (intel-corrected.log.gz): 910 records",
      "180 beams: 910 scans",
      "not a scan: ODOM: 14541",
      "steps back in time"
  });
}

TEST(InspectTest, SniffsLogKindByContent) {
  const fs::path dir = FreshScratchDir("sniff");
  const std::string gga = "$GPGGA,120000.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,*" +
                          io::NmeaChecksum("GPGGA,120000.00,4000.0,N,10000.0,E,4,10,1.0,10.0,M,0.0,M,,");
  EXPECT_EQ(SniffLogKind(WriteFile(dir / "a.txt", "# header\n\n1747031522.113 " + gga + "\n")),
            LogKind::kNmea);
  EXPECT_EQ(SniffLogKind(WriteFile(dir / "b.log", gga + "\n")), LogKind::kNmea);
  EXPECT_EQ(SniffLogKind(WriteFile(dir / "c.bin", std::string("\xb5\x62\x01\x07junk", 8) + gga + "\n")),
            LogKind::kNmea);
  const std::string carmen = "PARAM robot_width 0.5 host 1.0\nFLASER 3 1 2 3 0 0 0 0 0 0 1.0 h 1.0\n";
  EXPECT_EQ(SniffLogKind(WriteFile(dir / "d.nmea", carmen)), LogKind::kCarmen);  // name ignored
  const std::string gz = (dir / "e.clf.gz").string();
  gzFile file = gzopen(gz.c_str(), "wb");
  ASSERT_NE(file, nullptr);
  gzwrite(file, carmen.data(), static_cast<unsigned>(carmen.size()));
  gzclose(file);
  EXPECT_EQ(SniffLogKind(gz), LogKind::kCarmen);

  auto expect_error = [](const std::string& path, const std::string& text) {
    try {
      SniffLogKind(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const io::InputError& e) {
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
    }
  };
  expect_error(WriteFile(dir / "garbage.bin", std::string("\x00\x01\x02\xff\xfe binary\n", 14)),
               "neither NMEA nor CARMEN");
  // Text that only quotes a sentence is not a log.
  expect_error(WriteFile(dir / "readme.md", "# notes\nthe receiver sends $GPGGA,1,2 lines\n"),
               "neither NMEA nor CARMEN");
  expect_error(WriteFile(dir / "empty.log", ""), "empty file");
  const std::string gz_nmea = (dir / "f.nmea.gz").string();
  file = gzopen(gz_nmea.c_str(), "wb");
  gzwrite(file, gga.data(), static_cast<unsigned>(gga.size()));
  gzclose(file);
  EXPECT_EQ(SniffLogKind(gz_nmea), LogKind::kNmea);  // gzip'd NMEA reads like a plain log

  // The program: garbage and a dump of the wrong kind are exit 2 with one line naming the file.
  ProgramRun run = RunInspectProgram((dir / "garbage.bin").string());
  testing_support::ExpectExitSaying(run.status, 2, run.err, {
      "garbage.bin:1: neither NMEA nor CARMEN"
  });
  run = RunInspectProgram(gz + " --dump gnss");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {"expects an NMEA log"});
  EXPECT_TRUE(run.out.empty()) << run.out;
}

TEST(InspectTest, MissingFileExitsTwoNamingThePath) {
  const std::string path = (fs::path(::testing::TempDir()) / "inspect_no_such_log.nmea").string();
  const ProgramRun run = RunInspectProgram(path);
  testing_support::ExpectExitSaying(run.status, 2, run.err, {path});
  EXPECT_EQ(std::count(run.err.begin(), run.err.end(), '\n'), 1) << run.err;
  const ProgramRun session = RunInspectProgram(path + ".yaml");
  testing_support::ExpectExitSaying(session.status, 2, session.err, {path + ".yaml"});
}

TEST(InspectTest, UsageErrorsHelpAndVersion) {
  ProgramRun run = RunInspectProgram("--help");
  testing_support::ExpectExitSaying(run.status, 0, run.out, {"--dump"});
  run = RunInspectProgram("--version");
  EXPECT_EQ(run.status, 0);
  EXPECT_EQ(run.out.rfind("wallcal inspect ", 0), 0u) << run.out;
  EXPECT_EQ(RunInspectProgram("").status, 2);
  run = RunInspectProgram("x --dump positions");
  testing_support::ExpectExitSaying(run.status, 2, run.err, {
      "expected gnss, heading, attitude, scans or survey"
  });
  EXPECT_EQ(RunInspectProgram("x --bogus").status, 2);
}

TEST(InspectTest, StreamStatsFindGapsAndStepsBack) {
  const std::vector<double> stamps = {0.0, 0.1, 0.2, 0.3, 1.3, 1.4, 1.35, 1.5, 1.6};
  const std::vector<int> lines = {1, 2, 3, 4, 5, 6, 7, 8, 9};
  const StreamStats s = ComputeStreamStats("x", "f", stamps, lines);
  EXPECT_EQ(s.records, 9);
  EXPECT_DOUBLE_EQ(s.start_s, 0.0);
  EXPECT_DOUBLE_EQ(s.end_s, 1.6);
  EXPECT_NEAR(s.median_period_s, 0.1, 1e-9);
  EXPECT_EQ(s.gaps, 1);
  EXPECT_NEAR(s.longest_gap_s, 1.0, 1e-9);
  EXPECT_EQ(s.longest_gap_line, 5);
  EXPECT_EQ(s.not_increasing, 1);
  EXPECT_EQ(s.first_not_increasing_line, 7);
}

}  // namespace
}  // namespace wallcal
