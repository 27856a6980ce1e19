// SPDX-License-Identifier: Apache-2.0
#pragma once
// The verdicts of a run with several scanners (pipeline/multi_scanner.h) and the change since
// an earlier calibration (calibrate --compare): each scanner compared by id, each relative
// transform by (from, to), the scanners found in one file only; a verdict on each scanner, on
// each relative transform and on the whole run. Computed once here, shown by the summary,
// offsets.yaml and the report.

#include <optional>
#include <string>
#include <vector>

#include "io/types.h"
#include "pipeline/calibration.h"
#include "pipeline/verdict.h"
#include "solvers/joint_mounts.h"

namespace wallcal::pipeline {

struct SeveralScannersResult;
struct JointScannerResult;

// The change of each scanner and relative transform since the previous file (now − previous;
// σ units from both covariances, pipeline::CompareMounts).
struct SeveralChanges {
  std::vector<std::optional<Change>> scanners;  // one per SeveralScannersResult::scanners
  std::vector<std::optional<Change>> relative;  // one per SeveralScannersResult::relative
  std::vector<std::string> not_in_previous;     // calibrated now, absent from the previous file
  std::vector<std::string> only_in_previous;    // in the previous file, not calibrated now
};

// Matches `several`'s calibrated scanners with `previous`: by id when it lists scanner_mounts,
// by the scanner's frame (its child_frame) when it holds one scanner_mount; the relative
// transforms by (from, to), or by (to, from) inverted (InvertPrevious; the change then says
// previous_inverted) when the previous session listed the two scanners in the other order.
// A refused scanner gets no change and is not "not in previous".
SeveralChanges CompareSeveral(const SeveralScannersResult& several,
                              const io::PreviousSeveralOffsets& previous);

// The verdict of a run (pipeline::Decide) on its estimate, forced flag, σ and flagged residual
// trends, with `change`.
Decision DecideCalibration(const CalibrationResult& result, const std::optional<Change>& change);
// The verdict of a scanner of several on its joint mount and σ, with its joint change and what
// its own run says of it (forced, σ known, flagged residual trends), as its own run decides.
Decision DecideJointScanner(const CalibrationResult& own, const JointScannerResult& joint);

// The verdict of a relative transform against acceptance.relative_* (σ beyond them: REJECT;
// a change beyond them or beyond max_change_sigmas combined σ: REVIEW). unit_share: the units'
// range models' share of relative.covariance; when it is what puts σ beyond the limits, the
// reason says so and what brings it down (each unit characterised).
Decision DecideRelative(const solvers::RelativeMount& relative, const std::optional<Change>& change,
                        const AcceptanceOptions& acceptance,
                        const Eigen::Matrix3d& unit_share = Eigen::Matrix3d::Zero());

// The run's verdict: the worst of the calibrated scanners' and the relative transforms', with
// one reason per one that is not ACCEPT ("front_left: REVIEW"); a run that left a scanner out
// (--allow-partial) is at least REVIEW. Reads each result's decision, so those come first.
Decision DecideSeveral(const SeveralScannersResult& several);

// The inverse pose b_T_a of a previous entry a_T_b = (x, y, yaw) (m, rad): yaw' = −yaw,
// t' = −R(−yaw) t, with the covariance carried through the inverse's Jacobian to first order,
// J = [[−c, −s, y'], [s, −c, −x'], [0, 0, −1]] (c, s of yaw; x', y' the inverse's translation).
// An unknown covariance (sigma_known false) stays unknown; the file and date are kept.
io::PreviousOffsets InvertPrevious(const io::PreviousOffsets& a_T_b);

// The change of a relative transform since `previous` (CompareMounts on the pose of `to` in
// `from` and its covariance).
Change CompareRelative(const solvers::RelativeMount& now, const io::PreviousOffsets& previous);

}  // namespace wallcal::pipeline
