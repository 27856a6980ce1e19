// SPDX-License-Identifier: Apache-2.0
// Several scanners: their own runs, then one joint adjustment (pipeline/multi_scanner.h).

#include "pipeline/multi_scanner.h"

#include <chrono>
#include <memory>
#include <vector>

#include "calib/detection_pass.h"
#include "calib/gnss_slices.h"
#include "common/sha256.h"
#include "io/config/offsets_reader.h"
#include "io/config/session_reader.h"
#include "pipeline/session.h"
#include "solvers/mount_problem.h"

namespace wallcal::pipeline {
namespace {

// A scanner's part of the joint adjustment with every pose re-interpolated at its own estimated
// scan time (stamp + the clock offset its run estimated): its run moves the poses only by what
// the data determine, and on stop-and-go drives, where they hold only the clock offset plus
// the heading delay, leaves the positions at the stamps. Two scanners' scans of one instant are
// then interpolated at the same phase of the GNSS period (to within the difference of their
// offsets' errors), from the same fixes with the same weights, and the joint adjustment can
// share the fixes' white noise between them (solvers/joint_mounts.cc). The headings stay where
// the run put them (at the offset plus the heading delay); the time block's warm start keeps
// what the poses do not carry. `moved` receives the re-interpolated observations when there is
// anything to move (part.observations then points at it).
void AtOwnScanTime(const CalibrationResult& result, solvers::ScannerObservations* part,
                   std::vector<calib::WallObservation>* moved) {
  const solvers::WarmStart* warm = part->warm.get();
  const calib::PoseInterpolator* poses = result.poses.interpolator.get();
  if (poses == nullptr || warm == nullptr || !result.solve.estimate.time_offset_estimated ||
      warm->time_offset_s == 0.0) {
    return;
  }
  const double move_s = warm->time_offset_s;
  *moved = result.solve.observations;
  calib::ShiftObservations(*poses, move_s, -move_s, moved);
  if (moved->empty()) return;  // nothing has a pose there: the run's own poses stay
  auto shifted = std::make_shared<solvers::WarmStart>(*warm);
  shifted->time_offset_s -= move_s;
  shifted->heading_delay_s += move_s;
  part->warm = std::move(shifted);
  part->observations = moved;
}

// The part on the joint adjustment's finer GNSS-error slices (alignment.joint_segment_max_s):
// each observation in its sub-slice of the slice its run solved, the run's bias of that slice
// the warm start of each of its sub-slices. Every scanner's slices stay one time grid: the
// runs read the same GNSS and heading logs, so their poses start at the same instant.
void InJointSlices(const CalibrationResult& result, solvers::ScannerObservations* part,
                   std::vector<calib::WallObservation>* moved) {
  const calib::AlignmentOptions& alignment = result.loaded.options.alignment;
  const int parts = calib::SliceParts(alignment.segment_max_s, alignment.joint_segment_max_s);
  const calib::PoseInterpolator* poses = result.poses.interpolator.get();
  if (poses == nullptr || parts <= 1) return;
  if (part->observations != moved) {
    *moved = *part->observations;
    part->observations = moved;
  }
  calib::RefineGnssSlices(poses->start_s(), alignment.segment_max_s, parts, moved);
  if (part->warm == nullptr) return;
  auto refined = std::make_shared<solvers::WarmStart>(*part->warm);
  refined->biases.clear();
  for (const calib::WallObservation& observation : *moved) {
    const int slice = observation.pose.gnss_segment;
    if (slice < 0) continue;
    const auto found = part->warm->biases.find(slice / parts);
    if (found != part->warm->biases.end()) refined->biases[slice] = found->second;
  }
  part->warm = std::move(refined);
}

}  // namespace

SeveralScannersResult RunSeveralScanners(const CalibrateRequest& request, bool allow_partial,
                                         const ProgressFn& progress) {
  const auto start = std::chrono::steady_clock::now();
  SeveralScannersResult several;
  several.session = io::ReadSession(request.session_path);
  if (several.session.scanners.empty()) {
    throw io::InputError(io::Where(several.session.file, 1,
                                   "no scanners: list; expected scanners: [{id, model, log}, ...]"));
  }
  // The previous calibration is read now: a bad --compare file fails before the work. The
  // scanners' own runs do not read it (it holds every scanner; the joint estimate is compared).
  std::optional<io::PreviousSeveralOffsets> previous;
  if (!request.compare_path.empty()) {
    previous = io::ReadPreviousSeveralOffsets(request.compare_path);
    several.previous_input = {"previous_offsets", request.compare_path,
                              Sha256OfFile(request.compare_path)};
  }
  std::vector<std::string> refused;
  for (size_t s = 0; s < several.session.scanners.size(); ++s) {
    ScannerRun run;
    run.spec = several.session.scanners[s];
    CalibrateRequest one = request;
    one.scanner_index = static_cast<int>(s);
    one.compare_path.clear();
    const std::string prefix = "scanner '" + run.spec.id + "': ";
    ProgressFn named;
    if (progress) {
      named = [&progress, &prefix](const Progress& p) {
        Progress q = p;
        q.text = prefix + p.text;
        progress(q);
      };
    }
    try {
      run.own = CalibrationSession(one, named).Run();
    } catch (const io::InputError& error) {
      throw io::InputError(prefix + error.what());
    }
    // Named only: its reason is the scanner's own (the summary's REFUSED line, offsets.yaml's
    // refused: list), said once.
    if (run.refused()) refused.push_back("'" + run.spec.id + "'");
    several.scanners.push_back(std::move(run));
  }

  std::vector<solvers::ScannerObservations> parts;
  std::vector<size_t> in_joint;  // the scanners of the parts, in order
  // The re-interpolated observations the parts point at (one slot per scanner: never resized).
  std::vector<std::vector<calib::WallObservation>> at_scan_time(several.scanners.size());
  for (size_t s = 0; s < several.scanners.size(); ++s) {
    const ScannerRun& run = several.scanners[s];
    if (run.refused()) continue;
    solvers::ScannerObservations part;
    part.id = run.spec.id;
    part.observations = &run.own.solve.observations;
    part.initial = run.own.solve.estimate.mount;
    part.warm = run.own.solve.estimate.solution_state;
    part.range_scale_sigma = run.own.loaded.preset.range_scale_sigma;
    part.range_offset_sigma_m = run.own.loaded.preset.range_offset_sigma_m;
    AtOwnScanTime(run.own, &part, &at_scan_time[s]);
    InJointSlices(run.own, &part, &at_scan_time[s]);
    parts.push_back(part);
    in_joint.push_back(s);
  }
  std::string refused_text;
  for (size_t i = 0; i < refused.size(); ++i) refused_text += (i > 0 ? ", " : "") + refused[i];
  if (parts.empty() || (!refused.empty() && !allow_partial)) {
    several.outcome = SeveralOutcome::kFailed;
    several.message = "mount not determined for scanner " + refused_text +
                      (parts.empty() ? "" : "; the others are not written without --allow-partial");
    several.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return several;
  }
  if (progress) {
    Progress p;
    p.stage = Stage::kSolving;
    p.text = "joint adjustment of " + std::to_string(parts.size()) + " scanners";
    progress(p);
  }
  const CalibrationResult& first = several.scanners.front().own;
  several.joint = solvers::SolveJointMounts(parts, first.survey.walls, first.SolverInUse());
  if (!several.joint.usable) {
    several.outcome = SeveralOutcome::kFailed;
    several.message = "the joint adjustment failed: " + several.joint.message;
    return several;
  }
  for (size_t k = 0; k < in_joint.size(); ++k) {
    ScannerRun& run = several.scanners[in_joint[k]];
    JointScannerResult joint;
    joint.index = static_cast<int>(k);
    joint.mount = several.joint.mounts[k];
    joint.covariance = several.joint.covariance.block<3, 3>(3 * k, 3 * k);
    joint.range_model_covariance = several.joint.range_model_covariance.block<3, 3>(3 * k, 3 * k);
    joint.unit_range = several.joint.unit_ranges[k];
    joint.time_offset_s = several.joint.time_offset_s[k];
    // Its page shows the joint numbers: its panels and site map are drawn with them too.
    joint.report = ReportAround(run.own, joint.mount, "joint estimate of all scanners");
    run.joint = std::move(joint);
  }
  for (size_t a = 0; a < several.scanners.size(); ++a) {
    for (size_t b = a + 1; b < several.scanners.size(); ++b) {
      const ScannerRun& from = several.scanners[a];
      const ScannerRun& to = several.scanners[b];
      if (!from.joint || !to.joint) continue;
      const int i = 3 * from.joint->index, j = 3 * to.joint->index;
      const auto pair_of = [i, j](const Eigen::MatrixXd& covariance) {
        Eigen::Matrix<double, 6, 6> pair;
        pair.block<3, 3>(0, 0) = covariance.block<3, 3>(i, i);
        pair.block<3, 3>(0, 3) = covariance.block<3, 3>(i, j);
        pair.block<3, 3>(3, 0) = covariance.block<3, 3>(j, i);
        pair.block<3, 3>(3, 3) = covariance.block<3, 3>(j, j);
        return pair;
      };
      RelativeMountResult relative;
      relative.from_id = from.spec.id;
      relative.to_id = to.spec.id;
      relative.mount = solvers::RelativeMountOf(from.joint->mount, to.joint->mount,
                                                pair_of(several.joint.covariance));
      relative.range_model_covariance =
          solvers::RelativeMountOf(from.joint->mount, to.joint->mount,
                                   pair_of(several.joint.range_model_covariance))
              .covariance;
      several.relative.push_back(relative);
    }
  }
  if (previous) {
    const SeveralChanges changes = CompareSeveral(several, *previous);
    for (size_t s = 0; s < several.scanners.size(); ++s) {
      if (several.scanners[s].joint) several.scanners[s].joint->change = changes.scanners[s];
    }
    for (size_t r = 0; r < several.relative.size(); ++r) {
      several.relative[r].change = changes.relative[r];
    }
    several.not_in_previous = changes.not_in_previous;
    several.only_in_previous = changes.only_in_previous;
  }
  // Each scanner's verdict on its joint estimate (σ, change), as its own run decides it.
  for (ScannerRun& run : several.scanners) {
    if (run.joint) run.joint->decision = DecideJointScanner(run.own, *run.joint);
  }
  const AcceptanceOptions& acceptance = first.loaded.options.acceptance;
  for (RelativeMountResult& relative : several.relative) {
    relative.decision =
        DecideRelative(relative.mount, relative.change, acceptance, relative.range_model_covariance);
  }
  several.decision = DecideSeveral(several);
  several.outcome = refused.empty() ? SeveralOutcome::kAll : SeveralOutcome::kPartial;
  if (!refused.empty()) several.message = "left out (--allow-partial): scanner " + refused_text;
  several.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return several;
}

}  // namespace wallcal::pipeline
