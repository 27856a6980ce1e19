// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide kept between refreshes, so that an update reads only what the logs gained since the
// last one. It holds a preview pipeline::CalibrationSession: loaded and surveyed once, then at
// each refresh asked for the poses on the pose logs as they are, the detection of the scans the
// log gained and the solve. The scan log is read on from where the last read stopped
// (guide/scan_feed.h): a CARMEN text log from the line of the first scan not yet settled (a
// gzip-compressed one is inflated up to there, not parsed), a ROS 1 bag, an MCAP file, a
// rosbag2 .db3 file or a rosbag2 folder from the end of the last whole record read (a record
// still being written is read next time), with its decoded scans from the first not yet
// settled kept in memory. The scans already read keep their wall observations (detected once,
// with the gates of the first read's first pass) and are only given their poses anew (a dwell
// that grew moves its mean pose); the scans of the last seconds before the pose logs' end,
// whose poses may still change, are detected again next time. The pose logs are read on from
// where the last read stopped too (guide/pose_logs.h).

#include <cstdint>
#include <memory>

#include "guide/guide.h"
#include "guide/pose_logs.h"

namespace wallcal::guide {

// What the last refresh read.
struct ReadCounts {
  bool incremental = false;       // the scan log was read on from where the last read stopped
  int64_t scan_log_from_byte = 0;  // where the scan log was read from (0: from its start; a
                                   // recording: the end of the last whole record read before)
  int64_t scan_log_bytes = 0;      // its size when read
  int64_t scans_detected = 0;      // scans read and run through the wall detector this time
  int64_t scans_kept = 0;          // scans read before, whose observations were kept
  // The GNSS and heading logs (the same when they are one log): where each was read from.
  PoseLogRead gnss_log;
  PoseLogRead heading_log;
  int64_t fixes_used = 0;    // GGA fixes of accepted quality they hold
  int64_t headings_used = 0;  // headings they hold
};

class GuideSession {
 public:
  // Validates `options` (throws io::InputError naming the bad one); reads nothing yet.
  explicit GuideSession(GuideOptions options);
  ~GuideSession();
  GuideSession(const GuideSession&) = delete;
  GuideSession& operator=(const GuideSession&) = delete;

  // Reads what the logs gained since the last refresh (everything, the first time) and reports
  // on the whole session as it is now. Throws io::InputError for bad input, or for logs that do
  // not hold enough yet (no fix, no scan): a caller that follows growing logs tries again.
  GuideReport Refresh();

  const ReadCounts& last_read() const { return last_read_; }
  const GuideOptions& options() const { return options_; }

 private:
  struct State;
  GuideOptions options_;
  std::unique_ptr<State> state_;
  ReadCounts last_read_;
};

}  // namespace wallcal::guide
