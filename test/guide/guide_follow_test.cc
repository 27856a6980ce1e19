// SPDX-License-Identifier: Apache-2.0
// guide --follow on logs that are still being written: a text log appended line by line (an
// unfinished last line included), a ROS 1 bag without its index and an MCAP file without its
// summary, each grown in pieces by a writer thread while the guide runs. The guide must print
// again as they grow, each time on what has been written.
//
// Tolerances of 1 mm keep the guide from stopping at "enough" (the simulated session meets the
// default ones after three stations), so it runs until --max-seconds. No timing is asserted:
// the writer is done after about 5 s, well inside the 15 s the guide follows; what is asserted
// holds whatever the pacing: the first report is on the first piece (written before the guide
// starts) and the last on the whole session (ten stations).

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "guide/run_guide.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/scratch_dir.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

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
    const std::string content = ReadAll(path);
    files.emplace_back(path, content);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(content.data(), static_cast<std::streamsize>(shares[0] * content.size()));
  }
  const fs::path options = dir / "tight.yaml";
  std::ofstream(options) << "acceptance:\n  max_sigma_xy_m: 0.001\n  max_sigma_yaw_deg: 0.001\n";
  std::thread writer(Grow, files, shares);
  std::ostringstream out, err;
  const int status =
      guide::RunGuide({dir.string(), "--follow", "--json", "--max-seconds", "15", "--next", "1",
                       "--config", options.string()},
                      out, err);
  writer.join();
  EXPECT_EQ(status, 0) << err.str();
  return Updates(out.str());
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

}  // namespace
}  // namespace wallcal
