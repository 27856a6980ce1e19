// SPDX-License-Identifier: Apache-2.0
#include "calib/detection_pass.h"

#include <algorithm>
#include <cmath>
#include <atomic>
#include <cstddef>
#include <future>
#include <thread>
#include <utility>

#include <Eigen/Geometry>

#include "calib/wall_detector.h"
#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "common/enum_text.h"
#include "io/scanner_geometry.h"

namespace wallcal::calib {

const char* ScanSkipName(ScanSkip reason) {
  static const EnumText<ScanSkip> kTexts[] = {
      {ScanSkip::kNoPoseBeforeLogs, "no pose: before the GNSS/heading logs"},
      {ScanSkip::kNoPoseAfterLogs, "no pose: after the GNSS/heading logs"},
      {ScanSkip::kNoPoseGnssGap, "no pose: in a GNSS gap"},
      {ScanSkip::kNoPoseHeadingGap, "no pose: in a heading gap"},
      {ScanSkip::kVehicleMoving, "vehicle moving"},
      {ScanSkip::kScannerBehindWall, "scanner at or behind the wall"},
      {ScanSkip::kWallNotDetected, "wall not detected"},
      {ScanSkip::kMalformedLine, "malformed scan line"},
      {ScanSkip::kNoPoseAtShiftedTime, "no pose at the clock-offset-corrected time"},
      {ScanSkip::kWallOutsideField, "wall outside the scanner's field of view"}};
  return TextOf(kTexts, reason, "unknown");
}

ScanSkip ScanSkipFor(PoseStatus status) {
  switch (status) {
    case PoseStatus::kBeforeStart:
      return ScanSkip::kNoPoseBeforeLogs;
    case PoseStatus::kAfterEnd:
      return ScanSkip::kNoPoseAfterLogs;
    case PoseStatus::kGnssGap:
      return ScanSkip::kNoPoseGnssGap;
    case PoseStatus::kHeadingGap:
    case PoseStatus::kOk:
      break;
  }
  return ScanSkip::kNoPoseHeadingGap;
}

LineGate GateFor(const WallObservation& at, const WallGeometry& wall, const Mount& mount,
                 const Gates& gates) {
  LineGate gate;
  gate.theta_rad = PredictTheta(at, wall, mount);
  gate.theta_halfwidth_rad = gates.angle_rad;
  gate.rho_m = PredictRho(at, wall, mount);
  gate.rho_halfwidth_m = gates.offset_m;
  if (gates.use_segment) {
    // The surveyed wall's ends seen from the scanner (current mount estimate).
    const VehiclePose& pose = at.pose;
    const double scanner_yaw = pose.yaw_rad + mount.yaw_rad;
    const Eigen::Rotation2Dd vehicle_R(pose.yaw_rad);
    const Eigen::Vector2d scanner_local =
        pose.antenna_local_m + vehicle_R * Eigen::Vector2d(mount.x_m, mount.y_m);
    const Eigen::Rotation2Dd scanner_R_local(-scanner_yaw);
    gate.has_segment = true;
    gate.segment_a_scanner = scanner_R_local * (wall.end_a_local - scanner_local);
    gate.segment_b_scanner = scanner_R_local * (wall.end_b_local - scanner_local);
  }
  return gate;
}

namespace {

// The scans' time span and order, over every scan (sampled or not).
void TrackStamp(double t, int64_t index, int line, PassOutcome* outcome) {
  if (index == 0) {
    outcome->first_stamp_s = outcome->last_stamp_s = t;
    return;
  }
  if (!(t > outcome->last_stamp_s) && outcome->not_increasing++ == 0) {
    outcome->first_not_increasing_line = line;
  }
  outcome->first_stamp_s = std::min(outcome->first_stamp_s, t);
  outcome->last_stamp_s = std::max(outcome->last_stamp_s, t);
}

// Whether some part of the wall's surveyed extent (its ends in the scanner frame, as `gate`
// holds them) lies within the bearings of the preset's beams. The segment subtends the shorter
// arc between its ends' bearings (the scanner is in front of it).
bool WallInField(const LineGate& gate, const io::ScannerPreset& preset) {
  const double first_rad = preset.start_angle_rad;
  const double last_rad = first_rad + (preset.num_beams - 1) * preset.angular_step_rad;
  const double field_half_rad = 0.5 * std::abs(last_rad - first_rad);
  const double a_rad = std::atan2(gate.segment_a_scanner.y(), gate.segment_a_scanner.x());
  const double b_rad = std::atan2(gate.segment_b_scanner.y(), gate.segment_b_scanner.x());
  const double span_rad = WrapAngle(b_rad - a_rad);
  const double middle_rad = a_rad + 0.5 * span_rad;
  const double apart_rad = std::abs(WrapAngle(0.5 * (first_rad + last_rad) - middle_rad));
  return apart_rad <= field_half_rad + 0.5 * std::abs(span_rad);
}

// One scan waiting for detection, and what its detection gave.
struct PendingScan {
  io::ScanRecord scan;
  int index = 0;
  VehiclePose pose;
  std::vector<WallObservation> observations;
  RangeCounts range_counts;
  ScanSkip why = ScanSkip::kWallNotDetected;
};

// Scans detected together: enough to keep the threads busy, few enough to bound memory. Each
// batch starts its detection threads and the reader of the next one: at 1024 scans (0.7 MB of
// LMS 291 ranges) an hour's log starts 300 of each instead of 1 200, which was a fifth of the
// run's system time.
constexpr size_t kBatchScans = 1024;

// The walls in one scan: an observation per wall found in scan->observations; scan->why says
// why when there is none.
void DetectInScan(const PassContext& context, const PassRequest& request, PendingScan* pending) {
  calib::DetectorOptions detector = *context.detector;
  if (request.gates.min_inliers > 0) detector.min_inliers = request.gates.min_inliers;
  const VehiclePose& pose = pending->pose;
  ScanSkip* why = &pending->why;
  thread_local ScanPoints points;  // reused: no allocation per scan once warm
  FillScanPoints(pending->scan, *context.preset, detector.min_range_m,
                 detector.mixed_pixel_jump_m, &pending->range_counts, &points);
  *why = ScanSkip::kWallNotDetected;
  size_t walls_outside_field = 0;
  for (size_t w = 0; w < context.walls->size(); ++w) {
    const WallGeometry& wall = (*context.walls)[w];
    WallObservation observation;
    observation.scan_index = pending->index;
    observation.wall_index = static_cast<int>(w);
    observation.pose = pose;
    // The gates are predicted at the scan's true time (the clock offset of the first pass
    // moves a moving vehicle's pose); the observation keeps the pose at the stamp.
    WallObservation gate_at = observation;
    gate_at.pose.antenna_local_m += request.gate_time_offset_s * pose.velocity_local_mps;
    gate_at.pose.yaw_rad += request.gate_time_offset_s * pose.yaw_rate_rps;
    const LineGate gate = GateFor(gate_at, wall, request.mount, request.gates);
    if (gate.rho_m + request.gates.offset_m <= detector.min_range_m) {
      *why = ScanSkip::kScannerBehindWall;
      continue;
    }
    const WallDetection detection =
        DetectWall(points, gate, detector, context.preset->range_sigma_m);
    if (!detection.found) {
      *why = ScanSkip::kWallNotDetected;
      Gates extent = request.gates;
      extent.use_segment = true;
      if (!WallInField(GateFor(gate_at, wall, request.mount, extent), *context.preset)) {
        ++walls_outside_field;
      }
      continue;
    }
    observation.rho_m = detection.rho_m;
    observation.theta_rad = detection.theta_rad;
    observation.sigma_rho_m = detection.sigma_rho_m;
    observation.sigma_theta_rad = detection.sigma_theta_rad;
    observation.cov_rho_theta = detection.cov_rho_theta;
    observation.num_inliers = detection.num_inliers;
    observation.range_min_m = detection.range_min_m;
    observation.drho_drange_offset = static_cast<float>(detection.range_offset_gain.x());
    observation.dtheta_drange_offset_per_m = static_cast<float>(detection.range_offset_gain.y());
    observation.range_max_m = detection.range_max_m;
    observation.residual_rms_m = detection.residual_rms_m;
    pending->observations.push_back(observation);
  }
  if (walls_outside_field > 0 && walls_outside_field == context.walls->size()) {
    *why = ScanSkip::kWallOutsideField;
  }
}

// Detects a batch over `threads` threads, then appends the results to the outcome in scan
// order. The threads take the next few scans as they get free (the reader's thread shares the
// cores: fixed slices would leave one thread waiting for the slice the reader held up).
void DetectBatch(const PassContext& context, const PassRequest& request,
                 std::vector<PendingScan>* batch, PassOutcome* outcome) {
  const size_t n = batch->size();
  const size_t threads = std::min<size_t>(std::max(1, context.threads), n);
  if (threads <= 1) {
    for (PendingScan& pending : *batch) DetectInScan(context, request, &pending);
  } else {
    constexpr size_t kScansPerTake = 8;
    std::atomic<size_t> next{0};
    auto work = [&]() {
      for (size_t first = next.fetch_add(kScansPerTake); first < n;
           first = next.fetch_add(kScansPerTake)) {
        for (size_t i = first; i < std::min(n, first + kScansPerTake); ++i) {
          DetectInScan(context, request, &(*batch)[i]);
        }
      }
    };
    std::vector<std::thread> workers;
    for (size_t t = 1; t < threads; ++t) workers.emplace_back(work);
    work();
    for (std::thread& worker : workers) worker.join();
  }
  for (PendingScan& pending : *batch) {
    outcome->range_counts += pending.range_counts;
    if (pending.observations.empty()) {
      ++outcome->skipped[pending.why];
    } else {
      outcome->observations.insert(outcome->observations.end(), pending.observations.begin(),
                                   pending.observations.end());
    }
  }
  batch->clear();
}

}  // namespace

namespace {

// What reading a batch found besides its scans (the reader's own counts, merged at the end).
struct ReadBatch {
  std::vector<PendingScan> scans;
  bool at_end = false;
};

// Reads scans in file order until kBatchScans wait for detection or the source ends. With
// request.min_interval_s > 0 only the stamps of the scans passed over are read (skimming,
// io/scan_source.h). Counts into *reading (stamps, skips before detection).
class BatchReader {
 public:
  BatchReader(const PassContext& context, const PassRequest& request, io::ScanSource* scans,
              PassOutcome* reading)
      : context_(context), request_(request), scans_(scans), reading_(reading) {}

  // Skimming: the scans read, those parsed whole and found sound plus those whose stamp alone
  // was read. A log whose every scan line is malformed gets each of them parsed (none becomes
  // the examined scan the interval counts from), so it reads no scan.
  int64_t skimmed_scans() const { return parsed_ + stamps_only_; }

  ReadBatch Read() {
    ReadBatch batch;
    batch.scans.reserve(kBatchScans);
    const bool skim = request_.min_interval_s > 0.0;
    io::ScanRecord scan;
    while (batch.scans.size() < kBatchScans) {
      double raw_stamp_s = 0.0;
      int line = 0;
      if (skim) {
        if (!scans_->NextStamp(&raw_stamp_s, &line)) {
          batch.at_end = true;
          break;
        }
      } else {
        if (!scans_->Next(&scan)) {
          batch.at_end = true;
          break;
        }
        raw_stamp_s = scan.stamp_s;
        line = scan.line;
      }
      ++scan_index_;
      const double stamp_s = raw_stamp_s + context_.scanner_time_offset_s;
      TrackStamp(stamp_s, scan_index_, line, reading_);
      if (request_.progress && scan_index_ % 2000 == 0) request_.progress(scan_index_);
      if (skim) {
        if (stamp_s - last_examined_s_ < request_.min_interval_s) {
          ++stamps_only_;
          continue;
        }
        if (!scans_->ParseCurrent(&scan)) continue;  // malformed: counted by the source
        ++parsed_;
        last_examined_s_ = stamp_s;
      }
      ++reading_->scans_examined;
      if (request_.tally != nullptr && !skim) Tally(scan, stamp_s);
      if (!io::BeamCountFits(static_cast<int64_t>(scan.ranges_m.size()), *context_.preset) &&
          reading_->beam_count_mismatch++ == 0) {
        reading_->first_mismatch_beams = static_cast<int>(scan.ranges_m.size());
      }
      VehiclePose pose;
      const PoseStatus status = context_.poses->At(stamp_s, &pose);
      if (status != PoseStatus::kOk) {
        ++reading_->skipped[ScanSkipFor(status)];
        TallyReadings(scan);
        continue;
      }
      if (!pose.stationary && !context_.use_moving) {
        ++reading_->skipped[ScanSkip::kVehicleMoving];
        TallyReadings(scan);
        continue;
      }
      PendingScan pending;
      pending.scan = std::move(scan);
      pending.index = static_cast<int>(scan_index_);
      pending.pose = pose;
      batch.scans.push_back(std::move(pending));
    }
    return batch;
  }

 private:
  const PassContext& context_;
  const PassRequest& request_;
  io::ScanSource* scans_;
  PassOutcome* reading_;
  // The tally (request.tally) of a scan read; a scan that goes to detection has its readings
  // counted there (DetectInScan) and added at the end of the pass.
  void Tally(const io::ScanRecord& scan, double stamp_s) {
    ScanLogTally& tally = *request_.tally;
    if (tally.stamps_s.empty()) {
      tally.first_start_rad = scan.start_angle_rad;
      tally.first_step_rad = scan.angular_step_rad;
      tally.first_max_range_m = scan.max_range_m;
    }
    tally.stamps_s.push_back(stamp_s);
    tally.lines.push_back(scan.line);
    ++tally.beams[scan.ranges_m.size()];
  }
  void TallyReadings(const io::ScanRecord& scan) {
    if (request_.tally == nullptr || request_.min_interval_s > 0.0) return;
    const calib::DetectorOptions& detector = *context_.detector;
    CountReadings(scan, *context_.preset, detector.min_range_m, &request_.tally->readings);
  }
  int64_t scan_index_ = -1;
  double last_examined_s_ = -1e300;
  int64_t parsed_ = 0;
  int64_t stamps_only_ = 0;
};

}  // namespace

PassOutcome DetectionPass(const PassContext& context, const PassRequest& request) {
  PassOutcome reading;  // the reader's part: stamps, examined scans, skips before detection
  PassOutcome outcome;  // detection's part: observations, detection skips, range counts
  const std::unique_ptr<io::ScanSource> scans = context.open_scans();
  BatchReader reader(context, request, scans.get(), &reading);
  if (context.threads <= 1) {
    for (bool more = true; more;) {
      ReadBatch batch = reader.Read();
      more = !batch.at_end;
      if (!batch.scans.empty()) DetectBatch(context, request, &batch.scans, &outcome);
    }
  } else {
    // Reading (parsing) the next batch overlaps the detection of this one: one reader at a
    // time, so the reader's state needs no lock; batches are detected in file order.
    std::future<ReadBatch> next = std::async(std::launch::async, [&reader]() { return reader.Read(); });
    for (bool more = true; more;) {
      ReadBatch batch = next.get();
      more = !batch.at_end;
      if (more) next = std::async(std::launch::async, [&reader]() { return reader.Read(); });
      if (!batch.scans.empty()) DetectBatch(context, request, &batch.scans, &outcome);
    }
  }
  // The reader's counts, with detection's observations, skips and range counts added.
  reading.observations = std::move(outcome.observations);
  reading.range_counts = outcome.range_counts;
  for (const auto& [reason, count] : outcome.skipped) reading.skipped[reason] += count;
  reading.scans_read = request.min_interval_s > 0.0 ? reader.skimmed_scans()
                                                    : scans->scans_read();
  reading.line_skips = scans->skipped();
  if (request.tally != nullptr && request.min_interval_s <= 0.0) {
    request.tally->readings += outcome.range_counts;  // the detected scans' readings
  }
  return reading;
}

int ShiftObservations(const PoseInterpolator& poses, double dt_s, double heading_shift_s,
                      std::vector<WallObservation>* observations) {
  // Compacted in place: a copy of an hour's observations would add to the run's peak memory.
  std::vector<WallObservation>& all = *observations;
  size_t kept = 0;
  for (size_t i = 0; i < all.size(); ++i) {
    WallObservation& o = all[i];
    VehiclePose pose;
    if (poses.At(o.pose.stamp_s + dt_s, o.pose.heading_shift_s + heading_shift_s, &pose) !=
        PoseStatus::kOk) {
      continue;
    }
    pose.clock_shift_s = o.pose.clock_shift_s + dt_s;
    o.pose = pose;
    if (kept != i) all[kept] = std::move(o);
    ++kept;
  }
  const int dropped = static_cast<int>(all.size() - kept);
  all.erase(all.begin() + static_cast<std::ptrdiff_t>(kept), all.end());
  return dropped;
}

}  // namespace wallcal::calib
