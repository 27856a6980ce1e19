// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session's GNSS, heading and attitude logs kept between the guide's refreshes, so that a
// refresh reads only what they gained: an NMEA text log is read on from where the last read
// stopped (io::NmeaFollower: the reader's state carried over, a last line still being written
// read again next time), once for all the streams it holds (the attitude sentences of the
// heading log come with its headings). A gzip-compressed log and a recording's topics (ROS 1
// bag, MCAP, rosbag2) are read whole at each refresh. Either way Read() returns what
// recording::ReadPoseLogs returns for the logs as they are now, for pipeline::PosesFromLogs,
// except that a text attitude log without a sample yet is no error (it may be still empty).

#include <cstdint>
#include <optional>

#include "io/text/nmea_reader.h"
#include "io/types.h"
#include "recording/recording_streams.h"

namespace wallcal::guide {

// Where a pose log was read from: the byte the last Read() started at (0: from its start, as a
// recording or a gzip-compressed log always is) and the bytes read up to (0 for a recording).
struct PoseLogRead {
  int64_t from_byte = 0;
  int64_t bytes = 0;
};

class PoseLogFollower {
 public:
  // The logs and topics of `session` (copied).
  explicit PoseLogFollower(io::SessionSpec session);

  // Reads what the logs gained since the last call (everything, the first time). Throws
  // io::InputError as recording::ReadPoseLogs does.
  recording::PoseLogs Read();

  const PoseLogRead& gnss_read() const { return gnss_read_; }
  const PoseLogRead& heading_read() const { return heading_read_; }
  const PoseLogRead& attitude_read() const { return attitude_read_; }

 private:
  io::SessionSpec session_;
  std::optional<io::NmeaFollower> gnss_;     // a text GNSS log
  std::optional<io::NmeaFollower> heading_;  // a text heading log other than the GNSS log
  std::optional<io::NmeaFollower> attitude_;  // a text attitude log of its own
  PoseLogRead gnss_read_;
  PoseLogRead heading_read_;
  PoseLogRead attitude_read_;
};

}  // namespace wallcal::guide
