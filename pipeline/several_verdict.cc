// SPDX-License-Identifier: Apache-2.0
// Changes and verdicts of a run with several scanners (pipeline/several_verdict.h).

#include "pipeline/several_verdict.h"

#include <algorithm>
#include <cmath>
#include <set>

#include <Eigen/Core>

#include "common/angles.h"
#include "common/format.h"
#include "pipeline/internal/steps.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::pipeline {

namespace {

// The verdict on `estimate` with what the run says of it.
Decision DecideOn(const solvers::MountEstimate& estimate, const CalibrationResult& run,
                  const std::optional<Change>& change) {
  DecisionInputs in;
  in.estimate = &estimate;
  in.why = run.Why();
  in.forced = run.solve.forced;
  in.sigma_known = run.solve.sigma_known;
  in.change = &change;
  in.acceptance = &run.loaded.options.acceptance;
  in.site_reviews = SiteReviews(run, estimate);
  for (const analysis::ResidualTrend& t : run.finish.residual_analysis.trends) {
    in.flagged_trends += t.flagged ? 1 : 0;
  }
  return Decide(in);
}

}  // namespace

Decision DecideCalibration(const CalibrationResult& result, const std::optional<Change>& change) {
  return DecideOn(result.solve.estimate, result, change);
}

Decision DecideJointScanner(const CalibrationResult& own, const JointScannerResult& joint) {
  solvers::MountEstimate estimate;
  estimate.usable = true;
  estimate.mount = joint.mount;
  estimate.covariance = joint.covariance;
  return DecideOn(estimate, own, joint.change);
}

Decision DecideRelative(const solvers::RelativeMount& relative, const std::optional<Change>& change,
                        const AcceptanceOptions& a,
                        const Eigen::Matrix3d& unit_share) {
  Decision d;
  d.verdict = Verdict::kAccept;
  auto flag = [&d](Verdict verdict, const std::string& why) {
    d.verdict = std::max(d.verdict, verdict);  // the enum runs ACCEPT < REVIEW < REJECT
    d.reasons.push_back(why);
  };
  const Eigen::Matrix3d& c = relative.covariance;
  const double sx = std::sqrt(c(0, 0)), sy = std::sqrt(c(1, 1)), syaw = std::sqrt(c(2, 2));
  // The data's σ alone: when it is within a limit that the total is not, the units' range
  // models put it there, and more driving does not help.
  const Eigen::Matrix3d data = c - unit_share;
  const auto data_sigma = [&data](int i) { return std::sqrt(std::max(0.0, data(i, i))); };
  const std::string units_advice =
      "; the units' range offsets and scales make most of it (their presets' range_model_sigma): "
      "characterise each unit (wallcal characterise) and give its measured preset as the "
      "scanner's model";
  if (!(std::max(sx, sy) <= a.relative_max_sigma_xy_m)) {
    const bool units = std::max(data_sigma(0), data_sigma(1)) <= a.relative_max_sigma_xy_m;
    flag(Verdict::kReject, Format("σ x %.2f mm, y %.2f mm: beyond "
                                  "acceptance.relative_max_sigma_xy_m %.2f mm",
                                  sx * 1e3, sy * 1e3, a.relative_max_sigma_xy_m * 1e3) +
                               (units ? units_advice : ""));
  }
  if (!(syaw <= a.relative_max_sigma_yaw_rad)) {
    const bool units = data_sigma(2) <= a.relative_max_sigma_yaw_rad;
    flag(Verdict::kReject,
         Format("σ yaw %.4f°: beyond acceptance.relative_max_sigma_yaw_deg %.4f°",
                syaw * kRadToDeg, a.relative_max_sigma_yaw_rad * kRadToDeg) +
             (units ? units_advice : ""));
  }
  if (change) {
    const Change& ch = *change;
    if (std::max(std::abs(ch.dx_m), std::abs(ch.dy_m)) > a.relative_max_change_xy_m) {
      flag(Verdict::kReview,
           Format("moved x %+.1f mm, y %+.1f mm against the other scanner since %s: beyond "
                  "acceptance.relative_max_change_xy_m %.1f mm (was one of them moved or bumped?)",
                  ch.dx_m * 1e3, ch.dy_m * 1e3, ch.previous_file.c_str(),
                  a.relative_max_change_xy_m * 1e3));
    }
    if (std::abs(ch.dyaw_rad) > a.relative_max_change_yaw_rad) {
      flag(Verdict::kReview,
           Format("turned %+.3f° against the other scanner since %s: beyond "
                  "acceptance.relative_max_change_yaw_deg %.3f°",
                  ch.dyaw_rad * kRadToDeg, ch.previous_file.c_str(),
                  a.relative_max_change_yaw_rad * kRadToDeg));
    }
    const double largest = std::max({ch.x_sigmas, ch.y_sigmas, ch.yaw_sigmas});
    if (largest > a.max_change_sigmas) {
      flag(Verdict::kReview, Format("the change is %.1f combined σ: more than the two "
                                    "calibrations' errors explain (acceptance.max_change_sigmas "
                                    "%.1f)",
                                    largest, a.max_change_sigmas));
    }
  }
  return d;
}

Decision DecideSeveral(const SeveralScannersResult& several) {
  Decision d;
  d.verdict = Verdict::kAccept;
  auto take = [&d](const Decision& part, const std::string& name) {
    if (part.verdict == Verdict::kAccept) return;
    d.verdict = std::max(d.verdict, part.verdict);
    d.reasons.push_back(name + ": " + VerdictName(part.verdict));
  };
  bool any = false;
  for (const ScannerRun& run : several.scanners) {
    if (!run.joint) {
      d.verdict = std::max(d.verdict, Verdict::kReview);
      d.reasons.push_back(run.spec.id + ": left out (mount not determined)");
      continue;
    }
    any = true;
    take(run.joint->decision, run.spec.id);
  }
  for (const RelativeMountResult& relative : several.relative) {
    take(relative.decision, relative.to_id + " in " + relative.from_id);
  }
  if (!any) d.verdict = Verdict::kReject;
  return d;
}

io::PreviousOffsets InvertPrevious(const io::PreviousOffsets& a_T_b) {
  io::PreviousOffsets b_T_a = a_T_b;
  const double c = std::cos(a_T_b.yaw_rad), s = std::sin(a_T_b.yaw_rad);
  b_T_a.x_m = -c * a_T_b.x_m - s * a_T_b.y_m;
  b_T_a.y_m = s * a_T_b.x_m - c * a_T_b.y_m;
  b_T_a.yaw_rad = WrapAngle(-a_T_b.yaw_rad);
  Eigen::Matrix3d jacobian;
  jacobian << -c, -s, b_T_a.y_m,  //
      s, -c, -b_T_a.x_m,          //
      0.0, 0.0, -1.0;
  const Eigen::Matrix3d covariance =
      jacobian * Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(a_T_b.covariance) *
      jacobian.transpose();
  Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(b_T_a.covariance) = covariance;
  return b_T_a;
}

Change CompareRelative(const solvers::RelativeMount& now, const io::PreviousOffsets& previous) {
  return CompareMounts(now.from_T_to, now.covariance, previous);
}

SeveralChanges CompareSeveral(const SeveralScannersResult& several,
                              const io::PreviousSeveralOffsets& previous) {
  SeveralChanges changes;
  changes.scanners.resize(several.scanners.size());
  changes.relative.resize(several.relative.size());
  std::set<std::string> matched;
  for (size_t s = 0; s < several.scanners.size(); ++s) {
    const ScannerRun& run = several.scanners[s];
    if (!run.joint) continue;
    // A one-scanner file names its scanner by the frame it was calibrated as.
    const std::string& key = previous.several ? run.spec.id : run.spec.frame;
    bool found = false;
    for (const io::PreviousScannerOffsets& old : previous.scanners) {
      if (old.id != key) continue;
      changes.scanners[s] = CompareMounts(run.joint->mount, run.joint->covariance, old.offsets);
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
    const RelativeMountResult& now = several.relative[r];
    for (const io::PreviousRelativeOffsets& old : previous.relative) {
      if (old.from_id == now.from_id && old.to_id == now.to_id) {
        changes.relative[r] = CompareRelative(now.mount, old.offsets);
        break;
      }
    }
    if (changes.relative[r]) continue;
    // The previous session listed the two scanners the other way round: it holds to_T_from.
    for (const io::PreviousRelativeOffsets& old : previous.relative) {
      if (old.from_id == now.to_id && old.to_id == now.from_id) {
        changes.relative[r] = CompareRelative(now.mount, InvertPrevious(old.offsets));
        changes.relative[r]->previous_inverted = true;
        break;
      }
    }
  }
  return changes;
}

}  // namespace wallcal::pipeline
