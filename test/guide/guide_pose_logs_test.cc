// SPDX-License-Identifier: Apache-2.0
// The guide kept between refreshes (GuideSession) reads the pose logs on from where the last
// refresh stopped, as it does the text scan log: the GNSS log cut between a GGA and its GST,
// the heading log in the middle of a sentence, then both grown to the whole. The grown session
// holds the fixes and headings of a fresh read to the one, and reports what a fresh session
// reports (within what the scan log's own reading on leaves: guide_follow_test.cc).
//
// A recording's GNSS and heading topics are read on too (PoseLogFollower over
// recording::PoseTail): a ROS 1 bag, an MCAP file, a .db3 file and rosbag2 folders grown in
// steps, and an MCAP file whose nmea_msgs/Sentence topic carries both streams (its first date
// arriving late). After each step Read() gives what recording::ReadPoseLogs gives for the
// recording as it stands, record for record. A recording's attitude topic is read whole at each
// refresh; a text log's attitude sentences are read on with the log that holds them.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "guide/guide_session.h"
#include "guide/pose_logs.h"
#include "io/config/session_reader.h"
#include "io/text/nmea_reader.h"
#include "io/writers/writers.h"
#include "recording/recording_streams.h"
#include "recording/writers/mcap_writer.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/guide_expect.h"
#include "test/support/nmea_logs.h"
#include "test/support/rosbag2_folders.h"
#include "test/support/scratch_dir.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

TEST(GuideSessionTest, ReadsThePoseLogsOnFromWhereTheyStopped) {
  const testing_support::ScratchDir scratch("wallcal_guide_pose_logs_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) +
                                                       "/configs/simulate/lms291_sapporo.yaml"),
                             11, dir.string(), sim::SessionFormat::kText);
  const fs::path scans_path = dir / "scans.clf", gnss_path = dir / "gnss.nmea",
                 heading_path = dir / "heading.nmea";
  const std::string scans = testing_support::ReadFile(scans_path), gnss = testing_support::ReadFile(gnss_path),
                    heading = testing_support::ReadFile(heading_path);
  guide::GuideOptions options;
  options.session_path = dir.string();
  options.threads = 2;
  guide::GuideSession fresh(options);
  const guide::GuideReport whole = fresh.Refresh();
  ASSERT_TRUE(whole.predicted.known);
  EXPECT_EQ(fresh.last_read().gnss_log.from_byte, 0);
  EXPECT_EQ(fresh.last_read().gnss_log.bytes, static_cast<int64_t>(gnss.size()));

  // The pose logs a little beyond the middle of the scans, as their fixes arrive while a scan
  // is written: the GNSS log just after a GGA whose GST is not written yet, the heading log
  // inside a sentence.
  const size_t scans_cut = scans.find('\n', scans.size() / 2) + 1;
  const size_t gst = gnss.find("GST,", gnss.size() / 2 + gnss.size() / 50);
  ASSERT_NE(gst, std::string::npos);
  const size_t gnss_cut = gnss.rfind('\n', gst) + 1;
  const size_t gga = gnss.rfind('\n', gnss_cut - 2) + 1;
  ASSERT_NE(gnss.substr(gga, gnss_cut - gga).find("GGA,"), std::string::npos);
  const size_t heading_cut = heading.find('\n', heading.size() / 2 + heading.size() / 50) + 9;
  ASSERT_NE(heading[heading_cut - 1], '\n');
  testing_support::WriteFirstBytes(scans_path, scans, scans_cut);
  testing_support::WriteFirstBytes(gnss_path, gnss, gnss_cut);
  testing_support::WriteFirstBytes(heading_path, heading, heading_cut);
  guide::GuideSession session(options);
  const guide::GuideReport half = session.Refresh();
  EXPECT_EQ(session.last_read().gnss_log.from_byte, 0);
  EXPECT_EQ(session.last_read().heading_log.from_byte, 0);
  EXPECT_LT(half.stations.size(), whole.stations.size());

  testing_support::WriteFirstBytes(scans_path, scans, scans.size());
  testing_support::WriteFirstBytes(gnss_path, gnss, gnss.size());
  testing_support::WriteFirstBytes(heading_path, heading, heading.size());
  const guide::GuideReport grown = session.Refresh();
  const guide::ReadCounts& read = session.last_read();
  // Read on from the cut (the GNSS log's fell at a line end), the heading log from the start
  // of the line it cut.
  EXPECT_EQ(read.gnss_log.from_byte, static_cast<int64_t>(gnss_cut));
  EXPECT_EQ(read.heading_log.from_byte, static_cast<int64_t>(heading.rfind('\n', heading_cut) + 1));
  EXPECT_EQ(read.gnss_log.bytes, static_cast<int64_t>(gnss.size()));
  EXPECT_EQ(read.heading_log.bytes, static_cast<int64_t>(heading.size()));
  EXPECT_TRUE(read.incremental);
  // The same fixes (the GST joined to its GGA across the cut) and headings as a fresh read.
  EXPECT_EQ(read.fixes_used, fresh.last_read().fixes_used);
  EXPECT_EQ(read.headings_used, fresh.last_read().headings_used);

  ASSERT_TRUE(grown.predicted.known);
  ASSERT_EQ(grown.stations.size(), whole.stations.size());
  // What the scans read before the cut keep (the first read's gates) moves the σ by far less
  // than 1 % and a station's scan count by a scan or two.
  testing_support::ExpectSameSigma(grown.predicted, whole.predicted);
  for (size_t i = 0; i < whole.stations.size(); ++i) {
    EXPECT_NEAR(grown.stations[i].scans, whole.stations[i].scans, 2) << "station " << i;
  }
  EXPECT_EQ(grown.enough, whole.enough);

  // Nothing gained: each log is read on from its end (the last line ended).
  session.Refresh();
  EXPECT_EQ(session.last_read().gnss_log.from_byte, static_cast<int64_t>(gnss.size()));
  EXPECT_EQ(session.last_read().heading_log.from_byte, static_cast<int64_t>(heading.size()));
}

// GNSS and heading in one log: read once, its headings those of the same read.
TEST(PoseLogFollowerTest, ReadsOneLogOnceForBoth) {
  const testing_support::ScratchDir scratch("wallcal_pose_logs_one_");
  const fs::path path = scratch.path() / "poses.nmea";
  const std::string sample =
      testing_support::ReadFile(std::string(WALLCAL_SOURCE_DIR) + "/samples/lms291-sapporo/gnss.nmea");
  const std::string headings = "1747031522.050 $HEHDT,35.0024,T*2F\n";
  const size_t cut = sample.find('\n', sample.size() / 2) + 1;
  testing_support::WriteFirstBytes(path, sample, cut);
  std::ofstream(path, std::ios::binary | std::ios::app) << headings;
  io::SessionSpec session;
  session.gnss_log = session.heading_log = path.string();
  guide::PoseLogFollower follower(session);
  recording::PoseLogs logs = follower.Read();
  EXPECT_EQ(follower.gnss_read().from_byte, 0);
  ASSERT_EQ(logs.headings.headings.size(), 1u);
  EXPECT_EQ(logs.headings.fixes.size(), logs.gnss.fixes.size());

  std::ofstream(path, std::ios::binary | std::ios::app) << sample.substr(cut);
  logs = follower.Read();
  const int64_t read_on_from = static_cast<int64_t>(cut + headings.size());
  EXPECT_EQ(follower.gnss_read().from_byte, read_on_from);
  EXPECT_EQ(follower.heading_read().from_byte, read_on_from);
  EXPECT_EQ(logs.headings.headings.size(), 1u);
  EXPECT_EQ(logs.gnss.fixes.size(), io::ReadNmea(path.string()).fixes.size());
  EXPECT_EQ(logs.headings.fixes.size(), logs.gnss.fixes.size());
}

// ---- recordings --------------------------------------------------------------------------

using testing_support::GrowingRosbag2Folder;

// Every scan logged (75 Hz): an MCAP file's 1 MiB chunks then close several times over the
// session, as a recorder's do over a longer one.
sim::SimulationConfig SapporoConfig() {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
  config.log_every_n = 1;
  return config;
}

// Reads the follower on after each step of `grow` (shares of the recording) and expects the
// logs of a whole read of the recording as it stands, each read after the first started where
// the last one stopped. A step the whole reader refuses (no topic yet: an MCAP file's first
// chunk not closed; a split file's header not whole yet) is not compared; the follower is read
// on all the same.
void ExpectReadOnAsWhole(const std::string& session_dir, const std::function<void(double)>& grow,
                         const std::string& what) {
  const io::SessionSpec spec = io::ReadSession(session_dir);
  guide::PoseLogFollower follower(spec);
  int compared = 0;
  bool compared_before = false;
  for (const double share : {0.15, 0.4, 0.41, 0.62, 0.77, 1.0}) {
    grow(share);
    const std::string where = what + " at " + std::to_string(share);
    recording::PoseLogs whole;
    try {
      whole = recording::ReadPoseLogs(spec);
    } catch (const io::InputError&) {
      try {
        follower.Read();
      } catch (const io::InputError&) {
      }
      continue;
    }
    const recording::PoseLogs logs = follower.Read();
    testing_support::ExpectSameLog(logs.gnss, whole.gnss, where + ", GNSS");
    testing_support::ExpectSameLog(logs.headings, whole.headings, where + ", heading");
    EXPECT_GT(logs.gnss.fixes.size(), 0u) << where;
    EXPECT_GT(logs.headings.headings.size(), 0u) << where;
    if (compared_before) {
      EXPECT_GT(follower.gnss_read().from_byte, 0) << where;
    }
    EXPECT_EQ(follower.heading_read().from_byte, follower.gnss_read().from_byte) << where;
    compared_before = true;
    ++compared;
  }
  EXPECT_GE(compared, 4) << what;
}

// Grows the file at `path` to a share of `content`, cut at any byte.
std::function<void(double)> GrowByBytes(const fs::path& path) {
  return [path, content = testing_support::ReadFile(path)](double share) {
    testing_support::WriteFirstBytes(
        path, content, static_cast<size_t>(share * static_cast<double>(content.size())));
  };
}

struct RecordingCase {
  const char* name;
  sim::SessionFormat format;  // as simulated
  bool folder;                // split into a rosbag2 folder (4 files)
  bool metadata;
};

class PoseLogFollowerRecordingTest : public testing::TestWithParam<RecordingCase> {};

TEST_P(PoseLogFollowerRecordingTest, ReadsARecordingOnAsAWholeReadOfEachStep) {
  const testing_support::ScratchDir scratch("wallcal_pose_logs_recorded_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(SapporoConfig(), 13, dir.string(), GetParam().format);
  const io::SessionSpec spec = io::ReadSession(dir.string());
  const std::string recorded = spec.gnss_log;
  if (GetParam().format == sim::SessionFormat::kRos1 ||
      (GetParam().format == sim::SessionFormat::kMcap && !GetParam().folder)) {
    ExpectReadOnAsWhole(dir.string(), GrowByBytes(recorded), GetParam().name);
    return;
  }
  // A .db3 file grown row by row in place, or a rosbag2 folder growing file by file.
  const testing_support::SplitFolder complete = testing_support::SplitIntoFiles(
      recorded, scratch.path() / "complete" / "rec", GetParam().folder ? 4 : 1, 64 * 1024);
  fs::remove(recorded);
  GrowingRosbag2Folder folder(complete, dir / "rec", GetParam().metadata);
  folder.WriteUpTo(0.05);
  testing_support::PointSessionAt(
      dir, GetParam().folder ? folder.path().string() : (folder.path() / complete.files[0]).string());
  ExpectReadOnAsWhole(dir.string(), [&](double share) { folder.WriteUpTo(share); },
                      GetParam().name);
}

INSTANTIATE_TEST_SUITE_P(
    Recordings, PoseLogFollowerRecordingTest,
    testing::Values(RecordingCase{"Ros1Bag", sim::SessionFormat::kRos1, false, false},
                    RecordingCase{"Mcap", sim::SessionFormat::kMcap, false, false},
                    RecordingCase{"Db3", sim::SessionFormat::kDb3, false, false},
                    RecordingCase{"Rosbag2FolderDb3", sim::SessionFormat::kDb3, true, false},
                    RecordingCase{"Rosbag2FolderMcap", sim::SessionFormat::kMcap, true, true}),
    [](const testing::TestParamInfo<RecordingCase>& param_info) {
      return param_info.param.name;
    });

// "$body*hh" with the right checksum.
std::string Sentence(const std::string& body) { return "$" + body + "*" + io::NmeaChecksum(body); }

// GNSS and heading as nmea_msgs/Sentence messages on one topic of an MCAP file: the simulated
// session's NMEA lines, their logger stamps in the header, and an RMC a third of the way in
// whose date is the day after the stamps' (it dates the GGAs before it too, which moves their
// epochs by a day: they are read again when it comes). Grown by bytes.
TEST(PoseLogFollowerRecordingTest, ReadsNmeaSentenceTopicsOnAsAWholeReadOfEachStep) {
  const testing_support::ScratchDir scratch("wallcal_pose_logs_sentences_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(SapporoConfig(), 13, dir.string(), sim::SessionFormat::kText);
  std::vector<std::pair<double, std::string>> lines;
  for (const char* name : {"gnss.nmea", "heading.nmea"}) {
    std::istringstream in(testing_support::ReadFile(dir / name));
    for (std::string line; std::getline(in, line);) {
      const size_t space = line.find(' ');
      if (space == std::string::npos || line[space + 1] != '$') continue;
      lines.emplace_back(std::stod(line.substr(0, space)), line.substr(space + 1));
    }
  }
  std::stable_sort(lines.begin(), lines.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  ASSERT_GT(lines.size(), 300u);
  {
    const double stamp_s = lines[lines.size() / 3].first;
    const std::time_t t = static_cast<std::time_t>(stamp_s) + 86400;
    std::tm utc{};
    gmtime_r(&t, &utc);
    char body[96];
    std::snprintf(body, sizeof body, "GPRMC,%02d%02d%02d.00,A,4304.2741,N,14120.3917,E,0.0,0.0,%02d%02d%02d,,,A",
                  utc.tm_hour, utc.tm_min, utc.tm_sec, utc.tm_mday, utc.tm_mon + 1,
                  utc.tm_year % 100);
    lines.insert(lines.begin() + static_cast<long>(lines.size() / 3), {stamp_s, Sentence(body)});
  }
  const fs::path path = dir / "nmea.mcap";
  {
    recording::McapWriter writer(path.string(), recording::ChunkCompression::kZstd, 4096);
    const uint16_t channel = writer.AddChannel(
        "/nmea", "nmea_msgs/msg/Sentence",
        recording::RosTypeDefinition(recording::RosType::kNmeaSentence,
                                     recording::WireFormat::kCdr));
    recording::NmeaSentenceMsg msg;
    msg.header.frame_id = "gps";
    for (const auto& [stamp_s, sentence] : lines) {
      msg.header.stamp_s = stamp_s;
      msg.sentence = sentence;
      writer.Write(channel, stamp_s, stamp_s,
                   recording::EncodeNmeaSentence(msg, recording::WireFormat::kCdr));
    }
    writer.Close();
  }
  io::SessionSpec spec = io::ReadSession(dir.string());
  spec.gnss_log = spec.heading_log = path.string();
  spec.gnss_topic = spec.heading_topic = "/nmea";
  io::WriteFileAtomically(spec.file, io::FormatSessionYaml(spec));
  ExpectReadOnAsWhole(dir.string(), GrowByBytes(path), "nmea_msgs/Sentence");
}

// The attitude sentences of the heading log come with its headings, from the same read on; an
// attitude log of its own is read on by itself, and one still empty is no error.
TEST(PoseLogFollowerTest, ReadsTheAttitudeStreamOnWithTheLogThatHoldsIt) {
  const testing_support::ScratchDir scratch("wallcal_pose_logs_attitude_");
  const auto pashr = [](double stamp_s, double roll_deg) {
    char body[160];
    std::snprintf(body, sizeof(body), "PASHR,000000.00,35.00,T,%+.4f,+0.5000,0.00,,,,1,0",
                  roll_deg);
    return std::to_string(stamp_s) + " $" + body + "*" + io::NmeaChecksum(body) + "\n";
  };
  const fs::path heading = scratch.path() / "heading.nmea";
  const fs::path own = scratch.path() / "attitude.nmea";
  const std::string first = "1747031522.050 $HEHDT,35.0024,T*2F\n" + pashr(1747031522.06, 1.0);
  testing_support::WriteFile(heading.string(), first);
  testing_support::WriteFile(own.string(), "");
  io::SessionSpec session;
  session.gnss_log = (scratch.path() / "gnss.nmea").string();
  testing_support::WriteFile(session.gnss_log, "");
  session.heading_log = session.attitude_log = heading.string();
  session.attitude_time_offset_s = 0.5;
  guide::PoseLogFollower follower(session);
  recording::PoseLogs logs = follower.Read();
  ASSERT_EQ(logs.attitudes.attitudes.size(), 1u);
  EXPECT_DOUBLE_EQ(logs.attitudes.attitudes[0].stamp_s, 1747031522.56);

  std::ofstream(heading, std::ios::binary | std::ios::app) << pashr(1747031522.16, 2.0);
  logs = follower.Read();
  EXPECT_EQ(follower.attitude_read().from_byte, static_cast<int64_t>(first.size()));
  EXPECT_EQ(follower.attitude_read().from_byte, follower.heading_read().from_byte);
  ASSERT_EQ(logs.attitudes.attitudes.size(), 2u);
  EXPECT_NEAR(logs.attitudes.attitudes[1].roll_rad, 2.0 * kDegToRad, 1e-12);
  EXPECT_EQ(logs.headings.headings.size(), 1u);

  // A log of its own, empty at first, then grown.
  session.attitude_log = own.string();
  guide::PoseLogFollower own_follower(session);
  EXPECT_TRUE(own_follower.Read().attitudes.attitudes.empty());
  std::ofstream(own, std::ios::binary | std::ios::app) << pashr(1747031522.26, 3.0);
  logs = own_follower.Read();
  ASSERT_EQ(logs.attitudes.attitudes.size(), 1u);
  EXPECT_EQ(own_follower.attitude_read().from_byte, 0);
  EXPECT_GT(own_follower.attitude_read().bytes, 0);
}

// A recording's attitude topic (sensor_msgs/Imu in an MCAP file) is read whole at each
// refresh, beside the GNSS and heading topics read on: Read() gives the attitude stream a
// whole read gives.
TEST(PoseLogFollowerRecordingTest, ReadsARecordedAttitudeTopicAsAWholeRead) {
  const testing_support::ScratchDir scratch("wallcal_pose_logs_recorded_attitude_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(
      sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) +
                                "/configs/simulate/bench_lms291_yard2_attitude.yaml"),
      5, dir.string(), sim::SessionFormat::kMcap);
  const io::SessionSpec spec = io::ReadSession(dir.string());
  ASSERT_FALSE(spec.attitude_topic.empty());
  guide::PoseLogFollower follower(spec);
  const recording::PoseLogs whole = recording::ReadPoseLogs(spec);
  ASSERT_GT(whole.attitudes.attitudes.size(), 0u);
  for (int refresh = 0; refresh < 2; ++refresh) {
    const recording::PoseLogs logs = follower.Read();
    testing_support::ExpectSameLog(logs.gnss, whole.gnss, "GNSS");
    testing_support::ExpectSameLog(logs.headings, whole.headings, "heading");
    ASSERT_EQ(logs.attitudes.attitudes.size(), whole.attitudes.attitudes.size());
    for (size_t i = 0; i < whole.attitudes.attitudes.size(); ++i) {
      const io::AttitudeSample& a = logs.attitudes.attitudes[i];
      const io::AttitudeSample& b = whole.attitudes.attitudes[i];
      EXPECT_TRUE(a.stamp_s == b.stamp_s && a.roll_rad == b.roll_rad &&
                  a.pitch_rad == b.pitch_rad && a.line == b.line)
          << "attitude " << i;
    }
    EXPECT_EQ(logs.attitudes.lines_read, whole.attitudes.lines_read);
  }
}

}  // namespace
}  // namespace wallcal
