// SPDX-License-Identifier: Apache-2.0
#include "guide/pose_logs.h"

#include <utility>

#include "recording/attitude_stream.h"
#include "recording/recording.h"

namespace wallcal::guide {
namespace {

// Reads on from where `follower` stopped (made for `path` on first use).
io::NmeaLog ReadOn(const std::string& path, std::optional<io::NmeaFollower>* follower,
                   PoseLogRead* read) {
  if (!*follower) follower->emplace(path);
  read->from_byte = (*follower)->ReadMore();
  read->bytes = (*follower)->bytes_read();
  return (*follower)->Log();
}

PoseLogRead ReadOf(const recording::TailRead& tail) {
  return PoseLogRead{static_cast<int64_t>(tail.from_byte), static_cast<int64_t>(tail.file_bytes)};
}

}  // namespace

PoseLogFollower::PoseLogFollower(io::SessionSpec session) : session_(std::move(session)) {}

recording::PoseLogs PoseLogFollower::Read() {
  const io::SessionSpec& spec = session_;
  // Told apart by content at each refresh, as ReadPoseLogs does: a log that did not exist yet
  // may turn out to be a recording.
  const bool gnss_recorded = recording::IsRecording(spec.gnss_log);
  const bool heading_recorded = recording::IsRecording(spec.heading_log);
  const bool attitude_named = !spec.attitude_log.empty();
  const bool attitude_recorded = attitude_named && recording::IsRecording(spec.attitude_log);
  recording::PoseLogs logs;
  gnss_read_ = PoseLogRead{};
  heading_read_ = PoseLogRead{};
  attitude_read_ = PoseLogRead{};
  if (!gnss_recorded && !heading_recorded) {
    recorded_.reset();
  } else {
    if (!recorded_ || gnss_recorded != gnss_recorded_ || heading_recorded != heading_recorded_) {
      recorded_ = std::make_unique<recording::PoseTail>(spec, gnss_recorded, heading_recorded);
      gnss_recorded_ = gnss_recorded;
      heading_recorded_ = heading_recorded;
    }
    logs = recorded_->ReadOn();
    if (gnss_recorded) gnss_read_ = ReadOf(recorded_->gnss_read());
    if (heading_recorded) heading_read_ = ReadOf(recorded_->heading_read());
  }
  if (attitude_recorded) {
    // PoseTail reads no attitude topic: the recording's attitude stream is read whole.
    logs.attitudes = recording::ReadPoseLogs(spec, false, false, true).attitudes;
  }
  if (gnss_recorded) {
    gnss_.reset();
  } else {
    recording::RequireNoTopic(spec.gnss_topic, spec.gnss_log, "gnss.topic");
    logs.gnss = ReadOn(spec.gnss_log, &gnss_, &gnss_read_);
  }
  if (heading_recorded) {
    heading_.reset();
  } else {
    recording::RequireNoTopic(spec.heading_topic, spec.heading_log, "heading.topic");
    if (!gnss_recorded && spec.heading_log == spec.gnss_log) {
      logs.headings = logs.gnss;  // one log read once, as ReadPoseLogs does
      heading_read_ = gnss_read_;
    } else {
      logs.headings = ReadOn(spec.heading_log, &heading_, &heading_read_);
    }
  }
  if (attitude_recorded || !attitude_named) {
    attitude_.reset();
    return logs;
  }
  recording::RequireNoTopic(spec.attitude_topic, spec.attitude_log, "attitude.topic");
  const double offset_s = spec.attitude_time_offset_s;
  if (!heading_recorded && spec.attitude_log == spec.heading_log) {
    logs.attitudes = recording::AttitudeStreamOf(logs.headings, offset_s);  // one log read once
    attitude_read_ = heading_read_;
  } else if (!gnss_recorded && spec.attitude_log == spec.gnss_log) {
    logs.attitudes = recording::AttitudeStreamOf(logs.gnss, offset_s);
    attitude_read_ = gnss_read_;
  } else {
    logs.attitudes = recording::AttitudeStreamOf(
        ReadOn(spec.attitude_log, &attitude_, &attitude_read_), offset_s);
  }
  return logs;
}

}  // namespace wallcal::guide
