// SPDX-License-Identifier: Apache-2.0
#include "guide/guide_session.h"

#include <algorithm>
#include <iterator>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "analysis/repeatability.h"
#include "calib/detection_pass.h"
#include "guide/scan_feed.h"
#include "pipeline/steps.h"

namespace wallcal::guide {
namespace {

// A scan this close to the end of the pose logs (s) is read again at the next refresh: its pose
// (the velocity window around it, a dwell that may yet begin there) can still change.
constexpr double kSettleS = 5.0;

}  // namespace

struct GuideSession::State {
  bool loaded = false;
  std::unique_ptr<ScanFeed> scans;  // null: the scan log is read whole at each refresh
  pipeline::CalibrationResult result;  // session, options, preset, walls, first pass
  pipeline::RunInputs inputs;
  pipeline::CalibrateRequest request;
  bool passes_prepared = false;
  bool first_pass_done = false;
  // The scans read and settled: their observations (poses as last given), how many scans come
  // before the first not settled.
  std::vector<calib::WallObservation> detected;
  int64_t scans_before = 0;
  bool solved_once = false;
  std::optional<PoseLogFollower> pose_logs;  // read on from where the last refresh stopped
  // The pose logs' end and their dwells at the last refresh (for Repose).
  double poses_end_s = -1e300;
  std::vector<calib::Dwell> dwells;
  // The options' solver before the measured white noise replaces theirs (at each refresh).
  solvers::SolverOptions configured_solver;
};

namespace {

// Gives the kept observations the poses of the grown logs. Only the last seconds change: the
// dwell in progress grew (its mean pose moves), a run of standing that was too short became a
// dwell, and a scan's velocity window gained samples; the observations from there on are
// interpolated anew. Before it only a moving scan's segment changes, by the dwells added
// (segment = dwells + the scan's 5 s slot, calib/time_alignment.h).
void Repose(const calib::PoseInterpolator& poses, const calib::AlignmentOptions& alignment,
            std::vector<calib::WallObservation>* observations, double* poses_end_s,
            std::vector<calib::Dwell>* dwells) {
  std::vector<calib::WallObservation>& detected = *observations;
  double from_s = *poses_end_s - kSettleS;
  if (!dwells->empty()) from_s = std::min(from_s, dwells->back().start_s);
  from_s -= alignment.min_dwell_s + alignment.stationary_window_s + 2.0 * alignment.dwell_guard_s;
  size_t tail = detected.size();
  while (tail > 0 && detected[tail - 1].pose.stamp_s >= from_s) --tail;
  const int added = static_cast<int>(poses.dwells().size()) - static_cast<int>(dwells->size());
  if (added != 0) {
    for (size_t i = 0; i < tail; ++i) {
      if (!detected[i].pose.stationary) detected[i].pose.segment += added;
    }
  }
  std::vector<calib::WallObservation> moved(detected.begin() + static_cast<long>(tail),
                                            detected.end());
  calib::ShiftObservations(poses, 0.0, 0.0, &moved);
  detected.resize(tail);
  detected.insert(detected.end(), moved.begin(), moved.end());
  *poses_end_s = poses.end_s();
  *dwells = poses.dwells();
}

}  // namespace

GuideSession::GuideSession(GuideOptions options)
    : options_(std::move(options)), state_(std::make_unique<State>()) {
  options_.Validate();
}

GuideSession::~GuideSession() = default;

GuideReport GuideSession::Refresh() {
  State& s = *state_;
  pipeline::CalibrateRequest& request = s.request;
  if (!s.loaded) {
    request.session_path = options_.session_path;
    request.scanner_id = options_.scanner_id;
    request.config_path = options_.config_path;
    request.preview = true;
    request.force = true;  // the σ along a weak direction, not a refusal
    request.threads = options_.threads;
    pipeline::Setup setup = pipeline::LoadSessionAndOptions(request);
    s.result.session = std::move(setup.session);
    s.result.options = std::move(setup.options);
    s.result.preset = std::move(setup.preset);
    s.configured_solver = s.result.options.solver;
    s.scans = ScanFeed::For(s.result.session, &s.result.preset);
    s.pose_logs.emplace(s.result.session);
    if (s.scans) {
      pipeline::SurveyStep survey =
          pipeline::TieSurveyAndFitWalls(s.result.session, s.result.options.solver);
      s.result.frame = survey.frame;
      s.result.walls = std::move(survey.walls);
      s.inputs.survey = std::move(survey.survey);
      s.inputs.tie = std::move(survey.tie);
    }
    s.loaded = true;
  }
  last_read_ = ReadCounts{};
  if (!s.scans) {
    return ReportOn(pipeline::RunCalibration(request), options_.max_next);
  }
  pipeline::CalibrationResult& result = s.result;
  pipeline::RunInputs& inputs = s.inputs;
  {
    pipeline::PoseStep poses = pipeline::PosesFromLogs(result, s.pose_logs->Read());
    last_read_.gnss_log = s.pose_logs->gnss_read();
    last_read_.heading_log = s.pose_logs->heading_read();
    last_read_.fixes_used = poses.fixes_used;
    last_read_.headings_used = poses.headings_used;
    result.num_dwells = poses.num_dwells;
    // The white noise measured at the stops so far, as calibrate takes it.
    pipeline::UseMeasuredWhiteNoise(poses, s.configured_solver, &result);
    inputs.gnss = std::move(poses.gnss);
    inputs.headings = std::move(poses.headings);
    inputs.used_fixes = std::move(poses.used_fixes);
    inputs.poses = std::move(poses.poses);
  }
  if (!s.passes_prepared) {
    pipeline::PassSetup passes = pipeline::PreparePasses(request, result, *inputs.poses);
    inputs.pass = std::move(passes.pass);
    inputs.moving_by_default = passes.moving_by_default;
    s.passes_prepared = true;
    // The opener's copy of a recording's scans (the preset check's) is let go before the feed
    // decodes its own: the passes read through the feed.
    inputs.pass.open_scans = nullptr;
  }
  inputs.pass.poses = inputs.poses.get();
  {
    // As a fresh read would choose for the dwells found so far. The scans read before keep the
    // detections they got: a drive's scans detected while the passes used them stay.
    const pipeline::MovingScans moving =
        pipeline::ChooseMovingScans(result.options, result.num_dwells);
    inputs.pass.use_moving = moving.use_moving;
    inputs.moving_by_default = moving.moving_by_default;
  }
  const FeedRead feed = s.scans->Update();
  last_read_.scan_log_bytes = feed.log_bytes;
  if (feed.restarted) {
    // A log shorter than what was read (a new recording under the same name): from the start.
    s.first_pass_done = false;
    s.solved_once = false;
    s.detected.clear();
    s.scans_before = 0;
    s.poses_end_s = -1e300;
    s.dwells.clear();
  }
  ScanFeed* scans = s.scans.get();

  if (!s.first_pass_done) {
    // The first pass (a subsample, wide gates) over the whole log, until it gives a start.
    inputs.pass.open_scans = [scans]() { return scans->OpenAll(); };
    const pipeline::FirstPassStep first = pipeline::FirstPass(request, {}, result, inputs);
    result.first_pass = first.estimate;
    if (first.stopped) {
      result.estimate = first.estimate;
      result.observations.clear();
      return ReportOn(result, options_.max_next);
    }
    s.first_pass_done = true;
  }

  // The second pass's detection on what the log gained since the last read.
  std::vector<ScanMark> marks;
  inputs.pass.open_scans = [scans, &marks]() { return scans->OpenUnsettled(&marks); };
  calib::PassRequest pass;
  pass.mount = result.first_pass.mount;
  pass.gates = pipeline::TightGates(result);
  pass.gate_time_offset_s =
      result.first_pass.time_offset_estimated ? result.first_pass.time_offset_s : 0.0;
  calib::PassOutcome fresh = calib::DetectionPass(inputs.pass, pass);
  last_read_.incremental = feed.from_byte > 0;
  last_read_.scan_log_from_byte = feed.from_byte;
  last_read_.scans_detected = static_cast<int64_t>(marks.size());
  last_read_.scans_kept = s.scans_before;

  Repose(*inputs.poses, result.options.alignment, &s.detected, &s.poses_end_s, &s.dwells);
  // Settled: the scans up to kSettleS before the pose logs end, and never the last one read
  // (the next read starts at its line, so that a line cut off after it is read whole then).
  const double settle_s = inputs.poses->end_s() - kSettleS;
  size_t settled = 0;
  while (settled + 1 < marks.size() &&
         marks[settled].stamp_s + result.session.scanner_time_offset_s <= settle_s) {
    ++settled;
  }
  // The settled scans' observations join the kept ones for good, the others for this refresh.
  // (The pass returns its observations in file order: the settled ones come first.)
  std::vector<calib::WallObservation>& all = s.detected;
  size_t kept = all.size();
  for (calib::WallObservation& o : fresh.observations) {
    if (static_cast<size_t>(o.scan_index) < settled) ++kept;
    o.scan_index += static_cast<int>(s.scans_before);
    all.push_back(std::move(o));
  }
  if (!marks.empty()) {
    scans->Settle(marks, settled);
    s.scans_before += static_cast<int64_t>(settled);
  }

  // The preview's solve, as pipeline::RunCalibration makes it: on every k-th observation
  // weighted by k, then every detection back for the report. It starts from the last refresh's
  // estimate (the first time: the first pass's).
  inputs.observation_weight = 1.0;
  analysis::ThinnedObservations thin = analysis::ThinForRefits(all);
  const bool thinned = thin.stride != 1.0;
  std::vector<calib::WallObservation> solve_on;
  if (thinned) {
    inputs.observation_weight = thin.stride;
    solve_on = std::move(thin.observations);
  } else {
    solve_on = all;
  }
  const calib::Mount first_pass_mount = result.first_pass.mount;
  if (s.solved_once && result.estimate.usable) result.first_pass.mount = result.estimate.mount;
  pipeline::SolveStep solved = pipeline::Solve(request, {}, result, inputs, std::move(solve_on));
  result.first_pass.mount = first_pass_mount;
  s.solved_once = true;
  result.forced = solved.forced;
  pipeline::FinishedEstimate finished =
      pipeline::FinishEstimate(request, result, std::move(solved.estimate));
  result.estimate = std::move(finished.estimate);
  result.forced = result.forced || finished.forced;
  GuideReport report;
  if (!thinned) {
    result.observations = std::move(solved.observations);
    report = ReportOn(result, options_.max_next);
  } else if (solved.drives_dropped > 0) {
    // The drives are left out of the report as the solve left them out.
    result.observations.clear();
    std::copy_if(all.begin(), all.end(), std::back_inserter(result.observations),
                 [](const calib::WallObservation& o) { return o.pose.stationary; });
    report = ReportOn(result, options_.max_next);
  } else {
    result.observations.swap(all);  // lent to the report, not copied
    report = ReportOn(result, options_.max_next);
    result.observations.swap(all);
  }
  result.observations.clear();
  all.resize(kept);  // the scans not settled are read again next time
  return report;
}

}  // namespace wallcal::guide
