// SPDX-License-Identifier: Apache-2.0
// The guide kept between refreshes (GuideSession) reads the pose logs on from where the last
// refresh stopped, as it does the text scan log: the GNSS log cut between a GGA and its GST,
// the heading log in the middle of a sentence, then both grown to the whole. The grown session
// holds the fixes and headings of a fresh read to the one, and reports what a fresh session
// reports (within what the scan log's own reading on leaves: guide_follow_test.cc).

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "common/angles.h"
#include "guide/guide_session.h"
#include "guide/pose_logs.h"
#include "io/text/nmea_reader.h"
#include "io/writers/writers.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/guide_expect.h"
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

}  // namespace
}  // namespace wallcal
