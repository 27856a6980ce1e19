// SPDX-License-Identifier: Apache-2.0
// The change since a previous calibration and the verdicts of a run with several scanners
// (pipeline/several_verdict.h), on hand-made results: which entries are matched, what is named,
// and which tolerances decide.

#include "pipeline/several_verdict.h"

#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "common/angles.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::pipeline {
namespace {

ScannerRun Calibrated(const std::string& id, const std::string& frame, int joint_index,
                      const solvers::Mount& mount) {
  ScannerRun run;
  run.spec.id = id;
  run.spec.frame = frame;
  run.own.solve.estimate.mount = mount;
  run.own.solve.estimate.covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal();
  run.own.solve.estimate.usable = true;
  if (joint_index >= 0) {
    JointScannerResult joint;
    joint.index = joint_index;
    joint.mount = mount;
    joint.covariance = run.own.solve.estimate.covariance;
    run.joint = joint;
  }
  return run;
}

io::PreviousOffsets Offsets(double x_m, double y_m, double yaw_rad, double variance_xy_m2) {
  io::PreviousOffsets offsets;
  offsets.file = "old.yaml";
  offsets.x_m = x_m;
  offsets.y_m = y_m;
  offsets.yaw_rad = yaw_rad;
  offsets.sigma_known = true;
  offsets.covariance[0] = offsets.covariance[4] = variance_xy_m2;
  offsets.covariance[8] = 1e-6;
  return offsets;
}

// Two calibrated scanners (left, right), one refused (rear), and left -> right.
SeveralScannersResult TwoOfThree() {
  SeveralScannersResult several;
  several.scanners.push_back(Calibrated("left", "laser_left", 0, {2.45, 0.75, 0.5236}));
  several.scanners.push_back(Calibrated("right", "laser_right", 1, {2.45, -0.75, -0.5236}));
  ScannerRun rear = Calibrated("rear", "rear", -1, {-1.0, 0.0, kPi});
  rear.own.solve.estimate.usable = false;
  several.scanners.push_back(rear);
  RelativeMountResult relative;
  relative.from_id = "left";
  relative.to_id = "right";
  relative.mount.from_T_to = {-0.75, -1.299, -1.0472};
  relative.mount.covariance = Eigen::Vector3d(1e-7, 1e-7, 1e-9).asDiagonal();
  several.relative.push_back(relative);
  return several;
}

TEST(SeveralVerdictTest, ComparesEachScannerByIdAndNamesThoseInOneFileOnly) {
  io::PreviousSeveralOffsets previous;
  previous.several = true;
  previous.scanners.push_back({"left", Offsets(2.44, 0.75, 0.5236, 1e-4)});
  previous.scanners.push_back({"middle", Offsets(1.0, 0.0, 0.0, 1e-4)});
  previous.relative.push_back({"left", "right", Offsets(-0.75, -1.2985, -1.0472, 1e-7)});
  const SeveralChanges changes = CompareSeveral(TwoOfThree(), previous);
  ASSERT_EQ(changes.scanners.size(), 3u);
  ASSERT_TRUE(changes.scanners[0].has_value());
  EXPECT_NEAR(changes.scanners[0]->dx_m, 0.01, 1e-12);
  // σ now and before both 10 mm: 10 mm is 1/√2 combined σ.
  EXPECT_NEAR(changes.scanners[0]->x_sigmas, 1.0 / std::sqrt(2.0), 1e-9);
  EXPECT_FALSE(changes.scanners[1].has_value());
  EXPECT_FALSE(changes.scanners[2].has_value());  // refused: nothing to compare
  EXPECT_EQ(changes.not_in_previous, std::vector<std::string>{"right"});
  EXPECT_EQ(changes.only_in_previous, std::vector<std::string>{"middle"});
  ASSERT_EQ(changes.relative.size(), 1u);
  ASSERT_TRUE(changes.relative[0].has_value());
  EXPECT_NEAR(changes.relative[0]->dy_m, -0.0005, 1e-12);
  // σ 0.32 mm now and before: 0.5 mm is 1.12 combined σ.
  EXPECT_NEAR(changes.relative[0]->y_sigmas, 0.0005 / std::sqrt(2e-7), 1e-9);
}

TEST(SeveralVerdictTest, InvertedPreviousPoseCarriesItsCovarianceThroughTheJacobian) {
  // a_T_b = (1 m, 0, 90°): a's origin lies 1 m along b's y axis, b_T_a = (0, 1 m, −90°).
  io::PreviousOffsets a_T_b = Offsets(1.0, 0.0, 0.5 * kPi, 0.0);
  a_T_b.covariance[0] = 4e-6;  // σ x 2 mm
  a_T_b.covariance[4] = 1e-6;  // σ y 1 mm
  a_T_b.covariance[8] = 9e-6;  // σ yaw 3 mrad
  a_T_b.created_utc = "2026-01-01T00:00:00Z";
  const io::PreviousOffsets b_T_a = InvertPrevious(a_T_b);
  EXPECT_NEAR(b_T_a.x_m, 0.0, 1e-12);
  EXPECT_NEAR(b_T_a.y_m, 1.0, 1e-12);
  EXPECT_NEAR(b_T_a.yaw_rad, -0.5 * kPi, 1e-12);
  // J = [[0, −1, 1], [1, 0, 0], [0, 0, −1]] at yaw 90°: x' takes y's and yaw's variance (the
  // 1 m lever arm), y' takes x's, and x' and yaw' are anti-correlated.
  const double expected[9] = {1e-6 + 9e-6, 0.0, -9e-6, 0.0, 4e-6, 0.0, -9e-6, 0.0, 9e-6};
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(b_T_a.covariance[k], expected[k], 1e-18) << k;
  EXPECT_TRUE(b_T_a.sigma_known);
  EXPECT_EQ(b_T_a.file, "old.yaml");
  EXPECT_EQ(b_T_a.created_utc, a_T_b.created_utc);
  // The inverse of the inverse is the pose and covariance again.
  const io::PreviousOffsets again = InvertPrevious(b_T_a);
  EXPECT_NEAR(again.x_m, 1.0, 1e-12);
  EXPECT_NEAR(again.y_m, 0.0, 1e-12);
  EXPECT_NEAR(again.yaw_rad, 0.5 * kPi, 1e-12);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(again.covariance[k], a_T_b.covariance[k], 1e-18) << k;
}

TEST(SeveralVerdictTest, RelativeTransformHeldTheOtherWayRoundIsInvertedAndSaysSo) {
  // The previous session listed right before left: it holds left in right, the inverse of a
  // left -> right 5 mm further along x, with σ x 0.6 mm and σ y 0.3 mm in left's frame.
  io::PreviousOffsets left_T_right = Offsets(-0.745, -1.299, -1.0472, 1e-7);
  left_T_right.covariance[0] = 3.6e-7;
  io::PreviousSeveralOffsets previous;
  previous.several = true;
  previous.relative.push_back({"right", "left", InvertPrevious(left_T_right)});
  const SeveralChanges changes = CompareSeveral(TwoOfThree(), previous);
  ASSERT_TRUE(changes.relative[0].has_value());
  const Change& change = *changes.relative[0];
  EXPECT_TRUE(change.previous_inverted);
  EXPECT_NEAR(change.dx_m, -0.005, 1e-9);
  EXPECT_NEAR(change.dy_m, 0.0, 1e-9);
  EXPECT_NEAR(change.dyaw_rad, 0.0, 1e-9);
  // σ x now 0.32 mm, before 0.6 mm (in left's frame again, not the 0.3-0.6 mm mix of right's).
  EXPECT_NEAR(change.x_sigmas, 0.005 / std::sqrt(1e-7 + 3.6e-7), 1e-6);
  // The same direction is taken as it is.
  previous.relative.push_back({"left", "right", left_T_right});
  const SeveralChanges direct = CompareSeveral(TwoOfThree(), previous);
  ASSERT_TRUE(direct.relative[0].has_value());
  EXPECT_FALSE(direct.relative[0]->previous_inverted);
  EXPECT_NEAR(direct.relative[0]->dx_m, -0.005, 1e-12);
}

TEST(SeveralVerdictTest, OneScannerFileIsMatchedByTheScannersFrame) {
  io::PreviousSeveralOffsets previous;
  previous.several = false;
  previous.scanners.push_back({"laser_right", Offsets(2.45, -0.76, -0.5236, 1e-4)});
  const SeveralChanges changes = CompareSeveral(TwoOfThree(), previous);
  EXPECT_FALSE(changes.scanners[0].has_value());
  ASSERT_TRUE(changes.scanners[1].has_value());
  EXPECT_NEAR(changes.scanners[1]->dy_m, 0.01, 1e-12);
  EXPECT_EQ(changes.not_in_previous, std::vector<std::string>{"left"});
  EXPECT_TRUE(changes.only_in_previous.empty());
}

TEST(SeveralVerdictTest, ScannerVerdictFollowsTheSigmaAndChangeItIsGiven) {
  const ScannerRun run = TwoOfThree().scanners[0];  // σ 10 mm, 0.057°
  JointScannerResult joint = *run.joint;
  EXPECT_EQ(DecideJointScanner(run.own, joint).verdict, Verdict::kAccept);
  // σ yaw 0.057° is within the default 0.2°; a joint σ beyond it rejects.
  joint.covariance(2, 2) = std::pow(0.3 / kRadToDeg, 2);
  EXPECT_EQ(DecideJointScanner(run.own, joint).verdict, Verdict::kReject);
  // The own run's σ decides its own verdict: the joint one does not change it.
  EXPECT_EQ(DecideCalibration(run.own, std::nullopt).verdict, Verdict::kAccept);
  joint.covariance(2, 2) = 1e-6;
  Change moved;
  moved.previous_file = "old.yaml";
  moved.dx_m = 0.03;  // beyond acceptance.max_change_xy_m (20 mm)
  joint.change = moved;
  const Decision decision = DecideJointScanner(run.own, joint);
  EXPECT_EQ(decision.verdict, Verdict::kReview);
  ASSERT_EQ(decision.reasons.size(), 1u);
  EXPECT_NE(decision.reasons[0].find("max_change_xy_m"), std::string::npos) << decision.reasons[0];
}

TEST(SeveralVerdictTest, RelativeTransformIsJudgedByItsOwnTolerances) {
  const AcceptanceOptions acceptance;  // 5 mm, 0.05°; changes 10 mm, 0.1°
  solvers::RelativeMount relative = TwoOfThree().relative[0].mount;  // σ 0.32 mm, 0.0018°
  EXPECT_EQ(DecideRelative(relative, std::nullopt, acceptance).verdict, Verdict::kAccept);
  relative.covariance(1, 1) = std::pow(0.006, 2);  // σ y 6 mm: merged scans part
  Decision decision = DecideRelative(relative, std::nullopt, acceptance);
  EXPECT_EQ(decision.verdict, Verdict::kReject);
  ASSERT_EQ(decision.reasons.size(), 1u);
  EXPECT_NE(decision.reasons[0].find("acceptance.relative_max_sigma_xy_m"), std::string::npos);
  relative.covariance(1, 1) = 1e-7;
  relative.covariance(2, 2) = std::pow(0.06 / kRadToDeg, 2);
  EXPECT_EQ(DecideRelative(relative, std::nullopt, acceptance).verdict, Verdict::kReject);
  relative.covariance(2, 2) = 1e-9;
  // A change within the mm tolerances but of many combined σ: REVIEW by max_change_sigmas.
  Change small;
  small.previous_file = "old.yaml";
  small.dx_m = 0.002;
  small.x_sigmas = 4.5;
  decision = DecideRelative(relative, small, acceptance);
  EXPECT_EQ(decision.verdict, Verdict::kReview);
  ASSERT_EQ(decision.reasons.size(), 1u);
  EXPECT_NE(decision.reasons[0].find("max_change_sigmas"), std::string::npos);
  Change turned;
  turned.previous_file = "old.yaml";
  turned.dyaw_rad = 0.15 / kRadToDeg;
  decision = DecideRelative(relative, turned, acceptance);
  EXPECT_EQ(decision.verdict, Verdict::kReview);
  EXPECT_NE(decision.reasons[0].find("relative_max_change_yaw_deg"), std::string::npos);
  small.x_sigmas = 1.0;
  EXPECT_EQ(DecideRelative(relative, small, acceptance).verdict, Verdict::kAccept);
}

TEST(SeveralVerdictTest, RunVerdictIsTheWorstAndALeftOutScannerIsAtLeastReview) {
  SeveralScannersResult several = TwoOfThree();
  several.scanners[0].joint->decision.verdict = Verdict::kAccept;
  several.scanners[1].joint->decision.verdict = Verdict::kAccept;
  several.scanners[2].own.decided.decision.verdict = Verdict::kReject;  // refused: left out
  several.relative[0].decision.verdict = Verdict::kAccept;
  Decision run = DecideSeveral(several);
  EXPECT_EQ(run.verdict, Verdict::kReview);
  ASSERT_EQ(run.reasons.size(), 1u);
  EXPECT_EQ(run.reasons[0], "rear: left out (mount not determined)");
  several.scanners.pop_back();
  EXPECT_EQ(DecideSeveral(several).verdict, Verdict::kAccept);
  several.relative[0].decision.verdict = Verdict::kReject;
  run = DecideSeveral(several);
  EXPECT_EQ(run.verdict, Verdict::kReject);
  ASSERT_EQ(run.reasons.size(), 1u);
  EXPECT_EQ(run.reasons[0], "right in left: REJECT");
  several.scanners[0].joint->decision.verdict = Verdict::kReview;
  several.relative[0].decision.verdict = Verdict::kAccept;
  EXPECT_EQ(DecideSeveral(several).verdict, Verdict::kReview);
}

}  // namespace
}  // namespace wallcal::pipeline
