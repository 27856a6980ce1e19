// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session with several scanners (session.yaml `scanners:`) as one library call. Each scanner
// first goes through its own session (pipeline::CalibrationSession on io::SessionForScanner: its
// own detection passes, its own clock rounds, its own checks); the scanners that pass are then
// adjusted together (solvers::SolveJointMounts): one set of GNSS, heading, wall and survey-tie
// errors, one mount and one time block per scanner. The joint covariance gives each mount's σ
// and each pair's relative transform with its σ. Each scanner keeps its own run's result and its
// joint result side by side (ScannerRun). Nothing is written here.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/types.h"
#include "pipeline/calibration.h"
#include "pipeline/several_verdict.h"
#include "solvers/joint_mounts.h"

namespace wallcal::pipeline {

// How a multi-scanner run ended. kAll: every scanner calibrated; kPartial: some were refused
// and --allow-partial gave the others their result; kFailed: nothing is written.
enum class SeveralOutcome { kAll, kPartial, kFailed };

// A scanner's part of the joint adjustment: its mount and σ there (the σ includes what the
// other scanners tell about the shared errors), its clock offset there, the change since the
// --compare file's entry of this scanner and the verdict on them, and its report's drawings
// around the joint mount. What the joint adjustment does not re-estimate (the error budget, the
// residual analysis, the repeatability, the clock offset's σ) stays in the scanner's own run.
struct JointScannerResult {
  int index = -1;  // its place in the joint adjustment
  calib::Mount mount;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  // x, y, yaw (m, m, rad)
  // The units' range models' share of it (solvers::JointMountEstimate::range_model_covariance).
  Eigen::Matrix3d range_model_covariance = Eigen::Matrix3d::Zero();
  // Its unit's range offset and scale as the joint adjustment estimated them.
  solvers::JointMountEstimate::UnitRange unit_range;
  // The clock offset (s): what its own run's poses carry plus what the joint time block adds.
  double time_offset_s = 0.0;
  std::optional<Change> change;  // since the --compare file's entry of this scanner
  Decision decision;             // on the joint mount and σ (pipeline::DecideJointScanner)
  ReportData report;             // its own run's drawings around the joint mount
};

struct ScannerRun {
  io::ScannerSpec spec;
  // Its own run: what a calibration of this scanner alone gives (the benchmark differences two
  // of them). Never changed by the joint adjustment.
  CalibrationResult own;
  // Its result in the joint adjustment; empty when it is not in it (refused, or the joint
  // adjustment failed).
  std::optional<JointScannerResult> joint;
  // Its own run could not determine the mount (own.solve.estimate says why).
  bool refused() const { return !own.solve.estimate.usable; }
};

struct RelativeMountResult {
  std::string from_id, to_id;  // from: the scanner listed earlier in session.yaml
  solvers::RelativeMount mount;  // its covariance includes the units' range models
  // Their share of mount.covariance: what the two units' range offsets and scales add.
  Eigen::Matrix3d range_model_covariance = Eigen::Matrix3d::Zero();
  std::optional<Change> change;  // since the --compare file's (from, to) entry, when it has one
  Decision decision;             // against acceptance.relative_* (pipeline::DecideRelative)
};

struct SeveralScannersResult {
  io::SessionSpec session;
  std::vector<ScannerRun> scanners;  // in session.yaml's order
  solvers::JointMountEstimate joint;  // over the scanners with a joint result, in that order
  std::vector<RelativeMountResult> relative;  // every pair of scanners in the joint adjustment
  // --compare: the scanners in one file only (pipeline::SeveralChanges), and the file's digest
  // for offsets.yaml's source.inputs (empty role: no --compare).
  std::vector<std::string> not_in_previous, only_in_previous;
  io::InputFileDigest previous_input;
  // The run's verdict (pipeline::DecideSeveral): the worst of the scanners' and the relative
  // transforms'. Decided when the joint adjustment gave a result.
  Decision decision;
  SeveralOutcome outcome = SeveralOutcome::kFailed;
  std::string message;  // why kFailed or kPartial, naming the scanners
  double seconds = 0.0;
};

// Runs every scanner of request.session_path's `scanners:` and the joint adjustment.
// allow_partial: a refused scanner does not fail the run while at least one other is
// calibrated. request.compare_path (optional) is read as io::ReadPreviousSeveralOffsets: each
// scanner and relative transform is compared with its entry there, and each scanner's verdict
// is decided on the joint estimate. Throws io::InputError for bad input (with the scanner's
// name where it is the scanner's), and when the session has no `scanners:` list.
SeveralScannersResult RunSeveralScanners(const CalibrateRequest& request, bool allow_partial,
                                         const ProgressFn& progress = nullptr);

}  // namespace wallcal::pipeline
