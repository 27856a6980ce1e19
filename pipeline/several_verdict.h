// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a run with several scanners (pipeline/multi_scanner.h) tells about the change since an
// earlier calibration (calibrate --compare): each scanner compared by id, each relative
// transform by (from, to), and the scanners found in one file only. Computed once here, shown
// by the summary, offsets.yaml and the report.

#include <optional>
#include <string>
#include <vector>

#include "io/types.h"
#include "pipeline/calibration.h"
#include "pipeline/verdict.h"
#include "solvers/joint_mounts.h"

namespace wallcal::pipeline {

struct SeveralScannersResult;

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
// transforms by (from, to). A refused scanner gets no change and is not "not in previous".
SeveralChanges CompareSeveral(const SeveralScannersResult& several,
                              const io::PreviousSeveralOffsets& previous);

// The verdict of a scanner's result (pipeline::Decide) on the estimate, forced flag, σ and
// flagged residual trends `result` holds, with `change`: a one-scanner run's on its own
// estimate, a scanner of several's on the joint mount and σ.
Decision DecideCalibration(const CalibrationResult& result, const std::optional<Change>& change);

// The change of a relative transform since `previous` (CompareMounts on the pose of `to` in
// `from` and its covariance).
Change CompareRelative(const solvers::RelativeMount& now, const io::PreviousOffsets& previous);

}  // namespace wallcal::pipeline
