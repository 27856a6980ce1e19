// SPDX-License-Identifier: Apache-2.0
// Changes and verdicts of a run with several scanners (pipeline/several_verdict.h).

#include "pipeline/several_verdict.h"

#include <set>

#include "pipeline/multi_scanner.h"

namespace wallcal::pipeline {

Decision DecideCalibration(const CalibrationResult& result, const std::optional<Change>& change) {
  DecisionInputs in;
  in.estimate = &result.estimate;
  in.forced = result.forced;
  in.sigma_known = result.sigma_known;
  in.change = &change;
  in.acceptance = &result.options.acceptance;
  for (const analysis::ResidualTrend& t : result.residual_analysis.trends) {
    in.flagged_trends += t.flagged ? 1 : 0;
  }
  return Decide(in);
}

Change CompareRelative(const solvers::RelativeMount& now, const io::PreviousOffsets& previous) {
  solvers::MountEstimate estimate;
  estimate.mount = now.from_T_to;
  estimate.covariance = now.covariance;
  estimate.usable = true;
  return CompareMounts(estimate, previous);
}

SeveralChanges CompareSeveral(const SeveralScannersResult& several,
                              const io::PreviousSeveralOffsets& previous) {
  SeveralChanges changes;
  changes.scanners.resize(several.scanners.size());
  changes.relative.resize(several.relative.size());
  std::set<std::string> matched;
  for (size_t s = 0; s < several.scanners.size(); ++s) {
    const ScannerRun& run = several.scanners[s];
    if (run.joint_index < 0) continue;
    // A one-scanner file names its scanner by the frame it was calibrated as.
    const std::string& key = previous.several ? run.spec.id : run.spec.frame;
    bool found = false;
    for (const io::PreviousScannerOffsets& old : previous.scanners) {
      if (old.id != key) continue;
      changes.scanners[s] = CompareMounts(run.result.estimate, old.offsets);
      matched.insert(old.id);
      found = true;
      break;
    }
    if (!found) changes.not_in_previous.push_back(run.spec.id);
  }
  for (const io::PreviousScannerOffsets& old : previous.scanners) {
    if (matched.count(old.id) == 0) changes.only_in_previous.push_back(old.id);
  }
  for (size_t r = 0; r < several.relative.size(); ++r) {
    for (const io::PreviousRelativeOffsets& old : previous.relative) {
      if (old.from_id == several.relative[r].from_id && old.to_id == several.relative[r].to_id) {
        changes.relative[r] = CompareRelative(several.relative[r].mount, old.offsets);
        break;
      }
    }
  }
  return changes;
}

}  // namespace wallcal::pipeline
