// SPDX-License-Identifier: Apache-2.0
// The guide kept between refreshes (GuideSession) reads a ROS 1 bag still being recorded and an
// MCAP file still being written on from where it stopped: the second refresh starts at the end
// of the last whole record the first one read, detects only the scans after the last settled
// one, and reports what a fresh GuideSession reports on the same bytes. A last record cut off
// (the recorder between two writes) is read at the next refresh, not reported as damage.
//
// A gzip-compressed CARMEN log is read on the same way (inflated up to where the last read
// stopped, parsed from there). A rosbag2 folder (.db3 or MCAP storage, with and without
// metadata.yaml) is read on file by file as split files appear, and a folder replaced by a
// shorter recording is read from its start.
//
// The sessions are simulated and written by the project's recording writers, then cut, as the
// --follow tests do: a cut bag or MCAP file is what a recorder leaves on disk while it runs (no
// index, no summary, a record half written at the end).

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <zlib.h>

#include "guide/guide_session.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/scratch_dir.h"
#include "test/support/guide_expect.h"
#include "test/support/rosbag2_folders.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

sim::SimulationConfig Sapporo() {
  sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
  // Every scan logged (75 Hz): the chunks (768 kB in a bag, 1 MiB in MCAP) then close many
  // times over the session, as a recorder's do over a longer one.
  config.log_every_n = 1;
  return config;
}

struct Case {
  sim::SessionFormat format;
  const char* file;
};

class GuideResumeTest : public testing::TestWithParam<Case> {};

TEST_P(GuideResumeTest, ReadsARecordingOnFromWhereItStopped) {
  const testing_support::ScratchDir scratch("wallcal_guide_resume_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(Sapporo(), 11, dir.string(), GetParam().format);
  const fs::path path = dir / GetParam().file;
  const std::string content = testing_support::ReadFile(path);
  guide::GuideOptions options;
  options.session_path = dir.string();
  options.threads = 2;

  // Cut inside the recording (a record half written), then a few bytes more (still inside it).
  const size_t cut = content.size() * 3 / 5 + 17;
  testing_support::WriteFirstBytes(path, content, cut);
  guide::GuideSession session(options);
  const guide::GuideReport part = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_EQ(session.last_read().scan_log_from_byte, 0);
  EXPECT_GE(part.stations.size(), 3u);
  testing_support::WriteFirstBytes(path, content, cut + 5);
  const guide::GuideReport torn = session.Refresh();  // not an error: read next time
  EXPECT_TRUE(session.last_read().incremental);
  EXPECT_LE(session.last_read().scan_log_from_byte, static_cast<int64_t>(cut));
  EXPECT_EQ(torn.stations.size(), part.stations.size());

  // The same bytes, read by a fresh session: the reference for the grown one.
  testing_support::WriteFirstBytes(path, content, content.size());
  const guide::GuideReport grown = session.Refresh();
  const guide::ReadCounts read = session.last_read();
  guide::GuideSession fresh_session(options);
  const guide::GuideReport fresh = fresh_session.Refresh();
  const int64_t all_scans = fresh_session.last_read().scans_detected;
  ASSERT_TRUE(fresh.predicted.known);

  EXPECT_TRUE(read.incremental);
  // Read on from the end of the last whole record before the cut: at most a chunk (1 MiB)
  // and the last kSettleS of scans before it.
  EXPECT_GT(read.scan_log_from_byte, static_cast<int64_t>(cut) - (4 << 20));
  EXPECT_LE(read.scan_log_from_byte, static_cast<int64_t>(cut));
  // Only the scans after the last settled one are detected: the cut is at 60 % of the bytes,
  // and the whole records before it (less a chunk and the last seconds) hold a fifth at least.
  EXPECT_GT(read.scans_kept, all_scans / 5);
  EXPECT_EQ(read.scans_kept + read.scans_detected, all_scans);

  // As for a text log (GuideSessionTest.ReadsATextScanLogOnFromWhereItStopped): the scans read
  // before the cut were detected with the gates of the first read's first pass; a scan or two
  // at a station's edge may differ, which moves the σ by far less than 1 %.
  EXPECT_EQ(grown.stations.size(), fresh.stations.size());
  testing_support::ExpectSameSigma(grown.predicted, fresh.predicted);
  for (size_t i = 0; i < fresh.stations.size() && i < grown.stations.size(); ++i) {
    EXPECT_NEAR(grown.stations[i].scans, fresh.stations[i].scans, 2) << "station " << i;
  }

  // A recording shorter than what was read (a new one under the same name): from its start.
  testing_support::WriteFirstBytes(path, content, cut);
  const guide::GuideReport again = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_EQ(session.last_read().scans_kept, 0);
  EXPECT_EQ(again.stations.size(), part.stations.size());
}

INSTANTIATE_TEST_SUITE_P(Recordings, GuideResumeTest,
                         testing::Values(Case{sim::SessionFormat::kRos1, "session.bag"},
                                         Case{sim::SessionFormat::kRos1Lz4, "session.bag"},
                                         Case{sim::SessionFormat::kMcap, "session.mcap"}),
                         [](const testing::TestParamInfo<Case>& param_info) {
                           return param_info.param.format == sim::SessionFormat::kMcap ? "Mcap"
                                  : param_info.param.format == sim::SessionFormat::kRos1 ? "Ros1Bag"
                                                                                  : "Ros1BagLz4";
                         });

// A gzip-compressed CARMEN log being written: the compressed stream cut in the middle (as a
// logger leaves it between two flushes), then whole. The second refresh inflates up to the
// first scan not settled and parses from there.
TEST(GuideResumeGzipTest, ReadsAGzipScanLogOnFromWhereItStopped) {
  const testing_support::ScratchDir scratch("wallcal_guide_resume_gz_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(Sapporo(), 11, dir.string(), sim::SessionFormat::kText);
  const fs::path scans = dir / "scans.clf";
  {
    const std::string text = testing_support::ReadFile(scans);
    gzFile out = gzopen(scans.string().c_str(), "wb6");
    ASSERT_NE(out, nullptr);
    ASSERT_EQ(gzwrite(out, text.data(), static_cast<unsigned>(text.size())),
              static_cast<int>(text.size()));
    gzclose(out);
  }
  const std::string content = testing_support::ReadFile(scans);
  guide::GuideOptions options;
  options.session_path = dir.string();
  options.threads = 2;
  // The pose logs are whole: the scans' share is what grows.
  testing_support::WriteFirstBytes(scans, content, content.size() * 3 / 5);
  guide::GuideSession session(options);
  const guide::GuideReport part = session.Refresh();
  EXPECT_EQ(session.last_read().scan_log_from_byte, 0);
  EXPECT_GE(part.stations.size(), 3u);
  testing_support::WriteFirstBytes(scans, content, content.size());
  const guide::GuideReport grown = session.Refresh();
  const guide::ReadCounts read = session.last_read();
  guide::GuideSession fresh_session(options);
  const guide::GuideReport fresh = fresh_session.Refresh();
  const int64_t all_scans = fresh_session.last_read().scans_detected;
  EXPECT_TRUE(read.incremental);
  EXPECT_GT(read.scans_kept, all_scans / 5);
  EXPECT_EQ(read.scans_kept + read.scans_detected, all_scans);
  EXPECT_EQ(grown.stations.size(), fresh.stations.size());
  testing_support::ExpectSameSigma(grown.predicted, fresh.predicted);
}

// A rosbag2 folder being recorded: the simulated session split into 4 storage files
// (test/support/rosbag2_folders.h), grown so that a split file appears between two refreshes.
// After each step the report is that of a fresh session on the same folder: the same stations,
// the σ within 1 %, every scan read once (kept + detected = a fresh read's), the same fixes and
// headings.
struct FolderCase {
  const char* name;
  sim::SessionFormat format;  // kDb3: .db3 storage; kMcap: .mcap storage
  bool metadata;
};

class GuideResumeRosbag2Test : public testing::TestWithParam<FolderCase> {};

TEST_P(GuideResumeRosbag2Test, ReadsARosbag2FolderOnFileByFile) {
  const testing_support::ScratchDir scratch("wallcal_guide_resume_rosbag2_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(Sapporo(), 11, dir.string(), GetParam().format);
  const fs::path recorded =
      dir / (GetParam().format == sim::SessionFormat::kMcap ? "session.mcap" : "session.db3");
  const testing_support::SplitFolder complete = testing_support::SplitIntoFiles(
      recorded.string(), scratch.path() / "complete" / "session", 4,
      256 * 1024);  // a few MCAP chunks a file
  ASSERT_EQ(complete.files.size(), 4u);
  fs::remove(recorded);
  testing_support::GrowingRosbag2Folder folder(complete, dir / "session", GetParam().metadata);
  folder.WriteUpTo(0.5);
  testing_support::PointSessionAt(dir, folder.path().string());
  guide::GuideOptions options;
  options.session_path = dir.string();
  options.threads = 2;

  guide::GuideSession session(options);
  const guide::GuideReport first = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_GE(first.stations.size(), 3u);
  for (const double share : {0.6, 0.8, 1.0}) {
    SCOPED_TRACE("at " + std::to_string(share));
    folder.WriteUpTo(share);
    const guide::GuideReport grown = session.Refresh();
    const guide::ReadCounts read = session.last_read();
    guide::GuideSession fresh_session(options);
    const guide::GuideReport fresh = fresh_session.Refresh();
    const guide::ReadCounts& whole = fresh_session.last_read();
    ASSERT_TRUE(fresh.predicted.known);
    EXPECT_TRUE(read.incremental);
    EXPECT_GT(read.scans_kept, 0);
    EXPECT_EQ(read.scans_kept + read.scans_detected, whole.scans_detected);
    EXPECT_GT(read.gnss_log.from_byte, 0);
    EXPECT_EQ(read.fixes_used, whole.fixes_used);
    EXPECT_EQ(read.headings_used, whole.headings_used);
    ASSERT_EQ(grown.stations.size(), fresh.stations.size());
    testing_support::ExpectSameSigma(grown.predicted, fresh.predicted);
    for (size_t i = 0; i < fresh.stations.size(); ++i) {
      EXPECT_NEAR(grown.stations[i].scans, fresh.stations[i].scans, 2) << "station " << i;
    }
  }

  // The folder replaced by a shorter recording (the same name recorded again): from its start.
  folder.Restart();
  folder.WriteUpTo(0.5);
  const guide::GuideReport again = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_EQ(session.last_read().scans_kept, 0);
  EXPECT_EQ(again.stations.size(), first.stations.size());
}

INSTANTIATE_TEST_SUITE_P(
    Storages, GuideResumeRosbag2Test,
    testing::Values(FolderCase{"Db3", sim::SessionFormat::kDb3, false},
                    FolderCase{"Db3WithMetadata", sim::SessionFormat::kDb3, true},
                    FolderCase{"Mcap", sim::SessionFormat::kMcap, false},
                    FolderCase{"McapWithMetadata", sim::SessionFormat::kMcap, true}),
    [](const testing::TestParamInfo<FolderCase>& param_info) { return param_info.param.name; });

}  // namespace
}  // namespace wallcal
