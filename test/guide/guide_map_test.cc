// SPDX-License-Identifier: Apache-2.0
// The guide's report as a map of the site (what guide --serve's page draws, from guide --json):
// the walls, each station's pose, the vehicle, each next stop as the pose the stop model places
// it at and the move to it in words; and the warnings a crew should see: a wall never detected,
// a log that stopped growing, fixes below RTK fixed while the GNSS log grows.

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/angles.h"
#include "guide/follow.h"
#include "guide/guide.h"
#include "guide/guide_session.h"
#include "guide/guide_text.h"
#include "sim/recording_session.h"
#include "sim/session_cut.h"
#include "sim/simulation_config.h"
#include "test/support/json_value.h"
#include "test/support/scratch_dir.h"
#include "test/support/scratch_files.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

sim::SimulationConfig Sapporo() {
  return sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) +
                                   "/configs/simulate/lms291_sapporo.yaml");
}

// The Sapporo session cut after `share` of its scans into dir/cut (the whole in dir/full).
fs::path CutSession(const fs::path& dir, double share) {
  sim::WriteSimulatedSession(Sapporo(), 5, (dir / "full").string(), sim::SessionFormat::kText);
  sim::CutTextSession((dir / "full").string(), (dir / "cut").string(), share);
  return dir / "cut";
}

bool HasWarning(const guide::GuideReport& report, guide::GuideWarningKind kind) {
  for (const guide::GuideWarning& w : report.warnings) {
    if (w.kind == kind) return true;
  }
  return false;
}

TEST(GuideMapTest, SaysAMoveAsADriverFollowsIt) {
  const guide::SitePose from{Eigen::Vector2d(0.0, 0.0), 90.0 * kDegToRad};  // facing grid north
  const guide::SitePose to{Eigen::Vector2d(-1.0, 2.0), 105.0 * kDegToRad};
  const guide::VehicleMove move = guide::MoveBetween(from, to);
  EXPECT_NEAR(move.forward_m, 2.0, 1e-12);
  EXPECT_NEAR(move.left_m, 1.0, 1e-12);
  EXPECT_NEAR(move.turn_rad, 15.0 * kDegToRad, 1e-12);
  EXPECT_EQ(guide::MoveWords(move), "forward 2.0 m, 1.0 m to the left, turn 15° left");
  EXPECT_EQ(guide::MoveWords(guide::MoveBetween(to, from)),
            "back 2.2 m, 0.4 m to the right, turn 15° right");
  EXPECT_EQ(guide::MoveWords(guide::VehicleMove{0.2, -0.1, 0.5 * kDegToRad}), "stay where you are");
}

TEST(GuideMapTest, PlacesAStopAtItsAngleAndDistanceWithTheScannerAbreastOfTheWallsMiddle) {
  guide::StopModel model;
  calib::WallGeometry wall;  // y = 10, from x = -15 to 15; the vehicle stands south of it
  wall.id = "A";
  wall.normal_local = Eigen::Vector2d(0.0, 1.0);
  wall.offset_m = 10.0;
  wall.end_a_local = Eigen::Vector2d(-15.0, 10.0);
  wall.end_b_local = Eigen::Vector2d(15.0, 10.0);
  model.walls = {wall};
  model.side = {1.0};
  model.mount = calib::Mount{2.5, 0.0, 0.0};
  guide::StopSpec stop;
  stop.vehicle_to_wall_rad = 30.0 * kDegToRad;
  stop.distance_m = 8.0;
  guide::SitePose pose;
  ASSERT_TRUE(guide::StopPose(model, stop, &pose));
  EXPECT_NEAR(pose.yaw_rad, 60.0 * kDegToRad, 1e-12);  // φ = 90° (the normal) − ψ
  EXPECT_NEAR(pose.antenna_local_m.y(), 2.0, 1e-12);    // 8 m from the wall
  const guide::ScannerPlace scanner = guide::ScannerAt(pose, model.mount);
  EXPECT_NEAR(scanner.p_local_m.x(), 0.0, 1e-12);  // abreast of the wall's middle
  stop.wall_index = 3;
  EXPECT_FALSE(guide::StopPose(model, stop, &pose));

  const guide::SitePose vehicle{Eigen::Vector2d(0.0, 0.0), 90.0 * kDegToRad};
  guide::StopSpec second = stop;
  second.wall_index = 0;
  second.vehicle_to_wall_rad = -20.0 * kDegToRad;
  stop.wall_index = 0;
  const std::vector<guide::StopTarget> targets = guide::TargetsFor(model, {stop, second}, vehicle);
  ASSERT_EQ(targets.size(), 2u);
  EXPECT_TRUE(targets[0].has_move);
  EXPECT_NEAR(targets[0].move.turn_rad, -30.0 * kDegToRad, 1e-12);  // from 90° to 60°
  EXPECT_NEAR(targets[1].move.turn_rad, 50.0 * kDegToRad, 1e-12);   // from 60° to 110°
  EXPECT_FALSE(guide::TargetsFor(model, {stop}, std::nullopt)[0].has_move);
}

TEST(GuideMapTest, ReportsTheSiteOfASessionInMidCollection) {
  const testing_support::ScratchDir scratch("wallcal_guide_map_");
  guide::GuideOptions options;
  options.session_path = CutSession(scratch.path(), 0.4).string();
  options.threads = 2;
  const fs::path tight = scratch.path() / "tight.yaml";
  std::ofstream(tight) << "acceptance:\n  max_sigma_xy_m: 0.005\n";
  options.config_path = tight.string();
  const guide::GuideReport report = guide::AssessSession(options);
  ASSERT_EQ(report.walls.size(), 1u);
  ASSERT_GE(report.stations.size(), 3u);
  ASSERT_TRUE(report.predicted.known);
  const calib::WallGeometry& wall = report.walls[0];
  for (const guide::StationSummary& s : report.stations) {
    // The mean pose is the station's: its distance from the wall and its angle to it.
    const double distance = std::abs(wall.offset_m - wall.normal_local.dot(s.pose.antenna_local_m));
    EXPECT_NEAR(distance, s.distance_m, 0.01);
    const double side = wall.offset_m - wall.normal_local.dot(s.pose.antenna_local_m) >= 0 ? 1.0 : -1.0;
    const Eigen::Vector2d towards = side * wall.normal_local;
    EXPECT_NEAR(WrapAngle(std::atan2(towards.y(), towards.x()) - s.pose.yaw_rad),
                s.vehicle_to_wall_rad, 0.01);
  }
  ASSERT_TRUE(report.vehicle.has_value());
  EXPECT_GE(report.vehicle_s, report.stations.back().end_s);
  ASSERT_TRUE(report.mount.has_value());
  ASSERT_TRUE(report.scanner.has_value());
  EXPECT_FALSE(report.enough);
  ASSERT_FALSE(report.next.empty());
  ASSERT_EQ(report.targets.size(), report.next.size());
  EXPECT_TRUE(report.targets[0].has_move);
  for (size_t i = 0; i < report.next.size(); ++i) {
    const guide::StopTarget& t = report.targets[i];
    EXPECT_NEAR(std::abs(wall.offset_m - wall.normal_local.dot(t.pose.antenna_local_m)),
                report.next[i].stop.distance_m, 1e-9);
  }
  EXPECT_TRUE(report.warnings.empty());
  EXPECT_GT(report.ellipse.major_m, 0.0);
  EXPECT_GE(report.ellipse.major_m, report.ellipse.minor_m);
  EXPECT_EQ(report.worst_axis, guide::SigmaAxis::kX);
  EXPECT_NE(guide::NotEnoughReason(report).find("σ x"), std::string::npos);
  EXPECT_NE(guide::GuideText(report).find("from here: "), std::string::npos);

  // guide --json carries it all, one object on one line.
  const std::string json = guide::GuideJson(report);
  EXPECT_EQ(json.find('\n'), json.size() - 1);
  testing_support::Json doc;
  ASSERT_TRUE(testing_support::JsonParser(json).Parse(&doc)) << json;
  EXPECT_EQ(doc["walls"].items.size(), 1u);
  EXPECT_EQ(doc["station_poses"].items.size(), report.stations.size());
  EXPECT_NEAR(doc["vehicle"]["x_m"].number, report.vehicle->antenna_local_m.x(), 1e-3);
  EXPECT_EQ(doc["next"].items.size(), report.next.size());
  EXPECT_EQ(doc["next"].items[0]["instruction"].text, guide::StopInstruction(report, 0));
  EXPECT_NEAR(doc["next"].items[0]["target"]["yaw_deg"].number,
              report.targets[0].pose.yaw_rad * kRadToDeg, 0.01);
  EXPECT_EQ(doc["worst_axis"].text, "x");
  EXPECT_EQ(doc["warnings"].items.size(), 0u);
}

TEST(GuideMapTest, WarnsOfAWallNeverDetected) {
  const testing_support::ScratchDir scratch("wallcal_guide_map_");
  const fs::path cut = CutSession(scratch.path(), 0.4);
  // A second surveyed wall, 60 m behind the vehicle: never in view.
  std::ofstream survey(cut / "survey.csv", std::ios::app);
  for (int i = 0; i < 10; ++i) {
    for (double z : {0.5, 2.5}) {
      survey << "F" << i << (z < 1.0 ? "a" : "b") << "," << -10.0 + 2.0 * i << ",-60.0," << z
             << ",WALL2\n";
    }
  }
  survey.close();
  std::string yaml = testing_support::ReadFile(cut / "session.yaml");
  yaml += "  - {id: far_wall, code: WALL2}\n";
  std::ofstream(cut / "session.yaml") << yaml;
  guide::GuideOptions options;
  options.session_path = cut.string();
  options.threads = 2;
  const guide::GuideReport report = guide::AssessSession(options);
  ASSERT_EQ(report.walls.size(), 2u);
  ASSERT_TRUE(HasWarning(report, guide::GuideWarningKind::kWallNotSeen));
  for (const guide::GuideWarning& w : report.warnings) {
    if (w.kind == guide::GuideWarningKind::kWallNotSeen) {
      EXPECT_EQ(w.subject, "far_wall");
    }
  }
  EXPECT_NE(guide::GuideJson(report).find("\"kind\": \"wall not seen\""), std::string::npos);
}

// A GGA line (after its logger stamp) with the fix quality `quality` and its checksum anew.
std::string WithQuality(const std::string& line, char quality) {
  const size_t dollar = line.find('$'), star = line.find('*');
  if (dollar == std::string::npos || star == std::string::npos || line.find("GGA,") == std::string::npos) {
    return line;
  }
  std::string sentence = line.substr(dollar + 1, star - dollar - 1);
  size_t field = 0;
  for (int commas = 0; commas < 6 && field != std::string::npos; ++commas) field = sentence.find(',', field) + 1;
  sentence[field] = quality;
  unsigned checksum = 0;
  for (char c : sentence) checksum ^= static_cast<unsigned char>(c);
  char hex[4];
  std::snprintf(hex, sizeof(hex), "%02X", checksum);
  return line.substr(0, dollar + 1) + sentence + "*" + hex;
}

TEST(GuideFollowWarningsTest, WarnsOfLogsThatStopGrowingAndOfFloatFixes) {
  const testing_support::ScratchDir scratch("wallcal_guide_map_");
  const fs::path cut = CutSession(scratch.path(), 0.4);
  const fs::path tight = scratch.path() / "tight.yaml";
  std::ofstream(tight) << "acceptance:\n  max_sigma_xy_m: 0.001\n  max_sigma_yaw_deg: 0.001\n";
  // The rest of the GNSS log, every fix RTK float (quality 5), appended a piece at a time.
  const std::string whole = testing_support::ReadFile(scratch.path() / "full" / "gnss.nmea");
  const std::string kept = testing_support::ReadFile(cut / "gnss.nmea");
  std::vector<std::string> floats;
  std::istringstream rest(whole.substr(kept.size()));
  for (std::string line; std::getline(rest, line);) floats.push_back(WithQuality(line, '5') + "\n");
  ASSERT_GT(floats.size(), 100u);
  std::atomic<bool> done{false};
  std::thread writer([&] {
    for (size_t i = 0; i < floats.size() && !done.load(); i += 20) {
      std::ofstream out(cut / "gnss.nmea", std::ios::app);
      for (size_t j = i; j < std::min(floats.size(), i + 20); ++j) out << floats[j];
      out.close();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  guide::GuideOptions options;
  options.session_path = cut.string();
  options.config_path = tight.string();
  options.threads = 2;
  guide::GuideSession session(options);
  guide::FollowOptions follow;
  follow.period_s = 0.25;
  follow.max_seconds = 8.0;
  follow.stale_after_s = 2.0;
  bool stale_scans = false, floats_seen = false;
  guide::Follow(
      &session, follow,
      [&](const guide::GuideReport& report) {
        for (const guide::GuideWarning& w : report.warnings) {
          if (w.kind == guide::GuideWarningKind::kLogStale && w.subject.find("scans.clf") != std::string::npos) {
            stale_scans = true;
          }
          if (w.kind == guide::GuideWarningKind::kFixesNotAccepted) {
            floats_seen = true;
            EXPECT_NE(w.message.find("gnss.nmea"), std::string::npos) << w.message;
          }
        }
      },
      [](const std::string&) {});
  done = true;
  writer.join();
  EXPECT_TRUE(stale_scans) << "no warning that the scan log stopped growing";
  EXPECT_TRUE(floats_seen) << "no warning of the GNSS log growing without RTK-fixed fixes";
}

}  // namespace
}  // namespace wallcal
