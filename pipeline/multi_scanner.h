// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session with several scanners (session.yaml `scanners:`) as one library call. Each scanner
// first goes through the one-scanner run (RunCalibration on io::SessionForScanner: its own
// detection passes, its own clock rounds, its own checks); the scanners that pass are then
// adjusted together (solvers::SolveJointMounts): one set of GNSS, heading, wall and survey-tie
// errors, one mount and one time block per scanner. The joint covariance gives each mount's σ
// and each pair's relative transform with its σ. Nothing is written here.

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

struct ScannerRun {
  io::ScannerSpec spec;
  // Its own run; when it is in the joint adjustment, result.estimate.mount and .covariance are
  // replaced by the joint ones (its σ then includes what the other scanners tell about the
  // shared errors), and result.change and result.decision are the joint estimate's (against
  // the --compare file's entry of this scanner).
  CalibrationResult result;
  // Its own run's estimate, before the joint adjustment replaced the mount and σ: what a
  // calibration of this scanner alone gives (the benchmark differences two of them).
  solvers::MountEstimate own_estimate;
  bool refused = false;   // its own run could not determine the mount (result.estimate says why)
  int joint_index = -1;   // its place in the joint adjustment (-1: not in it)
};

struct RelativeMountResult {
  std::string from_id, to_id;  // from: the scanner listed earlier in session.yaml
  solvers::RelativeMount mount;
  std::optional<Change> change;  // since the --compare file's (from, to) entry, when it has one
  Decision decision;             // against acceptance.relative_* (pipeline::DecideRelative)
};

struct SeveralScannersResult {
  io::SessionSpec session;
  std::vector<ScannerRun> scanners;  // in session.yaml's order
  solvers::JointMountEstimate joint;  // over the scanners with joint_index >= 0, in that order
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
