// SPDX-License-Identifier: Apache-2.0
// A simulated session's attitude stream written and read back, in every format `wallcal
// simulate --format` writes: $PASHR in the heading log, $PTNL,AVR in a log of its own, and
// sensor_msgs/Imu on /imu/data of a ROS 1 bag (plain, bz2, lz4), an MCAP file (zstd, lz4) and a
// .db3; each sample read back equal within what the format keeps (4 decimals of a degree in the
// sentences, which the recordings are converted from). The simulator does not make attitude
// samples itself yet: the test gives the simulated session its own.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "recording/attitude_stream.h"
#include "recording/recording_streams.h"
#include "sim/recording_session.h"
#include "sim/simulated_session.h"
#include "sim/simulation_config.h"
#include "sim/simulator.h"
#include "test/support/scratch_files.h"

namespace wallcal::sim {
namespace {

namespace fs = std::filesystem;
using testing_support::FreshScratchDir;
using testing_support::ReadFile;

// What the sentences keep of an angle (4 decimals of a degree) and of a stamp (the logger
// prefix's milliseconds; the samples are on whole milliseconds).
constexpr double kAngleStepRad = 0.5e-4 * kDegToRad + 1e-12;
constexpr double kStampStepS = 1e-6;

SimulationConfig ShortScenario() {
  SimulationConfig config = ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) +
                                                 "/configs/simulate/lms291_sapporo.yaml");
  config.num_stations = 4;
  config.dwell_s = 2.0;
  return config;
}

// Samples at 10 Hz over the headings' span, on whole milliseconds: a slow roll and pitch wave,
// every other one with σ of its own.
std::vector<io::AttitudeSample> Samples(const SimulatedSession& sim) {
  std::vector<io::AttitudeSample> samples;
  const double start_s = std::ceil(sim.headings.front().stamp_s * 1000.0) / 1000.0;
  for (int k = 0; start_s + 0.1 * k < sim.headings.back().stamp_s; ++k) {
    io::AttitudeSample a;
    a.stamp_s = std::round((start_s + 0.1 * k) * 1000.0) / 1000.0;
    a.roll_rad = (1.5 * std::sin(0.05 * k) - 0.25) * kDegToRad;
    a.pitch_rad = (2.0 * std::cos(0.03 * k) + 0.5) * kDegToRad;
    if (k % 2 == 0) {
      a.roll_sigma_rad = 0.05 * kDegToRad;
      a.pitch_sigma_rad = 0.0625 * kDegToRad;
    }
    samples.push_back(a);
  }
  return samples;
}

struct Written {
  fs::path dir;
  std::vector<io::AttitudeSample> samples;
  std::vector<io::HeadingSample> headings;
};

// The short scenario written as text into `name`, its simulated session given Samples().
Written TextSession(const std::string& name, const std::string& sentence, bool own_log) {
  Written w;
  w.dir = FreshScratchDir(name);
  SimulationConfig config = ShortScenario();
  config.attitude_sentence = sentence;
  config.attitude_own_log = own_log;
  const SimulateSummary summary =
      WriteSimulatedSession(config, 3, w.dir.string(), [&w](SimulatedSession& sim) {
        sim.attitudes = Samples(sim);
        w.samples = sim.attitudes;
        w.headings = sim.headings;
      });
  EXPECT_EQ(summary.attitudes, static_cast<int64_t>(w.samples.size()));
  return w;
}

// Each written sample read back within the format's steps; σ too when `sigma`, else NaN.
void ExpectReadBack(const std::vector<io::AttitudeSample>& written, const io::NmeaLog& read,
                    bool sigma) {
  ASSERT_EQ(read.attitudes.size(), written.size());
  for (size_t i = 0; i < written.size(); ++i) {
    const io::AttitudeSample& w = written[i];
    const io::AttitudeSample& r = read.attitudes[i];
    ASSERT_NEAR(r.stamp_s, w.stamp_s, kStampStepS) << i;
    ASSERT_NEAR(r.roll_rad, w.roll_rad, kAngleStepRad) << i;
    ASSERT_NEAR(r.pitch_rad, w.pitch_rad, kAngleStepRad) << i;
    if (sigma && std::isfinite(w.roll_sigma_rad)) {
      ASSERT_NEAR(r.roll_sigma_rad, w.roll_sigma_rad, kAngleStepRad) << i;
      ASSERT_NEAR(r.pitch_sigma_rad, w.pitch_sigma_rad, kAngleStepRad) << i;
    } else {
      ASSERT_TRUE(std::isnan(r.roll_sigma_rad) && std::isnan(r.pitch_sigma_rad)) << i;
    }
  }
}

TEST(AttitudeSessionTest, PashrLinesInTheHeadingLogReadBack) {
  const Written w = TextSession("pashr", "pashr", false);
  const io::SessionSpec spec = io::ReadSession(w.dir.string());
  EXPECT_EQ(spec.attitude_log, spec.heading_log);
  EXPECT_FALSE(fs::exists(w.dir / "attitude.nmea"));
  const recording::PoseLogs logs = recording::ReadPoseLogs(spec);
  ExpectReadBack(w.samples, logs.attitudes, true);
  EXPECT_EQ(logs.attitudes.attitudes_by_source.at("$PASHR"),
            static_cast<int64_t>(w.samples.size()));
  // The headings are the simulated ones still, the sentences in time order among them.
  EXPECT_EQ(logs.headings.headings.size(), w.headings.size());
  EXPECT_EQ(logs.headings.skipped.Problems(), 0);
}

TEST(AttitudeSessionTest, AvrLinesInALogOfTheirOwnReadBack) {
  const Written w = TextSession("avr", "avr", true);
  const io::SessionSpec spec = io::ReadSession(w.dir.string());
  EXPECT_EQ(spec.attitude_log, (w.dir / "attitude.nmea").string());
  EXPECT_EQ(ReadFile(spec.heading_log).find("PTNL"), std::string::npos);
  const io::NmeaLog log = recording::ReadAttitudeLog(spec);
  ExpectReadBack(w.samples, log, false);  // an AVR carries no σ
  EXPECT_EQ(log.attitudes_by_source.at("$PTNL,AVR"), static_cast<int64_t>(w.samples.size()));
}

TEST(AttitudeSessionTest, WithoutSamplesNoAttitudeStreamIsWritten) {
  const fs::path dir = FreshScratchDir("none");
  SimulationConfig config = ShortScenario();
  config.attitude_own_log = true;
  WriteSimulatedSession(config, 3, dir.string());
  EXPECT_TRUE(io::ReadSession(dir.string()).attitude_log.empty());
  EXPECT_FALSE(fs::exists(dir / "attitude.nmea"));
}

// An existing scenario (no attitude keys) writes its files as before this stream existed: no
// attitude sentence, no attitude: in session.yaml, no attitude key in truth.yaml, and in a
// recording no /imu/data topic.
TEST(AttitudeSessionTest, AnExistingScenarioWritesNoTraceOfAnAttitudeStream) {
  const fs::path dir = FreshScratchDir("existing");
  const SimulationConfig config = ShortScenario();
  const SimulateSummary summary = WriteSimulatedSession(config, 1, dir.string());
  EXPECT_EQ(summary.attitudes, 0);
  for (const char* file : {"session.yaml", "truth.yaml", "heading.nmea", "gnss.nmea"}) {
    const std::string text = ReadFile((dir / file).string());
    EXPECT_EQ(text.find("attitude"), std::string::npos) << file;
    EXPECT_EQ(text.find("PASHR"), std::string::npos) << file;
    EXPECT_EQ(text.find("PTNL"), std::string::npos) << file;
  }
  const fs::path bag = FreshScratchDir("existing_bag");
  fs::copy(dir, bag, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
  ConvertSessionToRecording(bag.string(), SessionFormat::kMcap);
  EXPECT_EQ(ReadFile((bag / "session.yaml").string()).find("attitude"), std::string::npos);
  EXPECT_EQ(ReadFile((bag / "session.mcap").string()).find("/imu/data"), std::string::npos);
}

// The attitude settings are optional keys of the scenario: truth.yaml names them only when the
// simulation has a stream (attitude_rate_hz > 0), and reads them back.
TEST(AttitudeSessionTest, TruthYamlNamesTheAttitudeSettingsOnlyWhenSet) {
  SimulationConfig config = ShortScenario();
  EXPECT_EQ(FormatTruthYaml(config, 1).find("attitude"), std::string::npos);
  config.attitude_rate_hz = 20.0;
  config.attitude_white_sigma_rad = 0.05 * kDegToRad;
  config.attitude_sentence = "avr";
  config.attitude_own_log = true;
  const fs::path dir = FreshScratchDir("truth");
  const std::string path = (dir / "truth.yaml").string();
  { std::ofstream(path) << FormatTruthYaml(config, 1); }
  const SimulationConfig read = ReadTruthYaml(path);
  EXPECT_DOUBLE_EQ(read.attitude_rate_hz, 20.0);
  EXPECT_NEAR(read.attitude_white_sigma_rad, 0.05 * kDegToRad, 1e-15);
  EXPECT_EQ(read.attitude_sentence, "avr");
  EXPECT_TRUE(read.attitude_own_log);
}

TEST(AttitudeSessionTest, EveryRecordingFormatCarriesTheImuTopic) {
  const Written text = TextSession("recorded_text", "pashr", true);
  for (const std::string format : {"ros1", "ros1-bz2", "ros1-lz4", "mcap", "mcap-lz4", "db3"}) {
    SCOPED_TRACE(format);
    const fs::path dir = FreshScratchDir("recorded_" + format);
    fs::copy(text.dir, dir, fs::copy_options::recursive | fs::copy_options::overwrite_existing);
    ConvertSessionToRecording(dir.string(), *ParseSessionFormat(format));
    EXPECT_FALSE(fs::exists(dir / "attitude.nmea"));  // moved into the recording
    io::SessionSpec spec = io::ReadSession(dir.string());
    EXPECT_EQ(spec.attitude_topic, "/imu/data");
    EXPECT_EQ(spec.attitude_log, spec.gnss_log);
    const recording::PoseLogs logs = recording::ReadPoseLogs(spec);
    ExpectReadBack(text.samples, logs.attitudes, true);
    EXPECT_EQ(logs.attitudes.attitudes_by_source.at("sensor_msgs/Imu"),
              static_cast<int64_t>(text.samples.size()));
    // The Imu's yaw is the heading log's at the sample's time.
    spec.heading_topic = "/imu/data";
    const recording::PoseLogs as_headings = recording::ReadPoseLogs(spec, false, true, false);
    ASSERT_EQ(as_headings.headings.headings.size(), text.samples.size());
    for (size_t i = 0; i < text.samples.size(); i += 17) {
      const double expected = HeadingAt(text.headings, text.samples[i].stamp_s);
      EXPECT_NEAR(WrapAngle(as_headings.headings.headings[i].heading_rad - expected), 0.0,
                  1e-4 * kDegToRad)
          << i;
    }
  }
}

TEST(AttitudeSessionTest, HeadingAtInterpolatesAlongTheShorterArc) {
  std::vector<io::HeadingSample> headings(2);
  headings[0].stamp_s = 10.0;
  headings[0].heading_rad = 350.0 * kDegToRad;
  headings[1].stamp_s = 11.0;
  headings[1].heading_rad = 10.0 * kDegToRad;
  EXPECT_NEAR(HeadingAt(headings, 10.25), 355.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(HeadingAt(headings, 10.75), 5.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(HeadingAt(headings, 9.0), 350.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(HeadingAt(headings, 12.0), 10.0 * kDegToRad, 1e-12);
  EXPECT_TRUE(std::isnan(HeadingAt({}, 1.0)));
}

}  // namespace
}  // namespace wallcal::sim
