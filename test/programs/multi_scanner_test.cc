// SPDX-License-Identifier: Apache-2.0
// Sessions with several scanners (session.yaml `scanners:`), end to end: `wallcal simulate`
// writes one two-scanner session in text, ROS 1 bag and MCAP form and `wallcal calibrate` gives
// the same mounts from each; the emitted URDF and static TF form one tree; bad input names the
// scanner; a scanner that never sees the wall fails the run unless --allow-partial.
//
// Tolerances: the mounts lie within 4.5 σ of the truth on every axis (a test that fails by
// chance once in ~10⁵ runs per axis), σ from the joint covariance. The three forms' agreement
// is explained where it is checked.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "calib/detection_pass.h"
#include "common/angles.h"
#include "io/config/session_reader.h"
#include "pipeline/multi_scanner.h"
#include "preflight/inspect.h"
#include "sim/simulated_session.h"
#include "test/support/json_value.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"
#include "test/programs/multi_scanner_session.h"

namespace wallcal {
namespace {

namespace fs = std::filesystem;

using namespace multi_scanner_testing;

TEST(MultiScannerTest, SessionListsEveryScannerWithItsOwnLog) {
  const io::SessionSpec session = io::ReadSession(TextSession().string());
  ASSERT_EQ(session.scanners.size(), 2u);
  EXPECT_EQ(session.scanners[0].id, "front_left");
  EXPECT_EQ(session.scanners[0].frame, "front_left");
  EXPECT_NE(session.scanners[0].log, session.scanners[1].log);
  const io::SessionSpec one = io::SessionForScanner(session, 1);
  EXPECT_EQ(one.scanner_log, session.scanners[1].log);
  EXPECT_TRUE(one.scanners.empty());
}

TEST(MultiScannerTest, RelativeTransformIsTheDifferenceOfTheMounts) {
  const pipeline::SeveralScannersResult result = Calibrate(TextSession());
  ASSERT_EQ(result.outcome, pipeline::SeveralOutcome::kAll) << result.message;
  ASSERT_TRUE(result.scanners[0].joint && result.scanners[1].joint);
  const solvers::Mount& a = result.scanners[0].joint->mount;
  const solvers::Mount& b = result.scanners[1].joint->mount;
  const solvers::Mount& rel = result.relative[0].mount.from_T_to;
  // Back to b: a ∘ rel.
  EXPECT_NEAR(a.x_m + std::cos(a.yaw_rad) * rel.x_m - std::sin(a.yaw_rad) * rel.y_m, b.x_m, 1e-9);
  EXPECT_NEAR(a.y_m + std::sin(a.yaw_rad) * rel.x_m + std::cos(a.yaw_rad) * rel.y_m, b.y_m, 1e-9);
  EXPECT_NEAR(a.yaw_rad + rel.yaw_rad, b.yaw_rad, 1e-9);
  // The joint covariance is a covariance: symmetric, positive definite.
  const Eigen::MatrixXd& c = result.joint.covariance;
  ASSERT_EQ(c.rows(), 6);
  EXPECT_LT((c - c.transpose()).norm(), 1e-12 * c.norm());
  EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(c).eigenvalues().minCoeff(), 0.0);
}

// The other scanner shares the vehicle's errors (the GNSS bias, the survey tie), which set each
// mount's x and y, and adds next to nothing to them. A joint problem that reads the RTK error's
// wander within a GNSS-error slice as white noise it can resolve claims more: σ 0.87–0.93 × the
// own run's with the joint on 0.25 s slices, where its error is not smaller. 0.97 leaves room
// for what the other scanner does add, whether each unit's range model is taken as exact or
// estimated.
TEST(MultiScannerTest, JointMountIsNoSurerThanEachScannersOwnRun) {
  const fs::path exact = SessionAs("text", "units_exact");
  OwnUnitPresets(exact, 0.0, 0.0);
  for (const fs::path& dir : {exact, TextSession()}) {
    const pipeline::SeveralScannersResult result = Calibrate(dir);
    ASSERT_EQ(result.outcome, pipeline::SeveralOutcome::kAll) << result.message;
    for (const auto& run : result.scanners) {
      for (int axis = 0; axis < 2; ++axis) {
        ASSERT_TRUE(run.joint) << run.spec.id;
        // The data's σ (its own run takes its unit's range model as exact too).
        const double joint = std::sqrt(run.joint->covariance(axis, axis) -
                                       run.joint->range_model_covariance(axis, axis));
        const double own = std::sqrt(run.own.solve.estimate.covariance(axis, axis));
        EXPECT_GT(joint, 0.97 * own) << dir << " " << run.spec.id << (axis == 0 ? " x" : " y");
      }
    }
  }
}

TEST(MultiScannerTest, EachScannersPageIsDrawnWithItsJointMount) {
  const pipeline::SeveralScannersResult result =
      Calibrate(TextSession(), /*allow_partial=*/false, /*collect_report_data=*/true);
  ASSERT_EQ(result.outcome, pipeline::SeveralOutcome::kAll) << result.message;
  for (const pipeline::ScannerRun& run : result.scanners) {
    ASSERT_TRUE(run.joint) << run.spec.id;
    const solvers::Mount& joint = run.joint->mount;
    const pipeline::ReportData& report = run.joint->report;
    ASSERT_TRUE(report.collected && report.have_mount) << run.spec.id;
    // The joint adjustment moved the mount (else this test could not tell the two apart).
    ASSERT_NE(joint.x_m, run.own.solve.estimate.mount.x_m) << run.spec.id;
    // Its own run's drawings stay around its own mount.
    EXPECT_EQ(run.own.report.mount.x_m, run.own.solve.estimate.mount.x_m) << run.spec.id;
    EXPECT_EQ(report.mount.x_m, joint.x_m) << run.spec.id;
    EXPECT_EQ(report.mount.y_m, joint.y_m) << run.spec.id;
    EXPECT_EQ(report.mount.yaw_rad, joint.yaw_rad) << run.spec.id;
    EXPECT_NE(report.mount_source.find("joint"), std::string::npos) << report.mount_source;
    // The scanner at each station and each panel's gate follow that mount.
    ASSERT_FALSE(report.stations.empty()) << run.spec.id;
    for (const pipeline::Station& station : report.stations) {
      const Eigen::Vector2d expected =
          station.antenna_local_m +
          Eigen::Rotation2Dd(station.yaw_rad) * Eigen::Vector2d(joint.x_m, joint.y_m);
      EXPECT_LT((station.scanner_local_m - expected).norm(), 1e-9) << run.spec.id;
    }
    int drawn = 0;
    for (const pipeline::ScanPanel& panel : report.panels) {
      if (!panel.have_scan) continue;
      ++drawn;
      const calib::WallObservation& o = run.own.solve.observations[panel.observation];
      const calib::LineGate gate =
          calib::GateFor(o, run.own.survey.walls[o.wall_index], joint, report.tight_gates);
      EXPECT_EQ(panel.gate.rho_m, gate.rho_m) << run.spec.id;
      EXPECT_EQ(panel.gate.theta_rad, gate.theta_rad) << run.spec.id;
      EXPECT_TRUE(panel.detection.found) << run.spec.id << ": " << panel.detection.reason;
    }
    EXPECT_GT(drawn, 0) << run.spec.id;
    ASSERT_TRUE(report.hough.have) << run.spec.id;
    const pipeline::ScanPanel& middle = report.panels[report.hough.panel];
    const calib::WallObservation& o = run.own.solve.observations[middle.observation];
    const calib::LineGate centre =
        calib::GateFor(o, run.own.survey.walls[o.wall_index], joint, report.tight_gates);
    EXPECT_EQ(report.hough.window.rho_m, centre.rho_m) << run.spec.id;
    EXPECT_EQ(report.hough.window.theta_rad, centre.theta_rad) << run.spec.id;
  }
}

TEST(MultiScannerTest, InspectChecksEachScannerAndSuggestsEveryScanTopic) {
  const preflight::SessionInspection inspection =
      preflight::InspectSession(TextSession().string());
  EXPECT_NE(inspection.report.find("=== scanner 'front_left' (1 of 2)"), std::string::npos);
  EXPECT_NE(inspection.report.find("=== scanner 'front_right' (2 of 2)"), std::string::npos);
  EXPECT_TRUE(inspection.enough) << inspection.report;
  const fs::path mcap = SessionAs("mcap", "mcap_suggest");
  const std::string suggested = preflight::SuggestSession((mcap / "session.mcap").string());
  EXPECT_NE(suggested.find("scanners:"), std::string::npos) << suggested;
  EXPECT_NE(suggested.find("  - id: front_left\n"), std::string::npos) << suggested;
  EXPECT_NE(suggested.find("    topic: /front_right/scan"), std::string::npos) << suggested;
  // Each scanner's mount_guess, which the recording does not hold, as a line to fill in.
  size_t guesses = 0;
  for (size_t at = suggested.find("    # mount_guess: {"); at != std::string::npos;
       at = suggested.find("    # mount_guess: {", at + 1)) {
    ++guesses;
  }
  EXPECT_EQ(guesses, 2u) << suggested;
}

// ---- The program ----------------------------------------------------------------------------


// The text session with antenna_in_base, so that --emit gives base_link too.
fs::path SessionWithBase() {
  const fs::path dir = FreshDir("with_base");
  fs::copy(TextSession(), dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  std::ofstream(dir / "session.yaml", std::ios::app) << "antenna_in_base: {x: -0.4, y: 0, z: 2.1}\n";
  return dir;
}

// parent -> child pairs form one tree: every child one parent, one root, every frame reached.
void ExpectOneTree(const std::multimap<std::string, std::string>& child_to_parent,
                   const std::set<std::string>& expected_children) {
  std::set<std::string> frames, children;
  for (const auto& [child, parent] : child_to_parent) {
    EXPECT_EQ(child_to_parent.count(child), 1u) << child << " has two parents";
    children.insert(child);
    frames.insert(child);
    frames.insert(parent);
  }
  int roots = 0;
  for (const std::string& frame : frames) roots += children.count(frame) == 0 ? 1 : 0;
  EXPECT_EQ(roots, 1);
  for (const std::string& child : expected_children) EXPECT_EQ(children.count(child), 1u) << child;
}

// The first column of a CSV dump, after its header.
std::vector<std::string> FirstColumn(const std::string& csv) {
  std::vector<std::string> column;
  std::istringstream lines(csv);
  std::string line;
  std::getline(lines, line);
  while (std::getline(lines, line)) column.push_back(line.substr(0, line.find(',')));
  return column;
}

TEST(MultiScannerTest, InspectDumpsTheNamedScannersScansAndTheSessionsSurvey) {
  const std::string dir = TextSession().string();
  const auto run = [](std::vector<std::string> args) {
    args.insert(args.begin(), "inspect");
    return testing_support::RunWallcal(args);
  };
  // Which scanner's scans: the session does not say, so it is asked for by name.
  const testing_support::ProgramRun unnamed = run({dir, "--dump", "scans"});
  EXPECT_EQ(unnamed.exit_code, 2);
  EXPECT_NE(unnamed.err.find("expected --scanner ID with ID one of front_left, front_right"),
            std::string::npos)
      << unnamed.err;
  EXPECT_TRUE(unnamed.out.empty()) << unnamed.out;
  const testing_support::ProgramRun unknown = run({dir, "--dump", "scans", "--scanner", "rear"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("no scanner 'rear'"), std::string::npos) << unknown.err;
  // The named scanner's log, with the session's time offset (0 here) on its stamps.
  for (const std::string id : {"front_left", "front_right"}) {
    const testing_support::ProgramRun named = run({dir, "--dump", "scans", "--scanner", id});
    ASSERT_EQ(named.exit_code, 0) << named.err;
    const testing_support::ProgramRun log =
        run({dir + "/scans_" + id + ".clf", "--dump", "scans"});
    ASSERT_EQ(log.exit_code, 0) << log.err;
    EXPECT_FALSE(FirstColumn(named.out).empty());
    EXPECT_EQ(FirstColumn(named.out), FirstColumn(log.out)) << id;
  }
  // --scanner names a scanner of the session's own scans only.
  EXPECT_EQ(run({dir, "--dump", "gnss", "--scanner", "front_left"}).exit_code, 2);
  // The session's survey file, as the survey file's own dump.
  const testing_support::ProgramRun survey = run({dir, "--dump", "survey"});
  ASSERT_EQ(survey.exit_code, 0) << survey.err;
  EXPECT_EQ(survey.out, run({dir + "/survey.csv", "--dump", "survey"}).out);
  EXPECT_NE(survey.out.find("C1,"), std::string::npos) << survey.out;
}

// guide and characterise take one scanner: a session with scanners: names it (--scanner ID).
// The guide's σ is calibrate's for that scanner alone (the one-scanner guide is held to 1 % of
// calibrate's σ under default options, GuidePredictionTest), and the joint mount's σ is within
// 3 % of the scanner's own (JointMountIsNoSurerThanEachScannersOwnRun; the --help says "a few
// per cent").
TEST(MultiScannerTest, GuideAndCharacteriseTakeOneScannerOfTheSessionByName) {
  const std::string dir = TextSession().string();
  const testing_support::ProgramRun unnamed = testing_support::RunWallcal({"guide", dir});
  EXPECT_EQ(unnamed.exit_code, 2);
  EXPECT_NE(unnamed.err.find("expected --scanner ID for this command (ID one of front_left, "
                             "front_right)"),
            std::string::npos)
      << unnamed.err;
  const testing_support::ProgramRun unknown =
      testing_support::RunWallcal({"guide", dir, "--scanner", "rear"});
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("no scanner 'rear'"), std::string::npos) << unknown.err;
  EXPECT_EQ(testing_support::RunWallcal({"characterise", dir, "--scanner", "rear"}).exit_code, 2);

  const pipeline::SeveralScannersResult calibrated = Calibrate(TextSession());
  ASSERT_EQ(calibrated.outcome, pipeline::SeveralOutcome::kAll) << calibrated.message;
  for (const pipeline::ScannerRun& run : calibrated.scanners) {
    const testing_support::ProgramRun guided =
        testing_support::RunWallcal({"guide", dir, "--scanner", run.spec.id, "--json"});
    ASSERT_EQ(guided.exit_code, 0) << guided.err;
    testing_support::Json j;
    ASSERT_TRUE(testing_support::JsonParser(guided.out).Parse(&j)) << guided.out;
    ASSERT_TRUE(run.joint) << run.spec.id;
    const double own_x_m = std::sqrt(run.own.solve.estimate.covariance(0, 0));
    // The guide speaks of the data: the units' range models are the joint adjustment's alone.
    const double joint_x_m =
        std::sqrt(run.joint->covariance(0, 0) - run.joint->range_model_covariance(0, 0));
    const double guided_x_m = j["predicted_sigma"]["x_m"].number;
    EXPECT_NEAR(guided_x_m / own_x_m, 1.0, 0.01) << run.spec.id;
    EXPECT_NEAR(guided_x_m / joint_x_m, 1.0, 0.03) << run.spec.id;
    const testing_support::ProgramRun text =
        testing_support::RunWallcal({"guide", dir, "--scanner", run.spec.id});
    EXPECT_NE(text.out.find(", scanner '" + run.spec.id + "'"), std::string::npos) << text.out;
  }
}

// One pose of offsets.yaml (a scanner_mounts or relative_mounts entry): x, y (m), yaw (rad)
// and their σ from stddev.
struct Pose {
  double value[3] = {0, 0, 0};
  double sigma[3] = {0, 0, 0};
};

Pose PoseOf(const YAML::Node& entry) {
  Pose pose;
  pose.value[0] = entry["x"].as<double>();
  pose.value[1] = entry["y"].as<double>();
  pose.value[2] = entry["yaw"].as<double>();
  pose.sigma[0] = entry["stddev"]["x"].as<double>();
  pose.sigma[1] = entry["stddev"]["y"].as<double>();
  pose.sigma[2] = entry["stddev"]["yaw_deg"].as<double>() / kRadToDeg;
  return pose;
}

// The scanners' mounts by id and the relative transforms by "from>to" of an offsets.yaml.
std::map<std::string, Pose> PosesOf(const fs::path& offsets) {
  const YAML::Node root = YAML::LoadFile(offsets.string());
  std::map<std::string, Pose> poses;
  for (const YAML::Node& mount : root["scanner_mounts"]) {
    poses[mount["id"].as<std::string>()] = PoseOf(mount);
  }
  for (const YAML::Node& relative : root["relative_mounts"]) {
    poses[relative["from"].as<std::string>() + ">" + relative["to"].as<std::string>()] =
        PoseOf(relative);
  }
  return poses;
}

// The parent of each child frame of `ros2 run tf2_ros static_transform_publisher` lines.
std::multimap<std::string, std::string> StaticTfEdges(const std::string& text) {
  std::multimap<std::string, std::string> edges;
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    const size_t f = line.find("--frame-id "), c = line.find("--child-frame-id ");
    if (f == std::string::npos || c == std::string::npos) continue;
    const std::string parent = line.substr(f + 11, line.find(' ', f + 11) - f - 11);
    edges.emplace(line.substr(c + 17), parent);
  }
  return edges;
}

TEST(MultiScannerTest, ProgramCalibratesTextRos1AndMcapToTheSameMountsNearTheTruth) {
  const sim::SimulationConfig truth = TwoScanners();
  std::map<std::string, std::map<std::string, Pose>> forms;
  for (const std::string format : {"text", "ros1", "mcap"}) {
    const fs::path dir = format == "text" ? TextSession() : SessionAs(format);
    const testing_support::ProgramRun run =
        RunCalibrate(dir, {"--quiet", "--emit", "ros2-static-tf"});
    ASSERT_EQ(run.exit_code, 0) << format << ": " << run.err;
    const std::multimap<std::string, std::string> edges = StaticTfEdges(run.out);
    EXPECT_EQ(edges.size(), 2u) << format << ":\n" << run.out;
    ExpectOneTree(edges, {"front_left", "front_right"});
    forms[format] = PosesOf(dir / "offsets.yaml");
    ASSERT_EQ(forms[format].size(), 3u) << format;  // two mounts, one relative transform
  }
  const std::map<std::string, Pose>& text = forms["text"];
  for (size_t k = 0; k < 2; ++k) {
    const sim::SimScanner& scanner = truth.scanners[k];
    ASSERT_EQ(text.count(scanner.id), 1u) << scanner.id;
    const Pose& pose = text.at(scanner.id);
    const double true_mount[3] = {scanner.mount_x_m, scanner.mount_y_m, scanner.mount_yaw_rad};
    for (int axis = 0; axis < 3; ++axis) {
      EXPECT_LT(std::abs(pose.value[axis] - true_mount[axis]), 4.5 * pose.sigma[axis])
          << scanner.id << " axis " << axis;
    }
  }
  // The recordings hold the text logs' numbers (ranges as float32, stamps in ns: a relative
  // rounding below 1e-7, under 1 µm at the wall's 10-15 m) and offsets.yaml prints 1 µm and
  // 1e-8 rad: together they move a mount by ~1e-4 of its σ and the relative transform (σ 0.4 mm,
  // 1 mdeg) by ~1e-2 of its own. 0.05 σ holds that; a wrong topic, frame or clock in one form
  // moves the estimate by whole σ.
  for (const std::string format : {"ros1", "mcap"}) {
    for (const auto& [key, pose] : text) {
      ASSERT_EQ(forms[format].count(key), 1u) << format << " " << key;
      const Pose& other = forms[format].at(key);
      for (int axis = 0; axis < 3; ++axis) {
        EXPECT_NEAR(other.value[axis], pose.value[axis], 0.05 * pose.sigma[axis])
            << format << " " << key << " axis " << axis;
      }
    }
  }
}

TEST(MultiScannerTest, EmittedStaticTfAndUrdfFormOneTree) {
  const fs::path dir = SessionWithBase();
  const fs::path out = dir / "offsets.yaml";
  const std::set<std::string> expected = {"gnss_antenna", "front_left", "front_right"};
  {
    const testing_support::ProgramRun run =
        RunCalibrate(dir, {"--quiet", "--emit", "ros2-static-tf"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    const std::multimap<std::string, std::string> edges = StaticTfEdges(run.out);
    EXPECT_EQ(edges.size(), 3u);
    ExpectOneTree(edges, expected);
  }
  {
    const testing_support::ProgramRun run = RunCalibrate(dir, {"--quiet", "--emit", "urdf"});
    ASSERT_EQ(run.exit_code, 0) << run.err;
    std::multimap<std::string, std::string> edges;
    size_t at = 0;
    while ((at = run.out.find("<parent link=\"", at)) != std::string::npos) {
      const size_t p = at + 14;
      const std::string parent = run.out.substr(p, run.out.find('"', p) - p);
      const size_t c = run.out.find("<child link=\"", p) + 13;
      edges.emplace(run.out.substr(c, run.out.find('"', c) - c), parent);
      at = c;
    }
    EXPECT_EQ(edges.size(), 3u);
    ExpectOneTree(edges, expected);
    // No scanner has z_m: the z = 0 note names each one, inside the XML document.
    for (const char* id : {"front_left", "front_right"}) {
      const size_t note = run.out.find(std::string("<!-- gnss_antenna -> ") + id + ": z = 0");
      EXPECT_NE(note, std::string::npos) << run.out;
      EXPECT_LT(note, run.out.find("<robot ")) << run.out;
    }
    EXPECT_EQ(run.out.find("scanner.z_m"), std::string::npos) << run.out;
  }
  const std::string offsets = ReadText(out);
  EXPECT_NE(offsets.find("scanner_mounts:\n  - id: front_left\n"), std::string::npos) << offsets;
  EXPECT_NE(offsets.find("  - id: front_right\n"), std::string::npos);
  EXPECT_NE(offsets.find("relative_mounts:\n  - from: front_left\n    to: front_right\n"),
            std::string::npos);
  EXPECT_NE(offsets.find("joint_covariance:\n"), std::string::npos);
  EXPECT_EQ(offsets.find("\nscanner_mount:"), std::string::npos);
}

TEST(MultiScannerTest, EmittedJsonCarriesTheVerdictsOfOffsetsYaml) {
  const fs::path dir = SessionAs("text", "emit_json");
  // A relative σ tolerance of 0.1 mm rejects the relative transform (σ 0.1-0.2 mm in x, y)
  // while the mounts are accepted: each verdict has to come from its own entry.
  const fs::path config = dir / "tight.yaml";
  std::ofstream(config) << "acceptance:\n  relative_max_sigma_xy_m: 0.0001\n";
  const testing_support::ProgramRun run =
      RunCalibrate(dir, {"--quiet", "--config", config.string(), "--emit", "json"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  testing_support::Json j;
  ASSERT_TRUE(testing_support::JsonParser(run.out).Parse(&j)) << run.out;
  const YAML::Node offsets = YAML::LoadFile((dir / "offsets.yaml").string());
  const auto expect_same = [](const testing_support::Json& json, const YAML::Node& yaml,
                              const std::string& what) {
    EXPECT_EQ(json["verdict"].text, yaml["verdict"].as<std::string>()) << what;
    ASSERT_EQ(json["reasons"].items.size(), yaml["reasons"].size()) << what;
    for (size_t i = 0; i < yaml["reasons"].size(); ++i) {
      EXPECT_EQ(json["reasons"].items[i].text, yaml["reasons"][i].as<std::string>()) << what;
    }
  };
  expect_same(j["verdict"], offsets["verdict"], "run");
  EXPECT_EQ(j["verdict"]["verdict"].text, "REJECT");
  const testing_support::Json& scanners = j["scanners"];
  ASSERT_EQ(scanners.items.size(), 2u);
  for (size_t s = 0; s < 2; ++s) {
    EXPECT_EQ(scanners.items[s]["id"].text, offsets["scanner_mounts"][s]["id"].as<std::string>());
    expect_same(scanners.items[s]["verdict"], offsets["scanner_mounts"][s]["verdict"],
                scanners.items[s]["id"].text);
  }
  const testing_support::Json& relative = j["relative"];
  ASSERT_EQ(relative.items.size(), 1u);
  expect_same(relative.items[0]["verdict"], offsets["relative_mounts"][0]["verdict"], "relative");
  EXPECT_EQ(relative.items[0]["verdict"]["verdict"].text, "REJECT");
  // Each scanner's clock offset carries its σ and status, in offsets.yaml and the summary (on
  // stderr beside --emit), as a one-scanner run's do; the mounts' comment heads their list.
  const std::string text = ReadText(dir / "offsets.yaml");
  EXPECT_NE(text.find("yaw ccw.\nscanner_mounts:\n"), std::string::npos) << text;
  for (size_t s = 0; s < 2; ++s) {
    const YAML::Node mount = offsets["scanner_mounts"][s];
    ASSERT_TRUE(mount["time_offset_sigma_s"].IsDefined()) << text;
    EXPECT_GT(mount["time_offset_sigma_s"].as<double>(), 0.0) << text;
    const std::string status = mount["time_offset_status"].as<std::string>();
    EXPECT_TRUE(status.rfind("determined", 0) == 0 || status.rfind("not determined", 0) == 0)
        << status;
    const std::string id = mount["id"].as<std::string>();
    const size_t line = run.err.find("  " + id + " (");
    ASSERT_NE(line, std::string::npos) << run.err;
    const std::string summary_line = run.err.substr(line, run.err.find('\n', line) - line);
    EXPECT_NE(summary_line.find(" s, " + status), std::string::npos) << summary_line;
  }
}

TEST(MultiScannerTest, RelativeTransformBeyondItsToleranceRejectsTheRun) {
  const fs::path dir = SessionAs("text", "relative_tolerance");
  // σ of the relative x, y here is 0.4-0.6 mm: a tolerance of 0.1 mm rejects it, while the
  // mounts (σ 7-13 mm against 20 mm) are still accepted.
  const fs::path config = dir / "tight.yaml";
  std::ofstream(config) << "acceptance:\n  relative_max_sigma_xy_m: 0.0001\n";
  const testing_support::ProgramRun run =
      RunCalibrate(dir, {"--quiet", "--config", config.string()});
  ASSERT_EQ(run.exit_code, 0) << run.err;  // written, as any determined mount: the verdict says
  EXPECT_NE(run.out.find("  verdict    REJECT"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("front_left (ACCEPT)"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("front_right in front_left (REJECT)"), std::string::npos) << run.out;
  const YAML::Node offsets = YAML::LoadFile((dir / "offsets.yaml").string());
  EXPECT_EQ(offsets["verdict"]["verdict"].as<std::string>(), "REJECT");
  EXPECT_EQ(offsets["verdict"]["reasons"][0].as<std::string>(), "front_right in front_left: REJECT");
  EXPECT_EQ(offsets["relative_mounts"][0]["verdict"]["verdict"].as<std::string>(), "REJECT");
  EXPECT_EQ(offsets["scanner_mounts"][1]["verdict"]["verdict"].as<std::string>(), "ACCEPT");
}

}  // namespace
}  // namespace wallcal
