// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session's GNSS, heading and attitude logs kept between the guide's refreshes, so that a
// refresh reads only what they gained: an NMEA text log is read on from where the last read
// stopped (io::NmeaFollower: the reader's state carried over, a last line still being written
// read again next time), once for all the streams it holds (the attitude sentences of the
// heading log come with its headings); a recording's GNSS and heading topics (ROS 1 bag, MCAP,
// .db3, rosbag2 folder) from the end of the last whole record read (recording::PoseTail: the
// decoders' state carried over; both topics in one pass when they share the recording). A
// recording's attitude topic and a gzip-compressed NMEA log are read whole at each refresh.
// Either way Read() returns what recording::ReadPoseLogs returns for the logs as they are now,
// for pipeline::PosesFromLogs, except for the container readers' warnings about a recording
// still being written (recording::PoseTail) and that a text attitude log without a sample yet
// is no error (it may be still empty).

#include <cstdint>
#include <memory>
#include <optional>

#include "io/text/nmea_reader.h"
#include "io/types.h"
#include "recording/recording_streams.h"

namespace wallcal::guide {

// Where a pose log was read from at the last Read(): the byte it started at (0: from its
// start, as a gzip-compressed log always is; a recording: recording::TailRead::from_byte) and
// the log's size then (a rosbag2 folder: its storage files').
struct PoseLogRead {
  int64_t from_byte = 0;
  int64_t bytes = 0;
};

class PoseLogFollower {
 public:
  // The logs and topics of `session` (copied).
  explicit PoseLogFollower(io::SessionSpec session);

  // Reads what the logs gained since the last call (everything, the first time). A log that
  // shrank is read from its start. Throws io::InputError as recording::ReadPoseLogs does.
  recording::PoseLogs Read();

  const PoseLogRead& gnss_read() const { return gnss_read_; }
  const PoseLogRead& heading_read() const { return heading_read_; }
  const PoseLogRead& attitude_read() const { return attitude_read_; }

 private:
  io::SessionSpec session_;
  std::optional<io::NmeaFollower> gnss_;     // a text GNSS log
  std::optional<io::NmeaFollower> heading_;  // a text heading log other than the GNSS log
  std::optional<io::NmeaFollower> attitude_;  // a text attitude log of its own
  // The recorded GNSS and heading streams: which ones, and their tail.
  bool gnss_recorded_ = false, heading_recorded_ = false;
  std::unique_ptr<recording::PoseTail> recorded_;
  PoseLogRead gnss_read_;
  PoseLogRead heading_read_;
  PoseLogRead attitude_read_;
};

}  // namespace wallcal::guide
