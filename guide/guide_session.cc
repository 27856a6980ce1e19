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
#include "pipeline/session.h"

namespace wallcal::guide {
namespace {

// A scan this close to the end of the pose logs (s) is read again at the next refresh: its pose
// (the velocity window around it, a dwell that may yet begin there) can still change.
constexpr double kSettleS = 5.0;

}  // namespace

struct GuideSession::State {
  // The calibration run on the logs as they are: loaded and surveyed once, then at each refresh
  // the poses, the detection of what the scan log gained and a preview solve.
  std::unique_ptr<pipeline::CalibrationSession> run;
  std::unique_ptr<ScanFeed> scans;
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

namespace {

pipeline::CalibrateRequest PreviewRequest(const GuideOptions& options) {
  pipeline::CalibrateRequest request;
  request.session_path = options.session_path;
  request.scanner_id = options.scanner_id;
  request.config_path = options.config_path;
  request.preview = true;
  request.force = true;  // the σ along a weak direction, not a refusal
  request.threads = options.threads;
  return request;
}

}  // namespace

GuideReport GuideSession::Refresh() {
  State& s = *state_;
  if (s.run == nullptr) {
    s.run = std::make_unique<pipeline::CalibrationSession>(PreviewRequest(options_));
    const pipeline::LoadResult& loaded = s.run->Load();
    s.scans = ScanFeed::For(loaded.session, &loaded.preset);
    s.pose_logs.emplace(loaded.session);
    s.run->Survey();
  }
  last_read_ = ReadCounts{};
  pipeline::CalibrationSession& run = *s.run;
  {
    const pipeline::PoseResult& poses = run.Poses(s.pose_logs->Read());
    last_read_.gnss_log = s.pose_logs->gnss_read();
    last_read_.heading_log = s.pose_logs->heading_read();
    last_read_.fixes_used = poses.fixes_used;
    last_read_.headings_used = poses.headings_used;
    run.Site();  // the yard and attitude as the logs hold them now
  }
  ScanFeed* scans = s.scans.get();
  // The first time, the preset is checked against the scan log before the feed decodes its
  // scans; from then on the passes read through the feed.
  run.ReadScansFrom([scans]() { return scans->OpenAll(); });
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

  if (!s.first_pass_done) {
    // The first pass (a subsample, wide gates) over the whole log, until it gives a start.
    if (run.FirstPass().stopped) {
      run.Solve({}, std::nullopt);  // the first pass's refusal
      return ReportOn(run.result(), options_.max_next);
    }
    s.first_pass_done = true;
  }

  // The second pass's detection on what the log gained since the last read.
  std::vector<ScanMark> marks;
  calib::PassOutcome fresh =
      run.DetectWithTightGates([scans, &marks]() { return scans->OpenUnsettled(&marks); });
  last_read_.incremental = feed.from_byte > 0;
  last_read_.scan_log_from_byte = feed.from_byte;
  last_read_.scans_detected = static_cast<int64_t>(marks.size());
  last_read_.scans_kept = s.scans_before;

  const calib::PoseInterpolator& poses = *run.result().poses.interpolator;
  const pipeline::LoadResult& loaded = run.result().loaded;
  Repose(poses, loaded.options.alignment, &s.detected, &s.poses_end_s, &s.dwells);
  // Settled: the scans up to kSettleS before the pose logs end, and never the last one read
  // (the next read starts at its line, so that a line cut off after it is read whole then).
  const double settle_s = poses.end_s() - kSettleS;
  size_t settled = 0;
  while (settled + 1 < marks.size() &&
         marks[settled].stamp_s + loaded.session.scanner_time_offset_s <= settle_s) {
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

  // The preview's solve, as calibrate's preview makes it (on every k-th observation weighted
  // by k, every detection back for the report), started from the last refresh's estimate (the
  // first time: the first pass's).
  std::optional<calib::Mount> start;
  const solvers::MountEstimate& last = run.result().solve.estimate;
  if (s.solved_once && last.usable) start = last.mount;
  run.Solve(all, start);
  s.solved_once = true;
  GuideReport report = ReportOn(run.result(), options_.max_next);
  all.resize(kept);  // the scans not settled are read again next time
  return report;
}

}  // namespace wallcal::guide
