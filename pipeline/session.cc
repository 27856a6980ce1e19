// SPDX-License-Identifier: Apache-2.0
#include "pipeline/session.h"

#include <cassert>
#include <chrono>
#include <utility>

#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {

CalibrationSession::CalibrationSession(CalibrateRequest request, ProgressFn progress)
    : request_(std::move(request)),
      progress_(std::move(progress)),
      state_(std::make_unique<RunState>()) {}

CalibrationSession::~CalibrationSession() = default;

CalibrationResult CalibrationSession::Run() {
  const auto start = std::chrono::steady_clock::now();
  Load();
  Survey();
  Poses();
  Site();
  Detect();
  Solve();
  Finish();
  ProbeMirroredSurvey();
  Decide();
  if (request_.collect_report_data) CollectReport();
  Say(progress_, Stage::kDone, "done");
  result_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return std::move(result_);
}

const LoadResult& CalibrationSession::Load() {
  result_.loaded = pipeline::Load(request_, state_.get());
  if (!request_.preview) StartDigests(request_, result_.loaded, state_.get());
  return result_.loaded;
}

const SurveyResult& CalibrationSession::Survey() {
  result_.survey = TieSurveyAndFitWalls(result_.loaded.session, result_.loaded.options.solver);
  return result_.survey;
}

const PoseResult& CalibrationSession::Poses() {
  // Text logs or recording topics (one pass when GNSS and heading share a recording).
  return Poses(recording::ReadPoseLogs(result_.loaded.session));
}

const PoseResult& CalibrationSession::Poses(recording::PoseLogs logs) {
  assert(!result_.survey.walls.empty());
  result_.poses = PosesFromLogs(result_, std::move(logs), state_.get());
  // The passes already set up follow the new poses (the guide's refreshes).
  state_->pass.poses = result_.poses.interpolator.get();
  return result_.poses;
}

const SiteResult& CalibrationSession::Site() {
  assert(result_.poses.interpolator != nullptr);
  result_.site = SiteFromPoses(result_, *state_);
  return result_.site;
}

const DetectionResult& CalibrationSession::Detect() {
  ReadScansFrom(nullptr);
  if (FirstPass().stopped) return result_.detection;
  SecondPassStep second = SecondPass(request_, progress_, result_, state_.get());
  DetectionResult& detection = result_.detection;
  detection.scans_skipped = std::move(second.scans_skipped);
  detection.scan_lines_skipped = std::move(second.scan_lines_skipped);
  detection.scans_total = second.scans_total;
  detection.scan_log = std::move(second.scan_log);
  Append(&detection.warnings, std::move(second.warnings));
  return detection;
}

void CalibrationSession::ReadScansFrom(ScanOpener open) {
  assert(result_.poses.interpolator != nullptr);
  DetectionResult& detection = result_.detection;
  if (!state_->passes_prepared) {
    PassSetup setup = PreparePasses(request_, result_, state_.get());
    detection.scanner_from_data = std::move(setup.scanner_from_data);
    detection.moving_by_default = setup.moving_by_default;
    Append(&detection.warnings, std::move(setup.warnings));
    state_->passes_prepared = true;
  } else {
    // As a fresh read would choose for the dwells found so far (the scans read before keep
    // their detections).
    const MovingScans moving = ChooseMovingScans(result_.loaded.options, result_.poses.num_dwells);
    state_->pass.use_moving = moving.use_moving;
    detection.moving_by_default = moving.moving_by_default;
  }
  if (open) state_->pass.open_scans = std::move(open);
}

const DetectionResult& CalibrationSession::FirstPass() {
  assert(state_->passes_prepared);
  const FirstPassStep first = pipeline::FirstPass(request_, progress_, result_, *state_);
  DetectionResult& detection = result_.detection;
  detection.first_pass = first.estimate;
  detection.stopped = first.stopped;
  detection.scans_in_log = first.scans_in_log;
  if (first.stopped) detection.scans_total = first.scans_total;
  return detection;
}

calib::PassOutcome CalibrationSession::DetectWithTightGates(ScanOpener open) {
  assert(state_->passes_prepared && !result_.detection.stopped);
  calib::PassContext pass = state_->pass;
  pass.open_scans = std::move(open);
  return calib::DetectionPass(pass, TightPass(result_));
}

const SolveResult& CalibrationSession::Solve() {
  // The detections are the solve's from here on: they are not kept twice.
  std::vector<calib::WallObservation> detections = std::move(state_->detections);
  state_->detections.clear();
  return Solve(std::move(detections), std::nullopt);
}

const SolveResult& CalibrationSession::Solve(std::vector<calib::WallObservation> observations,
                                             const std::optional<calib::Mount>& start) {
  result_.solve = pipeline::Solve(request_, progress_, result_, std::move(observations),
                                  start.value_or(result_.detection.first_pass.mount));
  return result_.solve;
}

const FinishResult& CalibrationSession::Finish() {
  result_.finish = pipeline::Finish(request_, progress_, result_);
  return result_.finish;
}

void CalibrationSession::ProbeMirroredSurvey() {
  pipeline::ProbeMirroredSurvey(request_, result_, *state_);
}

const DecideResult& CalibrationSession::Decide() {
  result_.decided = pipeline::Decide(request_, result_, *state_);
  return result_.decided;
}

void CalibrationSession::CollectReport() {
  Say(progress_, Stage::kReportData, "collecting the report's scans and site map");
  result_.report = CollectReportData(result_, *state_);
}

}  // namespace wallcal::pipeline
