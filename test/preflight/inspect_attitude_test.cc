// SPDX-License-Identifier: Apache-2.0
// inspect and the attitude stream: the session report's attitude block (its source, rate, range
// of roll and pitch, σ, overlap with the scans), a stream that gives no sample as a blocker,
// --dump attitude's CSV, the one-log and the recording reports, and --suggest-session's
// attitude: block and z_m lines; the yard the GNSS heights show.
#include <gtest/gtest.h>

#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/output_file.h"
#include "io/writers/writers.h"
#include "preflight/inspect.h"
#include "sim/recording_session.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"
#include "sim/simulator.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::preflight {
namespace {

namespace fs = std::filesystem;
using testing_support::ExpectContains;
using testing_support::FreshScratchDir;
using testing_support::MessageOf;

// The sample's scenario, short, its simulated session given an attitude stream at 10 Hz:
// roll from -1.0° to +1.0°, pitch 2.0°, σ 0.05°.
const fs::path& SessionWithAttitude() {
  static const fs::path dir = [] {
    const fs::path d = FreshScratchDir("text");
    sim::SimulationConfig config = sim::ReadSimulationConfig(
        std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
    config.num_stations = 4;
    config.dwell_s = 3.0;  // stations: stops of at least 2 s
    sim::WriteSimulatedSession(config, 7, d.string(), [](sim::SimulatedSession& s) {
      const double start_s = s.headings.front().stamp_s, end_s = s.headings.back().stamp_s;
      for (double t = start_s; t < end_s; t += 0.1) {
        io::AttitudeSample a;
        a.stamp_s = t;
        a.roll_rad = (-1.0 + 2.0 * (t - start_s) / (end_s - start_s)) * kDegToRad;
        a.pitch_rad = 2.0 * kDegToRad;
        a.roll_sigma_rad = a.pitch_sigma_rad = 0.05 * kDegToRad;
        s.attitudes.push_back(a);
      }
    });
    return d;
  }();
  return dir;
}

TEST(InspectAttitudeTest, TheSessionReportShowsTheAttitudeStream) {
  const SessionInspection inspection = InspectSession(SessionWithAttitude().string());
  ExpectContains(inspection.report,
                 {"  attitude ($PASHR ", "(heading.nmea)", "    rate      median period 0.1000 s",
                  "    roll      -1.00° .. +1.00°", "    pitch     +2.00° .. +2.00°",
                  "    sigma     median roll 0.050°, pitch 0.050° (the stream's)",
                  "    overlap   scans & attitude"});
  EXPECT_TRUE(inspection.enough) << inspection.report;
}

TEST(InspectAttitudeTest, AnAttitudeLogWithoutASampleBlocks) {
  const fs::path dir = FreshScratchDir("no_sample");
  fs::copy(SessionWithAttitude(), dir, fs::copy_options::recursive);
  const std::string bad = "PASHR,000000.00,35.00,T,+95.0000,+0.5000,0.00,,,,1,0";
  io::WriteFileAtomically((dir / "attitude.nmea").string(),
                          "1.0 $" + bad + "*" + io::NmeaChecksum(bad) + "\n");
  io::SessionSpec spec = io::ReadSession(dir.string());
  spec.attitude_log = (dir / "attitude.nmea").string();
  io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  const SessionInspection inspection = InspectSession(dir.string());
  EXPECT_FALSE(inspection.enough);
  ASSERT_FALSE(inspection.blockers.empty());
  std::string blockers;
  for (const std::string& b : inspection.blockers) blockers += b + "\n";
  ExpectContains(blockers,
                 {"attitude: ", "attitude.log: no attitude sample (lines read: 1; skipped: ",
                  "roll or pitch beyond 30 deg: 1, first at line 1"});
}

TEST(InspectAttitudeTest, DumpsTheAttitudeStreamAsCsv) {
  std::ostringstream csv;
  Dump(SessionWithAttitude().string(), DumpKind::kAttitude, csv);
  std::istringstream lines(csv.str());
  std::string header, first;
  std::getline(lines, header);
  std::getline(lines, first);
  EXPECT_EQ(header, "time_s,roll_deg,pitch_deg,roll_sigma_deg,pitch_sigma_deg,line");
  ExpectContains(first, {",-1.000000000,2.000000000,0.050000000,0.050000000,"});
  // The heading log by itself, as one log.
  std::ostringstream one;
  Dump((SessionWithAttitude() / "heading.nmea").string(), DumpKind::kAttitude, one);
  EXPECT_EQ(one.str(), csv.str());
  // A session without attitude: has none to dump.
  const fs::path plain = FreshScratchDir("plain");
  fs::copy(SessionWithAttitude(), plain, fs::copy_options::recursive);
  io::SessionSpec spec = io::ReadSession(plain.string());
  spec.attitude_log.clear();
  io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  std::ostringstream none;
  ExpectContains(
      MessageOf<io::InputError>([&] { Dump(plain.string(), DumpKind::kAttitude, none); }),
      {"names no attitude stream"});
}

TEST(InspectAttitudeTest, TheOneLogReportShowsTheAttitudeSentences) {
  ExpectContains(InspectLogFile((SessionWithAttitude() / "heading.nmea").string()),
                 {"  attitude ($PASHR ", "    roll      -1.00° .. +1.00°"});
}

TEST(InspectAttitudeTest, ARecordingsImuTopicIsReportedAndSuggested) {
  const fs::path dir = FreshScratchDir("mcap");
  fs::copy(SessionWithAttitude(), dir, fs::copy_options::recursive);
  sim::ConvertSessionToRecording(dir.string(), sim::SessionFormat::kMcap);
  const std::string mcap = (dir / "session.mcap").string();
  ExpectContains(InspectRecording(mcap),
                 {"/imu/data [sensor_msgs/msg/Imu]", "    attitude  ",
                  " messages give roll and pitch", "    roll      -1.00° .. +1.00°"});
  const std::string suggested = SuggestSession(mcap);
  ExpectContains(
      suggested,
      {"attitude:  # the vehicle's roll and pitch", "  log: session.mcap\n  topic: /imu/data",
       " with the vehicle's roll and pitch\n", "  stamp: header",
       "  # z_m: 0.0  # CHECK: the scanner's height relative to the antenna (m): tape "
       "from\n  #   the antenna's reference point to the scanner's optical centre, "
       "negative\n  #   when the scanner is below the antenna\n"});
  // --dump attitude on the recording: the one topic that fits.
  std::ostringstream csv;
  DumpRecording(mcap, DumpKind::kAttitude, "/imu/data", csv);
  ExpectContains(csv.str(), {"time_s,roll_deg,pitch_deg", ",-1.000000000,2.000000000,"});
}

// The session report's yard line from a session on the 2 % yard (stations at 6 to 10 m from
// the wall): the grade within a few of its σ (0.3 % on this set-up), rising towards the wall
// (north), and what to do about scanner.z_m; the level sample's yard is level.
std::string YardLineOf(const std::string& report) {
  const size_t at = report.find("  yard      ");
  if (at == std::string::npos) return "";
  return report.substr(at, report.find('\n', at) - at);
}

TEST(InspectAttitudeTest, TheSessionReportGivesTheYardsGrade) {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/bench_lms291_yard2.yaml");
  config.write_z_m = false;
  const fs::path dir = FreshScratchDir("yard");
  sim::WriteSimulatedSession(config, 3, dir.string());
  const std::string line = YardLineOf(InspectSession(dir.string()).report);
  ASSERT_FALSE(line.empty());
  const double grade_pct = std::stod(line.substr(std::string("  yard      ").size()));
  EXPECT_NEAR(grade_pct, 2.0, 1.0) << line;
  ExpectContains(line, {" % rising towards ", "antenna heights", "not level: give scanner.z_m"});
  const std::string level = YardLineOf(InspectSession(SessionWithAttitude().string()).report);
  EXPECT_TRUE(level.find("level within its σ") != std::string::npos ||
              level.find("not measured") != std::string::npos)
      << level;
}

}  // namespace
}  // namespace wallcal::preflight
