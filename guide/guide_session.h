// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide kept between refreshes, so that an update reads only what the logs gained since the
// last one. A CARMEN text scan log is read on from the byte where the last read stopped: the
// scans already read keep their wall observations (detected once, with the gates of the first
// read's first pass) and are only given their poses anew (a dwell that grew moves its mean
// pose); the scans of the last seconds before the pose logs' end, whose poses may still change,
// are read again next time, as is a last line still being written. The pose logs are read on
// from where the last read stopped too (guide/pose_logs.h). A session whose scans are in a
// recording (ROS 1 bag, MCAP, rosbag2) or in a gzip-compressed log is read whole at each refresh,
// its pose logs with it.

#include <cstdint>
#include <memory>

#include "guide/guide.h"
#include "guide/pose_logs.h"

namespace wallcal::guide {

// What the last refresh read.
struct ReadCounts {
  bool incremental = false;       // the scan log was read on from where the last read stopped
  int64_t scan_log_from_byte = 0;  // where the scan log was read from (0: from its start)
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
