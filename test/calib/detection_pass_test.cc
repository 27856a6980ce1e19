// SPDX-License-Identifier: Apache-2.0
// Tests of the observation finder (calib/detection_pass.h) on scans ray-cast from a known mount:
// a vehicle that stands 20 s in front of the north wall and then creeps east, with scans before,
// during and after its GNSS and heading logs. Each scan's fate is known by construction.

#include "calib/detection_pass.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "io/scan_source.h"
#include "test/support/shipped_presets.h"
#include "test/support/synthetic_fixtures.h"

namespace wallcal::calib {
namespace {

// The scans as a stream, in the given order.
class VectorScanSource : public io::ScanSource {
 public:
  explicit VectorScanSource(std::vector<io::ScanRecord> scans) : scans_(std::move(scans)) {}
  bool Next(io::ScanRecord* scan) override {
    if (next_ >= scans_.size()) return false;
    *scan = scans_[next_++];
    return true;
  }
  const io::SkipCounts& skipped() const override { return skipped_; }
  int64_t scans_read() const override { return static_cast<int64_t>(next_); }
  const std::string& path() const override { return path_; }

 private:
  std::vector<io::ScanRecord> scans_;
  size_t next_ = 0;
  io::SkipCounts skipped_;
  std::string path_ = "scans.clf";
};

// The session's timeline (s): logs from kLogStart to kLogEnd; the vehicle stands at
// kAntennaStill facing north until kStopEnd, then creeps east at kCreep_mps.
constexpr double kLogStart = 100.0, kStopEnd = 120.0, kLogEnd = 140.0;
constexpr double kCreep_mps = 0.25;
constexpr double kScanPeriod_s = 0.125;  // a binary fraction: stamps and intervals are exact
const Eigen::Vector2d kAntennaStill(0.0, 2.0);
const Mount kTruth{1.0, 0.2, 0.03};

Eigen::Vector2d TrueAntenna(double t) {
  return kAntennaStill + Eigen::Vector2d(kCreep_mps * std::max(0.0, t - kStopEnd), 0.0);
}

// The shipped LMS 291 with its range correction left out (the scans below are exact ranges
// plus noise).
io::ScannerPreset Preset() {
  io::ScannerPreset preset = testing_support::ShippedPreset("sick_lms291");
  preset.range_scale_k = 1.0;
  preset.range_offset_b_m = 0.0;
  return preset;
}

// GNSS at 5 Hz and heading at 10 Hz over the logs, noise-free.
PoseInterpolator Poses() {
  std::vector<PositionSample> positions;
  std::vector<YawSample> yaws;
  for (int i = 0; kLogStart + 0.1 * i <= kLogEnd + 1e-9; ++i) {
    const double t = kLogStart + 0.1 * i;
    if (i % 2 == 0) positions.push_back({t, TrueAntenna(t), 0.01});
    yaws.push_back({t, 0.5 * kPi});
  }
  return PoseInterpolator(positions, yaws, AlignmentOptions());
}

// One scan at stamp_s of the wall y = 10 (x in [−10, 10]) from the true pose, each range with
// Gaussian noise of the preset's σ; a beam that misses the wall reads the maximum (no return).
io::ScanRecord RayCast(double stamp_s, int line, const io::ScannerPreset& preset,
                       std::mt19937* rng) {
  std::normal_distribution<double> noise(0.0, preset.range_sigma_m);
  const WallGeometry wall = testing_support::NorthWall();
  const double yaw_rad = 0.5 * kPi;
  const Eigen::Vector2d scanner =
      TrueAntenna(stamp_s) + Eigen::Rotation2Dd(yaw_rad) * Eigen::Vector2d(kTruth.x_m, kTruth.y_m);
  io::ScanRecord scan;
  scan.stamp_s = stamp_s;
  scan.line = line;
  scan.start_angle_rad = preset.start_angle_rad;
  scan.angular_step_rad = preset.angular_step_rad;
  scan.max_range_m = preset.max_range_m;
  for (int i = 0; i < preset.num_beams; ++i) {
    const double bearing =
        yaw_rad + kTruth.yaw_rad + preset.start_angle_rad + i * preset.angular_step_rad;
    const Eigen::Vector2d direction(std::cos(bearing), std::sin(bearing));
    const double along = wall.normal_local.dot(direction);
    const double range_m =
        along > 1e-6 ? (wall.offset_m - wall.normal_local.dot(scanner)) / along : -1.0;
    const Eigen::Vector2d hit = scanner + range_m * direction;
    const bool on_wall =
        range_m > 0.0 && hit.x() >= wall.end_a_local.x() && hit.x() <= wall.end_b_local.x();
    scan.ranges_m.push_back(
        static_cast<float>(on_wall ? range_m + noise(*rng) : preset.max_range_m));
  }
  return scan;
}

// Scans every kScanPeriod_s over [from_s, to_s).
void AddScans(double from_s, double to_s, const io::ScannerPreset& preset, std::mt19937* rng,
              std::vector<io::ScanRecord>* scans) {
  for (double t = from_s; t < to_s; t += kScanPeriod_s) {
    scans->push_back(RayCast(t, static_cast<int>(scans->size()) + 1, preset, rng));
  }
}

// How many scans each stretch holds (each stretch is a whole number of periods).
constexpr int kBefore = 32, kStill = 120, kMoving = 112, kAfter = 32;

// Scans before the logs, standing, moving and after the logs; the first and last 2 s of the stop
// and the transition hold none (the dwell's edges are not under test here).
struct Session {
  io::ScannerPreset preset = Preset();
  DetectorOptions detector;
  std::vector<WallGeometry> walls{testing_support::NorthWall()};
  PoseInterpolator poses = Poses();
  std::vector<io::ScanRecord> scans;

  Session() {
    std::mt19937 rng(17);
    AddScans(kLogStart - 4.0, kLogStart, preset, &rng, &scans);    // kBefore
    AddScans(102.0, 117.0, preset, &rng, &scans);                  // kStill
    AddScans(123.0, 137.0, preset, &rng, &scans);                  // kMoving
    AddScans(kLogEnd + 1.0, kLogEnd + 5.0, preset, &rng, &scans);  // kAfter
  }

  PassContext Context(bool use_moving = false, int threads = 1) const {
    PassContext context;
    context.open_scans = [this]() { return std::make_unique<VectorScanSource>(scans); };
    context.preset = &preset;
    context.detector = &detector;
    context.walls = &walls;
    context.poses = &poses;
    context.use_moving = use_moving;
    context.threads = threads;
    return context;
  }
};

PassRequest Tight(const Mount& mount, const DetectorOptions& detector) {
  PassRequest request;
  request.mount = mount;
  request.gates = {detector.tight_angle_gate_rad, detector.tight_offset_gate_m, true,
                   detector.tight_min_inliers};
  return request;
}

int64_t Skipped(const PassOutcome& outcome, ScanSkip reason) {
  const auto it = outcome.skipped.find(reason);
  return it == outcome.skipped.end() ? 0 : it->second;
}

// RMS over the observations of (fitted − predicted from the true mount) / the fit's own σ, for
// rho and theta: about 1 when the lines sit where the mount puts them, to the noise.
std::pair<double, double> NormalisedRms(const Session& session, const PassOutcome& outcome) {
  double sum_rho = 0.0, sum_theta = 0.0;
  for (const WallObservation& o : outcome.observations) {
    const WallGeometry& wall = session.walls[o.wall_index];
    sum_rho += std::pow((o.rho_m - PredictRho(o, wall, kTruth)) / o.sigma_rho_m, 2);
    sum_theta +=
        std::pow(WrapAngle(o.theta_rad - PredictTheta(o, wall, kTruth)) / o.sigma_theta_rad, 2);
  }
  const double n = static_cast<double>(outcome.observations.size());
  return {std::sqrt(sum_rho / n), std::sqrt(sum_theta / n)};
}

TEST(DetectionPassTest, FindsTheWallWhereTheMountPutsItAndCountsEveryOtherScanByReason) {
  const Session session;
  const PassOutcome outcome = DetectionPass(session.Context(), Tight(kTruth, session.detector));
  EXPECT_EQ(outcome.scans_read, kBefore + kStill + kMoving + kAfter);
  EXPECT_EQ(outcome.scans_examined, outcome.scans_read);
  EXPECT_EQ(Skipped(outcome, ScanSkip::kNoPoseBeforeLogs), kBefore);
  EXPECT_EQ(Skipped(outcome, ScanSkip::kNoPoseAfterLogs), kAfter);
  EXPECT_EQ(Skipped(outcome, ScanSkip::kVehicleMoving), kMoving);
  EXPECT_EQ(Skipped(outcome, ScanSkip::kWallNotDetected), 0);
  ASSERT_EQ(outcome.observations.size(), static_cast<size_t>(kStill));
  for (const WallObservation& o : outcome.observations) {
    EXPECT_EQ(o.wall_index, 0);
    EXPECT_TRUE(o.pose.stationary);
    EXPECT_GE(o.scan_index, kBefore);
    EXPECT_LT(o.scan_index, kBefore + kStill);
  }
  // The scanner stands 7 m from the wall and is turned 0.03 rad: the fitted lines agree with
  // the true mount's prediction to their own σ (range noise over ~100 inliers).
  const auto [rms_rho, rms_theta] = NormalisedRms(session, outcome);
  EXPECT_GT(rms_rho, 0.5);
  EXPECT_LT(rms_rho, 2.0);
  EXPECT_GT(rms_theta, 0.5);
  EXPECT_LT(rms_theta, 2.0);
  EXPECT_DOUBLE_EQ(outcome.first_stamp_s, kLogStart - 4.0);
  EXPECT_DOUBLE_EQ(outcome.last_stamp_s, kLogEnd + 5.0 - kScanPeriod_s);
  EXPECT_EQ(outcome.not_increasing, 0);
  EXPECT_EQ(outcome.beam_count_mismatch, 0);
}

TEST(DetectionPassTest, MovingScansGiveObservationsWhenAsked) {
  const Session session;
  const PassOutcome outcome =
      DetectionPass(session.Context(/*use_moving=*/true), Tight(kTruth, session.detector));
  EXPECT_EQ(Skipped(outcome, ScanSkip::kVehicleMoving), 0);
  ASSERT_EQ(outcome.observations.size(), static_cast<size_t>(kStill + kMoving));
  int moving = 0;
  for (const WallObservation& o : outcome.observations) moving += o.pose.stationary ? 0 : 1;
  EXPECT_EQ(moving, kMoving);
  const auto [rms_rho, rms_theta] = NormalisedRms(session, outcome);
  EXPECT_LT(rms_rho, 2.0);
  EXPECT_LT(rms_theta, 2.0);
}

TEST(DetectionPassTest, TheOutcomeIsTheSameWhateverTheThreadCount) {
  // More scans than one batch, so that the batches and their overlap with reading are used.
  const Session session;
  ASSERT_GT(session.scans.size(), 256u);
  const PassOutcome one = DetectionPass(session.Context(true, 1), Tight(kTruth, session.detector));
  const PassOutcome three =
      DetectionPass(session.Context(true, 3), Tight(kTruth, session.detector));
  ASSERT_EQ(one.observations.size(), three.observations.size());
  for (size_t i = 0; i < one.observations.size(); ++i) {
    EXPECT_EQ(one.observations[i].scan_index, three.observations[i].scan_index);
    EXPECT_EQ(one.observations[i].rho_m, three.observations[i].rho_m);
    EXPECT_EQ(one.observations[i].theta_rad, three.observations[i].theta_rad);
  }
  EXPECT_EQ(one.skipped, three.skipped);
  EXPECT_EQ(one.range_counts.valid, three.range_counts.valid);
  EXPECT_EQ(one.range_counts.no_return, three.range_counts.no_return);
}

TEST(DetectionPassTest, GatesDecideWhatIsFound) {
  const Session session;
  const DetectorOptions& detector = session.detector;
  // A mount 0.6 m off in x moves the predicted wall 0.6 m: outside the tight offset gate
  // (0.25 m), inside the wide one (6 m).
  Mount off = kTruth;
  off.x_m += 0.6;
  const PassOutcome tight = DetectionPass(session.Context(), Tight(off, detector));
  EXPECT_TRUE(tight.observations.empty());
  EXPECT_EQ(Skipped(tight, ScanSkip::kWallNotDetected), kStill);
  PassRequest wide = Tight(off, detector);
  wide.gates = {detector.wide_angle_gate_rad, detector.wide_offset_gate_m, false, 0};
  EXPECT_EQ(DetectionPass(session.Context(), wide).observations.size(),
            static_cast<size_t>(kStill));
  // A mount that puts the scanner beyond the wall: no detection is tried.
  Mount beyond = kTruth;
  beyond.x_m = 20.0;
  const PassOutcome behind = DetectionPass(session.Context(), Tight(beyond, detector));
  EXPECT_TRUE(behind.observations.empty());
  EXPECT_EQ(Skipped(behind, ScanSkip::kScannerBehindWall), kStill);
  // A mount turned round puts the wall behind the scanner's field of view: found in no scan,
  // and said so (not "not detected").
  Mount turned = kTruth;
  turned.yaw_rad += kPi;
  const PassOutcome away = DetectionPass(session.Context(), Tight(turned, detector));
  EXPECT_TRUE(away.observations.empty());
  EXPECT_EQ(Skipped(away, ScanSkip::kWallOutsideField), kStill);
  EXPECT_EQ(Skipped(away, ScanSkip::kWallNotDetected), 0);
}

TEST(DetectionPassTest, AMinimumIntervalExaminesOnlyScansThatFarApartAndTalliesNothing) {
  const Session session;
  PassRequest request = Tight(kTruth, session.detector);
  request.min_interval_s = 8 * kScanPeriod_s;  // every 8th scan of each stretch
  ScanLogTally tally;
  request.tally = &tally;
  const PassOutcome outcome = DetectionPass(session.Context(), request);
  EXPECT_EQ(outcome.scans_examined, (kBefore + kStill + kMoving + kAfter) / 8);
  EXPECT_EQ(outcome.observations.size(), static_cast<size_t>(kStill / 8));
  EXPECT_EQ(Skipped(outcome, ScanSkip::kNoPoseBeforeLogs), kBefore / 8);
  EXPECT_TRUE(tally.stamps_s.empty());
}

TEST(DetectionPassTest, TheTallyCountsEveryScanAndEveryReading) {
  const Session session;
  PassRequest request = Tight(kTruth, session.detector);
  ScanLogTally tally;
  request.tally = &tally;
  const PassOutcome outcome = DetectionPass(session.Context(), request);
  const size_t n = session.scans.size();
  ASSERT_EQ(tally.stamps_s.size(), n);
  EXPECT_EQ(tally.lines.size(), n);
  EXPECT_EQ(tally.beams.at(181), static_cast<int64_t>(n));
  EXPECT_DOUBLE_EQ(tally.first_step_rad, session.preset.angular_step_rad);
  const RangeCounts& r = tally.readings;
  EXPECT_EQ(r.valid + r.error_code + r.no_return + r.too_close + r.non_finite,
            static_cast<int64_t>(181 * n));
  EXPECT_GT(r.valid, 0);
  EXPECT_GT(r.no_return, 0);
  EXPECT_GE(r.valid, outcome.range_counts.valid);
}

TEST(ShiftObservationsTest, MovesEachPoseToItsShiftedTimeAndDropsThoseWithNone) {
  const Session session;
  PassOutcome outcome =
      DetectionPass(session.Context(/*use_moving=*/true), Tight(kTruth, session.detector));
  const std::vector<WallObservation> before = outcome.observations;
  // 4 s later, the headings 0.05 s later still: the moving scans whose heading would be
  // taken after the logs end have no pose.
  const double dt_s = 4.0, heading_shift_s = 0.05;
  int beyond = 0;
  for (const WallObservation& o : before) {
    beyond += o.pose.stamp_s + dt_s + heading_shift_s > kLogEnd ? 1 : 0;
  }
  ASSERT_GT(beyond, 0);
  const int dropped =
      ShiftObservations(session.poses, dt_s, heading_shift_s, &outcome.observations);
  EXPECT_EQ(dropped, beyond);
  ASSERT_EQ(outcome.observations.size(), before.size() - beyond);
  for (size_t i = 0; i < outcome.observations.size(); ++i) {
    const WallObservation& was = before[i];
    const WallObservation& now = outcome.observations[i];
    EXPECT_EQ(now.scan_index, was.scan_index);
    EXPECT_EQ(now.rho_m, was.rho_m);  // the scan's line does not change
    EXPECT_DOUBLE_EQ(now.pose.stamp_s, was.pose.stamp_s + dt_s);
    EXPECT_DOUBLE_EQ(now.pose.clock_shift_s, dt_s);
    EXPECT_DOUBLE_EQ(now.pose.heading_shift_s, heading_shift_s);
    // Away from the start of the creep (where the cubics through two samples each side round
    // the corner) the track is straight at constant speed or still: the antenna is where it
    // was dt later.
    if (std::abs(now.pose.stamp_s - kStopEnd) > 0.5) {
      EXPECT_NEAR((now.pose.antenna_local_m - TrueAntenna(now.pose.stamp_s)).norm(), 0.0, 1e-9);
    }
  }
}

TEST(ScanSkipTest, EveryReasonHasItsOwnNameAndPoseStatusesMapToThem) {
  const std::vector<ScanSkip> reasons = {
      ScanSkip::kNoPoseBeforeLogs, ScanSkip::kNoPoseAfterLogs, ScanSkip::kNoPoseGnssGap,
      ScanSkip::kNoPoseHeadingGap, ScanSkip::kVehicleMoving,   ScanSkip::kScannerBehindWall,
      ScanSkip::kWallNotDetected,  ScanSkip::kMalformedLine,   ScanSkip::kNoPoseAtShiftedTime,
      ScanSkip::kWallOutsideField};
  for (size_t i = 0; i < reasons.size(); ++i) {
    for (size_t j = i + 1; j < reasons.size(); ++j) {
      EXPECT_STRNE(ScanSkipName(reasons[i]), ScanSkipName(reasons[j]));
    }
  }
  EXPECT_EQ(ScanSkipFor(PoseStatus::kBeforeStart), ScanSkip::kNoPoseBeforeLogs);
  EXPECT_EQ(ScanSkipFor(PoseStatus::kAfterEnd), ScanSkip::kNoPoseAfterLogs);
  EXPECT_EQ(ScanSkipFor(PoseStatus::kGnssGap), ScanSkip::kNoPoseGnssGap);
  EXPECT_EQ(ScanSkipFor(PoseStatus::kHeadingGap), ScanSkip::kNoPoseHeadingGap);
}

TEST(GateForTest, CentresOnThePredictedLineAndCarriesTheWallEndsInTheScannerFrame) {
  // Scanner at (−0.2, 3) facing north + 0.03 rad: the wall y = 10 is 7 m ahead, its normal at
  // −0.03 rad in the scanner frame; the end (10, 10) lies 7 m ahead and 10.2 m to the right.
  WallObservation at;
  at.pose.antenna_local_m = kAntennaStill;
  at.pose.yaw_rad = 0.5 * kPi;
  const Gates gates{0.1, 0.2, true, 0};
  const LineGate gate = GateFor(at, testing_support::NorthWall(), kTruth, gates);
  EXPECT_NEAR(gate.rho_m, 7.0, 1e-12);
  EXPECT_NEAR(gate.theta_rad, -0.03, 1e-12);
  EXPECT_EQ(gate.theta_halfwidth_rad, 0.1);
  EXPECT_EQ(gate.rho_halfwidth_m, 0.2);
  ASSERT_TRUE(gate.has_segment);
  const Eigen::Vector2d end_b = Eigen::Rotation2Dd(-kTruth.yaw_rad) * Eigen::Vector2d(7.0, -10.2);
  EXPECT_NEAR((gate.segment_b_scanner - end_b).norm(), 0.0, 1e-12);
  EXPECT_FALSE(
      GateFor(at, testing_support::NorthWall(), kTruth, Gates{0.1, 0.2, false, 0}).has_segment);
}

}  // namespace
}  // namespace wallcal::calib
