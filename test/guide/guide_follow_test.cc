// SPDX-License-Identifier: Apache-2.0
// wallcal guide --follow on logs that are still being written: a text log appended line by line
// (an unfinished last line included), a ROS 1 bag without its index, an MCAP file without
// its summary and a rosbag2 folder whose split files appear (.db3 and MCAP storage), each grown
// in pieces by a writer thread while the program runs. The guide must
// print again as they grow, each time on what has been written. And the guide kept between
// refreshes (GuideSession) reads a text scan log on from where it stopped, with the outcome of
// a fresh read of the whole.
//
// Tolerances of 1 mm keep the guide from stopping at "enough" (the simulated session meets the
// default ones after three stations), so it runs until --max-seconds. No timing is asserted:
// the writer is done after about 5 s, well inside the 15 s the guide follows; what is asserted
// holds whatever the pacing: the first report is on the first piece (written before the guide
// starts) and the last on the whole session (ten stations).

#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "guide/guide_session.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"
#include "test/support/guide_expect.h"
#include "test/support/rosbag2_folders.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

// The "stations": N and "enough" of each JSON line.
struct Update {
  int stations = 0;
  bool enough = false;
};
std::vector<Update> Updates(const std::string& output) {
  std::vector<Update> updates;
  std::istringstream in(output);
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("{\"stations\": ", 0) != 0) continue;
    Update u;
    u.stations = std::stoi(line.substr(13));
    u.enough = line.find("\"enough\": true") != std::string::npos;
    updates.push_back(u);
  }
  return updates;
}

// Grows `files` (each its whole content, the first shares[0] of it written) to the following
// shares, a piece at a time.
void Grow(const std::vector<std::pair<fs::path, std::string>>& files,
          const std::vector<double>& shares) {
  std::vector<size_t> written;
  for (const auto& file : files) {
    written.push_back(static_cast<size_t>(shares[0] * file.second.size()));
  }
  for (size_t piece = 1; piece < shares.size(); ++piece) {
    const double share = shares[piece];
    std::this_thread::sleep_for(std::chrono::milliseconds(1500));
    for (size_t f = 0; f < files.size(); ++f) {
      const std::string& content = files[f].second;
      const size_t upto = share >= 1.0 ? content.size()
                                       : static_cast<size_t>(share * content.size());
      if (upto <= written[f]) continue;
      std::ofstream out(files[f].first, std::ios::binary | std::ios::app);
      out.write(content.data() + written[f], static_cast<std::streamsize>(upto - written[f]));
      written[f] = upto;
    }
  }
}

// Runs guide --follow on the session in `dir` (tolerances of 1 mm) while a thread runs `grow`.
std::vector<Update> FollowWhileGrowing(const fs::path& dir, const std::function<void()>& grow) {
  const fs::path options = dir / "tight.yaml";
  std::ofstream(options) << "acceptance:\n  max_sigma_xy_m: 0.001\n  max_sigma_yaw_deg: 0.001\n";
  std::thread writer(grow);
  const testing_support::ProgramRun run =
      testing_support::RunWallcal({"guide", dir.string(), "--follow", "--json", "--max-seconds",
                                   "15", "--next", "1", "--config", options.string()});
  writer.join();
  EXPECT_EQ(run.exit_code, 0) << run.err;
  return Updates(run.out);
}

// Simulates the session, truncates its logs to the first share, and runs guide --follow while
// a thread grows them to the whole.
std::vector<Update> FollowGrowingSession(sim::SessionFormat format,
                                         const std::vector<std::string>& logs,
                                         const sim::SimulationConfig& config) {
  const testing_support::ScratchDir scratch("wallcal_guide_follow_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(config, 5, dir.string(), format);
  const std::vector<double> shares = {0.35, 0.55, 0.8, 1.0};
  std::vector<std::pair<fs::path, std::string>> files;
  for (const std::string& name : logs) {
    const fs::path path = dir / name;
    const std::string content = testing_support::ReadFile(path);
    files.emplace_back(path, content);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(content.data(), static_cast<std::streamsize>(shares[0] * content.size()));
  }
  return FollowWhileGrowing(dir, [&files, &shares] { Grow(files, shares); });
}

// Simulates the session as one recording, splits it into a rosbag2 folder of three storage
// files, shows the folder with its first share written, and runs guide --follow while a thread
// grows it to the whole (each split file appearing in turn).
std::vector<Update> FollowGrowingFolder(sim::SessionFormat format, bool metadata,
                                        const sim::SimulationConfig& config) {
  const testing_support::ScratchDir scratch("wallcal_guide_follow_rosbag2_");
  const fs::path dir = scratch.path() / "session";
  sim::WriteSimulatedSession(config, 5, dir.string(), format);
  const fs::path recorded =
      dir / (format == sim::SessionFormat::kMcap ? "session.mcap" : "session.db3");
  const testing_support::SplitFolder complete =
      testing_support::SplitIntoFiles(recorded.string(), scratch.path() / "complete" / "bag", 3);
  fs::remove(recorded);
  testing_support::GrowingRosbag2Folder folder(complete, dir / "bag", metadata);
  const std::vector<double> shares = {0.35, 0.55, 0.8, 1.0};
  folder.WriteUpTo(shares[0]);
  testing_support::PointSessionAt(dir, folder.path().string());
  return FollowWhileGrowing(dir, [&folder, &shares] {
    for (size_t piece = 1; piece < shares.size(); ++piece) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1500));
      folder.WriteUpTo(shares[piece]);
    }
  });
}

void ExpectGrowsToTheWhole(const std::vector<Update>& updates) {
  ASSERT_GE(updates.size(), 2u);
  EXPECT_LT(updates.front().stations, updates.back().stations);
  EXPECT_GE(updates.front().stations, 1);
  EXPECT_FALSE(updates.back().enough);
  EXPECT_EQ(updates.back().stations, 10);
  for (size_t i = 1; i < updates.size(); ++i) {
    EXPECT_GE(updates[i].stations, updates[i - 1].stations);
  }
}

sim::SimulationConfig Sapporo() {
  return sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) +
                                   "/configs/simulate/lms291_sapporo.yaml");
}

TEST(GuideFollowTest, FollowsTextLogsBeingAppended) {
  ExpectGrowsToTheWhole(FollowGrowingSession(sim::SessionFormat::kText,
                                           {"scans.clf", "gnss.nmea", "heading.nmea"}, Sapporo()));
}

TEST(GuideFollowTest, FollowsARos1BagBeingRecorded) {
  ExpectGrowsToTheWhole(FollowGrowingSession(sim::SessionFormat::kRos1, {"session.bag"}, Sapporo()));
}

TEST(GuideFollowTest, FollowsAnMcapFileBeingWritten) {
  // Every scan logged (75 Hz): the 1 MiB chunks then close several times over the session, as
  // a recorder's do over a longer one.
  sim::SimulationConfig config = Sapporo();
  config.log_every_n = 1;
  ExpectGrowsToTheWhole(FollowGrowingSession(sim::SessionFormat::kMcap, {"session.mcap"}, config));
}

TEST(GuideFollowTest, FollowsARosbag2FolderBeingRecorded) {
  ExpectGrowsToTheWhole(FollowGrowingFolder(sim::SessionFormat::kDb3, false, Sapporo()));
}

TEST(GuideFollowTest, FollowsAnMcapStorageRosbag2FolderBeingRecorded) {
  sim::SimulationConfig config = Sapporo();
  config.log_every_n = 1;
  ExpectGrowsToTheWhole(FollowGrowingFolder(sim::SessionFormat::kMcap, true, config));
}

// The scan log cut in the middle of a line (as a logger leaves it between two writes), the
// GNSS and heading logs up to the same time; then the rest of every log appended.
TEST(GuideSessionTest, ReadsATextScanLogOnFromWhereItStopped) {
  const testing_support::ScratchDir scratch("wallcal_guide_session_");
  const fs::path dir = scratch.path();
  sim::WriteSimulatedSession(Sapporo(), 11, dir.string(), sim::SessionFormat::kText);
  std::vector<std::pair<fs::path, std::string>> files;
  for (const char* name : {"scans.clf", "gnss.nmea", "heading.nmea"}) {
    files.emplace_back(dir / name, testing_support::ReadFile(dir / name));
  }
  guide::GuideOptions options;
  options.session_path = dir.string();
  options.threads = 2;
  const guide::GuideReport whole = guide::GuideSession(options).Refresh();
  ASSERT_TRUE(whole.predicted.known);

  const std::string& scans = files[0].second;
  const size_t cut = scans.size() / 2 + 17;  // inside a line
  ASSERT_NE(scans[cut - 1], '\n');
  for (const auto& [path, content] : files) {
    // The pose logs a little beyond the scans, as their fixes arrive while a scan is written.
    const size_t upto = path == files[0].first ? cut : content.size() / 2 + content.size() / 50;
    const size_t line_end = path == files[0].first ? upto : content.find('\n', upto) + 1;
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(content.data(), static_cast<std::streamsize>(line_end));
  }
  guide::GuideSession session(options);
  const guide::GuideReport half = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_EQ(session.last_read().scan_log_from_byte, 0);
  EXPECT_GE(half.stations.size(), 3u);
  EXPECT_LT(half.stations.size(), whole.stations.size());

  for (const auto& [path, content] : files) {
    std::ofstream(path, std::ios::binary | std::ios::trunc)
        .write(content.data(), static_cast<std::streamsize>(content.size()));
  }
  const guide::GuideReport grown = session.Refresh();
  const guide::ReadCounts& read = session.last_read();
  EXPECT_TRUE(read.incremental);
  // Read on from the last scan line settled before the cut, not from the start: at most the
  // last kSettleS (5 s) of scans, a few hundred kB, before the cut.
  EXPECT_GT(read.scan_log_from_byte, static_cast<int64_t>(cut) - 1000000);
  EXPECT_LE(read.scan_log_from_byte, static_cast<int64_t>(cut));
  EXPECT_GT(read.scans_kept, 0);
  EXPECT_EQ(grown.stations.size(), whole.stations.size());
  // The scans read before the cut were detected with the gates of the first read's first pass,
  // the whole with those of its own: a scan or two at a station's edge may differ. With
  // thousands of observations per σ, that moves the σ by far less than 1 %.
  testing_support::ExpectSameSigma(grown.predicted, whole.predicted);
  for (size_t i = 0; i < whole.stations.size(); ++i) {
    EXPECT_NEAR(grown.stations[i].scans, whole.stations[i].scans, 2) << "station " << i;
  }

  // A scan log shorter than what was read (a new recording under the same name) is read from
  // its start.
  std::ofstream(files[0].first, std::ios::binary | std::ios::trunc)
      .write(scans.data(), static_cast<std::streamsize>(cut));
  const guide::GuideReport again = session.Refresh();
  EXPECT_FALSE(session.last_read().incremental);
  EXPECT_EQ(session.last_read().scans_kept, 0);
  EXPECT_LT(again.stations.size(), whole.stations.size());
}

}  // namespace
}  // namespace wallcal
