// SPDX-License-Identifier: Apache-2.0
// The emitters of calibrate --emit: each form is parsed back and compared with the estimate.

#include "outputs/emit.h"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <memory>
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
#include "io/config/session_reader.h"
#include "common/angles.h"
#include "test/support/flow_names.h"
#include "test/support/json_value.h"
#include "test/support/program_runner.h"
#include "test/support/scratch_dir.h"

namespace wallcal {


namespace {

namespace fs = std::filesystem;
solvers::MountEstimate Estimate() {
  solvers::MountEstimate e;
  e.mount.x_m = 2.5398529;
  e.mount.y_m = -0.0575351632;
  e.mount.yaw_rad = -0.0486562944;
  e.covariance << 1.6e-4, 7.5e-8, -3.4e-8,  //
      7.5e-8, 1.7e-4, -1.6e-6,              //
      -3.4e-8, -1.6e-6, 6.5e-7;
  e.usable = true;
  e.method = solvers::Method::kCeres;
  return e;
}

// 9 significant digits are printed.
constexpr double kTol = 1e-7;

std::vector<std::string> Lines(const std::string& text) {
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

// ---- ros2 command line ----

struct Ros2Command {
  std::string program;                      // "ros2 run tf2_ros static_transform_publisher"
  std::map<std::string, std::string> flags;  // "--x" -> "2.5"
  bool ok = false;
};

Ros2Command ParseRos2(const std::string& line) {
  Ros2Command c;
  std::istringstream in(line);
  std::vector<std::string> words;
  for (std::string w; in >> w;) words.push_back(w);
  if (words.size() < 4) return c;
  c.program = words[0] + " " + words[1] + " " + words[2] + " " + words[3];
  for (size_t i = 4; i < words.size(); i += 2) {
    if (words[i].rfind("--", 0) != 0 || i + 1 >= words.size()) return c;  // flag without value
    if (c.flags.count(words[i])) return c;                                 // repeated flag
    c.flags[words[i]] = words[i + 1];
  }
  c.ok = true;
  return c;
}

double Number(const std::string& text) {
  size_t used = 0;
  const double v = std::stod(text, &used);
  EXPECT_EQ(used, text.size()) << "not a plain number: " << text;
  return v;
}

TEST(EmitTest, ParsesTheThreeFormatNames) {
  EmitFormat f = EmitFormat::kJson;
  EXPECT_TRUE(ParseEmitFormat("ros2-static-tf", &f));
  EXPECT_EQ(f, EmitFormat::kRos2StaticTf);
  EXPECT_TRUE(ParseEmitFormat("urdf", &f));
  EXPECT_EQ(f, EmitFormat::kUrdf);
  EXPECT_TRUE(ParseEmitFormat("json", &f));
  EXPECT_EQ(f, EmitFormat::kJson);
  EXPECT_FALSE(ParseEmitFormat("yaml", &f));
  EXPECT_FALSE(ParseEmitFormat("", &f));
  EXPECT_FALSE(ParseEmitFormat("JSON", &f));
}

TEST(EmitTest, FrameNamesMustBeSafeToPrint) {
  EXPECT_TRUE(IsValidFrameName("laser"));
  EXPECT_TRUE(IsValidFrameName("robot1/base_link"));
  EXPECT_TRUE(IsValidFrameName("gnss.antenna-2"));
  EXPECT_FALSE(IsValidFrameName("/laser"));  // tf2 rejects a leading slash
  EXPECT_FALSE(IsValidFrameName("laser/"));
  EXPECT_FALSE(IsValidFrameName("a//b"));
  EXPECT_NE(FrameNameProblem("/laser").find("leading slash"), std::string::npos);
  EXPECT_FALSE(IsValidFrameName(""));
  EXPECT_FALSE(IsValidFrameName("-x"));
  EXPECT_FALSE(IsValidFrameName("a b"));
  EXPECT_FALSE(IsValidFrameName("a\"b"));
  EXPECT_FALSE(IsValidFrameName("a<b"));
  EXPECT_FALSE(IsValidFrameName("a;rm"));
  EXPECT_FALSE(IsValidFrameName(std::string(129, 'a')));
  EmitFrames frames;
  frames.child = "bad name";
  EXPECT_THROW(FormatEmit(EmitFormat::kJson, Estimate(), std::nullopt, frames), std::invalid_argument);
}

TEST(EmitTest, Ros2StaticTfLineParsesBackToTheEstimate) {
  const solvers::MountEstimate e = Estimate();
  EmitFrames frames;
  frames.parent = "antenna";
  frames.child = "front_laser";
  const std::vector<std::string> lines =
      Lines(FormatEmit(EmitFormat::kRos2StaticTf, e, std::nullopt, frames));
  // A shell comment says z = 0 is not measured, then the command.
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("# antenna -> front_laser: z = 0", 0), 0u) << lines[0];
  const Ros2Command c = ParseRos2(lines[1]);
  ASSERT_TRUE(c.ok) << lines[0];
  EXPECT_EQ(c.program, "ros2 run tf2_ros static_transform_publisher");
  EXPECT_EQ(c.flags.size(), 8u);
  EXPECT_NEAR(Number(c.flags.at("--x")), e.mount.x_m, kTol);
  EXPECT_NEAR(Number(c.flags.at("--y")), e.mount.y_m, kTol);
  EXPECT_EQ(Number(c.flags.at("--z")), 0.0);
  EXPECT_NEAR(Number(c.flags.at("--yaw")), e.mount.yaw_rad, kTol);
  EXPECT_EQ(Number(c.flags.at("--pitch")), 0.0);
  EXPECT_EQ(Number(c.flags.at("--roll")), 0.0);
  EXPECT_EQ(c.flags.at("--frame-id"), "antenna");
  EXPECT_EQ(c.flags.at("--child-frame-id"), "front_laser");
}

TEST(EmitTest, Ros2WithAntennaInBaseEmitsOneTree) {
  const solvers::MountEstimate e = Estimate();
  const io::AntennaInBase antenna{-0.4, 0.1, 2.1};
  const std::vector<std::string> lines =
      Lines(FormatEmit(EmitFormat::kRos2StaticTf, e, antenna, EmitFrames(), -0.85));
  std::vector<Ros2Command> commands;
  for (const std::string& line : lines) {
    EXPECT_NE(line.rfind("#", 0), 0u) << "no note when the height is known: " << line;
    commands.push_back(ParseRos2(line));
  }
  ASSERT_EQ(commands.size(), 2u);
  ASSERT_TRUE(commands[0].ok && commands[1].ok);
  // base_link -> gnss_antenna -> laser: every frame has one parent.
  EXPECT_EQ(commands[0].flags.at("--frame-id"), "base_link");
  EXPECT_EQ(commands[0].flags.at("--child-frame-id"), "gnss_antenna");
  EXPECT_NEAR(Number(commands[0].flags.at("--x")), -0.4, kTol);
  EXPECT_NEAR(Number(commands[0].flags.at("--y")), 0.1, kTol);
  EXPECT_NEAR(Number(commands[0].flags.at("--z")), 2.1, kTol);
  EXPECT_EQ(Number(commands[0].flags.at("--yaw")), 0.0);
  EXPECT_EQ(commands[1].flags.at("--frame-id"), "gnss_antenna");
  EXPECT_EQ(commands[1].flags.at("--child-frame-id"), "laser");
  EXPECT_NEAR(Number(commands[1].flags.at("--x")), e.mount.x_m, kTol);
  EXPECT_NEAR(Number(commands[1].flags.at("--z")), -0.85, kTol);
  EXPECT_NEAR(Number(commands[1].flags.at("--yaw")), e.mount.yaw_rad, kTol);
}

TEST(EmitTest, BaseToLaserComposesWithTheTransformFormula) {
  // A point fixed in the laser frame must land at the same base_link position whether it goes
  // through the antenna frame or through the composed transform.
  solvers::Mount m;
  m.x_m = 1.2;
  m.y_m = -0.3;
  m.yaw_rad = 0.7;
  const io::AntennaInBase a{0.5, -0.25, 1.8};
  const PlanarTransform t = BaseToLaser(m, a, EmitFrames());
  const double px = 3.0, py = -1.0;
  const double ax = m.x_m + std::cos(m.yaw_rad) * px - std::sin(m.yaw_rad) * py;
  const double ay = m.y_m + std::sin(m.yaw_rad) * px + std::cos(m.yaw_rad) * py;
  const double bx = t.x_m + std::cos(t.yaw_rad) * px - std::sin(t.yaw_rad) * py;
  const double by = t.y_m + std::sin(t.yaw_rad) * px + std::cos(t.yaw_rad) * py;
  EXPECT_NEAR(bx, a.x_m + ax, 1e-12);
  EXPECT_NEAR(by, a.y_m + ay, 1e-12);
  EXPECT_EQ(t.z_m, a.z_m);
  EXPECT_EQ(t.parent, "base_link");
  EXPECT_EQ(t.child, "laser");
}

// ---- URDF ----

struct XmlElement {
  std::string name;
  std::map<std::string, std::string> attributes;
};

// A tiny tokenizer for the emitted URDF: start/empty tags with double-quoted attributes; end
// tags and comments are recorded by name ("/joint", "!--").
std::vector<XmlElement> Tags(const std::string& text) {
  std::vector<XmlElement> tags;
  size_t i = 0;
  while ((i = text.find('<', i)) != std::string::npos) {
    if (text.compare(i, 2, "<?") == 0) {  // the XML declaration
      const size_t end = text.find("?>", i);
      EXPECT_NE(end, std::string::npos);
      if (end == std::string::npos) break;
      i = end + 2;
      continue;
    }
    if (text.compare(i, 4, "<!--") == 0) {
      const size_t end = text.find("-->", i);
      EXPECT_NE(end, std::string::npos);
      tags.push_back({"!--", {}});
      if (end == std::string::npos) break;
      i = end + 3;
      continue;
    }
    const size_t end = text.find('>', i);
    EXPECT_NE(end, std::string::npos);
    if (end == std::string::npos) break;
    std::string body = text.substr(i + 1, end - i - 1);
    if (!body.empty() && body.back() == '/') body.pop_back();
    XmlElement e;
    size_t p = 0;
    while (p < body.size() && !std::isspace(static_cast<unsigned char>(body[p]))) e.name += body[p++];
    while (p < body.size()) {
      while (p < body.size() && std::isspace(static_cast<unsigned char>(body[p]))) ++p;
      if (p >= body.size()) break;
      const size_t eq = body.find('=', p);
      EXPECT_NE(eq, std::string::npos) << body;
      if (eq == std::string::npos || eq + 1 >= body.size() || body[eq + 1] != '"') {
        ADD_FAILURE() << "unquoted attribute in " << body;
        break;
      }
      const size_t close = body.find('"', eq + 2);
      EXPECT_NE(close, std::string::npos) << body;
      if (close == std::string::npos) break;
      e.attributes[body.substr(p, eq - p)] = body.substr(eq + 2, close - eq - 2);
      p = close + 1;
    }
    tags.push_back(e);
    i = end + 1;
  }
  return tags;
}

std::vector<double> Numbers(const std::string& text) {
  std::istringstream in(text);
  std::vector<double> v;
  for (std::string w; in >> w;) v.push_back(Number(w));
  return v;
}

// The tags of the first <joint> ... </joint> in the document.
std::vector<XmlElement> FirstJoint(const std::vector<XmlElement>& tags, size_t nth = 0) {
  std::vector<XmlElement> out;
  size_t seen = 0;
  bool in = false;
  for (const XmlElement& t : tags) {
    if (t.name == "joint" && seen++ == nth) in = true;
    if (in) out.push_back(t);
    if (in && t.name == "/joint") break;
  }
  return out;
}

TEST(EmitTest, UrdfIsAWholeDocumentWhoseJointParsesBack) {
  const solvers::MountEstimate e = Estimate();
  const std::string urdf = FormatEmit(EmitFormat::kUrdf, e, std::nullopt, EmitFrames());
  EXPECT_EQ(urdf.rfind("<?xml version=\"1.0\"?>\n", 0), 0u) << urdf;
  const std::vector<XmlElement> all = Tags(urdf);
  int robots = 0, links = 0;
  for (const XmlElement& t : all) {
    robots += t.name == "robot";
    links += t.name == "link";
  }
  EXPECT_EQ(robots, 1);
  EXPECT_EQ(links, 2);
  EXPECT_EQ(all.back().name, "/robot");
  const std::vector<XmlElement> tags = FirstJoint(all);
  ASSERT_EQ(tags.size(), 5u) << urdf;
  EXPECT_EQ(tags[0].attributes.at("type"), "fixed");
  EXPECT_FALSE(tags[0].attributes.at("name").empty());
  EXPECT_EQ(tags[1].name, "parent");
  EXPECT_EQ(tags[1].attributes.at("link"), "gnss_antenna");
  EXPECT_EQ(tags[2].name, "child");
  EXPECT_EQ(tags[2].attributes.at("link"), "laser");
  EXPECT_EQ(tags[3].name, "origin");
  const std::vector<double> xyz = Numbers(tags[3].attributes.at("xyz"));
  const std::vector<double> rpy = Numbers(tags[3].attributes.at("rpy"));
  ASSERT_EQ(xyz.size(), 3u);
  ASSERT_EQ(rpy.size(), 3u);
  EXPECT_NEAR(xyz[0], e.mount.x_m, kTol);
  EXPECT_NEAR(xyz[1], e.mount.y_m, kTol);
  EXPECT_EQ(xyz[2], 0.0);
  EXPECT_EQ(rpy[0], 0.0);
  EXPECT_EQ(rpy[1], 0.0);
  EXPECT_NEAR(rpy[2], e.mount.yaw_rad, kTol);
}

TEST(EmitTest, UrdfWithAntennaInBaseChainsBaseAntennaLaser) {
  const solvers::MountEstimate e = Estimate();
  EmitFrames frames;
  frames.base = "chassis";
  const std::string urdf = FormatEmit(EmitFormat::kUrdf, e, io::AntennaInBase{1.0, 0.0, 1.5}, frames);
  const std::vector<XmlElement> all = Tags(urdf);
  bool comment = false;
  for (const XmlElement& t : all) comment = comment || t.name == "!--";
  EXPECT_TRUE(comment);
  const std::vector<XmlElement> base = FirstJoint(all, 0);
  const std::vector<XmlElement> mount = FirstJoint(all, 1);
  ASSERT_EQ(base.size(), 5u) << urdf;
  ASSERT_EQ(mount.size(), 5u) << urdf;
  EXPECT_EQ(base[1].attributes.at("link"), "chassis");
  EXPECT_EQ(base[2].attributes.at("link"), "gnss_antenna");
  const std::vector<double> xyz = Numbers(base[3].attributes.at("xyz"));
  ASSERT_EQ(xyz.size(), 3u);
  EXPECT_NEAR(xyz[0], 1.0, kTol);
  EXPECT_NEAR(xyz[2], 1.5, kTol);
  EXPECT_EQ(mount[1].attributes.at("link"), "gnss_antenna");
  EXPECT_EQ(mount[2].attributes.at("link"), "laser");
  EXPECT_NEAR(Numbers(mount[3].attributes.at("rpy"))[2], e.mount.yaw_rad, kTol);
}

// ---- JSON ----

using testing_support::Json;
using testing_support::JsonParser;

TEST(EmitTest, JsonParserRejectsMalformedText) {
  // The parser the next tests rely on must be able to say no.
  for (const char* bad : {"{", "{\"a\": 1,}", "{\"a\" 1}", "{'a': 1}", "[1 2]", "{\"a\": 01}",
                          "{\"a\": .5}", "{\"a\": 1} x", "{\"a\": 1, \"a\": 2}", "{\"a\": nan}"}) {
    Json j;
    EXPECT_FALSE(JsonParser(bad).Parse(&j)) << bad;
  }
  Json j;
  EXPECT_TRUE(JsonParser("{\"a\": [1, -2.5e-3, true, null, \"x\"]}").Parse(&j));
}

TEST(EmitTest, JsonParsesBackToTheEstimate) {
  const solvers::MountEstimate e = Estimate();
  const std::string text = FormatEmit(EmitFormat::kJson, e, std::nullopt, EmitFrames());
  Json j;
  ASSERT_TRUE(JsonParser(text).Parse(&j)) << text;
  ASSERT_EQ(j.kind, Json::kObject);
  EXPECT_EQ(j["method"].text, "ceres");
  EXPECT_EQ(j["parent_frame"].text, "gnss_antenna");
  EXPECT_EQ(j["child_frame"].text, "laser");
  EXPECT_NEAR(j["mount"]["x_m"].number, e.mount.x_m, kTol);
  EXPECT_NEAR(j["mount"]["y_m"].number, e.mount.y_m, kTol);
  EXPECT_EQ(j["mount"]["z_m"].number, 0.0);
  EXPECT_NEAR(j["mount"]["yaw_rad"].number, e.mount.yaw_rad, kTol);
  EXPECT_NEAR(j["mount"]["yaw_deg"].number, e.mount.yaw_rad * 180.0 / kPi, 1e-6);
  EXPECT_NEAR(j["sigma"]["x_m"].number, std::sqrt(e.covariance(0, 0)), 1e-9);
  EXPECT_NEAR(j["sigma"]["y_m"].number, std::sqrt(e.covariance(1, 1)), 1e-9);
  EXPECT_NEAR(j["sigma"]["yaw_rad"].number, std::sqrt(e.covariance(2, 2)), 1e-11);
  const Json& order = j["covariance"]["order"];
  ASSERT_EQ(order.items.size(), 3u);
  EXPECT_EQ(order.items[0].text, "x_m");
  EXPECT_EQ(order.items[2].text, "yaw_rad");
  const Json& m = j["covariance"]["matrix"];
  ASSERT_EQ(m.items.size(), 3u);
  for (int r = 0; r < 3; ++r) {
    ASSERT_EQ(m.items[r].items.size(), 3u);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(m.items[r].items[c].number, e.covariance(r, c), 1e-8 * std::fabs(e.covariance(r, c)))
          << r << "," << c;
    }
  }
  EXPECT_EQ(j["base_link"].kind, Json::kNull);
}

TEST(EmitTest, JsonCarriesTheVerdictAsOffsetsYamlDoes) {
  pipeline::Decision decision;
  decision.verdict = pipeline::Verdict::kReview;
  decision.reasons = {"moved x +30.0 mm since \"old\".yaml", "second"};
  const std::string text =
      FormatEmit(EmitFormat::kJson, Estimate(), std::nullopt, EmitFrames(), std::nullopt, &decision);
  Json j;
  ASSERT_TRUE(JsonParser(text).Parse(&j)) << text;
  EXPECT_EQ(j["verdict"]["verdict"].text, "REVIEW");
  const Json& reasons = j["verdict"]["reasons"];
  ASSERT_EQ(reasons.items.size(), 2u);
  EXPECT_EQ(reasons.items[0].text, decision.reasons[0]);
  EXPECT_EQ(reasons.items[1].text, "second");
  // Without a decision (a library caller that has none) the member is null.
  Json without;
  ASSERT_TRUE(JsonParser(FormatEmit(EmitFormat::kJson, Estimate(), std::nullopt, EmitFrames()))
                  .Parse(&without));
  EXPECT_EQ(without["verdict"].kind, Json::kNull);
}

TEST(EmitTest, JsonWithAntennaInBaseCarriesTheBaseLinkTransform) {
  const solvers::MountEstimate e = Estimate();
  EmitFrames frames;
  frames.child = "lms";
  const std::string text = FormatEmit(EmitFormat::kJson, e, io::AntennaInBase{-0.4, 0.2, 2.1}, frames);
  Json j;
  ASSERT_TRUE(JsonParser(text).Parse(&j)) << text;
  const Json& b = j["base_link"];
  ASSERT_EQ(b.kind, Json::kObject);
  EXPECT_EQ(b["parent_frame"].text, "base_link");
  EXPECT_EQ(b["child_frame"].text, j["parent_frame"].text);  // base -> antenna: one tree
  EXPECT_NEAR(b["x_m"].number, -0.4, kTol);
  EXPECT_NEAR(b["y_m"].number, 0.2, kTol);
  EXPECT_NEAR(b["z_m"].number, 2.1, kTol);
  EXPECT_EQ(b["yaw_rad"].number, 0.0);
  EXPECT_FALSE(j["z_note"].text.empty());
}

// ---- The program: with --emit, stdout carries only the emitted text ----

struct CommandRun {
  int status = -1;
  std::string out;
};

// Runs a shell command line (test/support/program_runner.h); stdout only unless redirected.
CommandRun Capture(const std::string& command) {
  const testing_support::ProgramRun run = testing_support::RunShell(command);
  return {run.exit_code, run.out};
}

TEST(EmitProgramTest, EmitJsonPrintsOnlyJsonOnStdout) {
  const testing_support::ScratchDir scratch("wallcal_emit_program_");
  const fs::path dir = scratch.path() / "session";
  const sim::SimulationConfig config = sim::ReadSimulationConfig(
      std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml");
  WriteSimulatedSession(config, 3, dir.string());
  ASSERT_TRUE(fs::exists(testing_support::WallcalPath())) << "build the wallcal target first";
  const std::string calibrate = testing_support::ShellQuote(testing_support::WallcalPath()) + " calibrate";
  const CommandRun run = Capture(calibrate + " " + dir.string() + " --emit json --child-frame lms 2>/dev/null");
  ASSERT_EQ(run.status, 0) << run.out;
  Json j;
  ASSERT_TRUE(JsonParser(run.out).Parse(&j)) << run.out;
  EXPECT_EQ(j["child_frame"].text, "lms");
  // The verdict is offsets.yaml's.
  const YAML::Node offsets = YAML::LoadFile((dir / "offsets.yaml").string());
  EXPECT_EQ(j["verdict"]["verdict"].text, offsets["verdict"]["verdict"].as<std::string>());
  EXPECT_EQ(j["verdict"]["reasons"].items.size(), offsets["verdict"]["reasons"].size());
  EXPECT_NEAR(j["mount"]["x_m"].number, config.mount_x_m, 0.06);
  EXPECT_NEAR(j["mount"]["y_m"].number, config.mount_y_m, 0.06);
  EXPECT_NEAR(j["mount"]["yaw_rad"].number, config.mount_yaw_rad, 0.25 * kPi / 180.0);
  // The summary went to stderr.
  const CommandRun both = Capture(calibrate + " " + dir.string() + " --emit ros2-static-tf 2>&1 >/dev/null");
  EXPECT_NE(both.out.find("mount "), std::string::npos) << both.out;
  // A bad format or frame name is a usage error.
  EXPECT_EQ(Capture(calibrate + " " + dir.string() + " --emit yaml 2>/dev/null").status, 2);
  EXPECT_EQ(Capture(calibrate + " " + dir.string() + " --emit urdf --parent-frame 'a b' 2>/dev/null").status, 2);
}

}  // namespace
}  // namespace wallcal
