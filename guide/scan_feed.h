// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scans of a session that is still being recorded, read on from where the last refresh
// stopped: a CARMEN text log from the byte of the first scan not yet settled (a gzip-compressed
// one is inflated from its start up to there, but not parsed); a recording through
// recording::ScanTail, its decoded scans from the first not yet settled kept in memory: a ROS 1
// bag or an MCAP file from the end of the last whole record read, a rosbag2 .db3 file from the
// rows after the last one read, a rosbag2 folder file by file (each of its storage files so,
// the next one read as soon as it appears; recording/recording_tail.h).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "io/scan_source.h"
#include "io/types.h"

namespace wallcal::guide {

// Where a scan read on starts (its line's byte in a text log, its place among the kept scans
// of a recording), and its stamp as logged (s).
struct ScanMark {
  double stamp_s = 0.0;
  int64_t at = 0;
  int line = 0;
};

// What one Update read.
struct FeedRead {
  bool restarted = false;  // the log shrank (a new recording under the same name): read anew
  int64_t from_byte = 0;   // where the log was read on from (0: its start; a CARMEN log:
                           // a byte of its text, of the inflated text when gzip-compressed;
                           // a rosbag2 folder: of its storage files' bytes in split order)
  int64_t log_bytes = 0;   // the log's file size when read (a folder: its storage files')
};

class ScanFeed {
 public:
  virtual ~ScanFeed() = default;
  // A feed for the session's scan log (never null). Throws io::InputError for a log too short
  // yet to tell its kind (under 16 bytes) or a folder without a storage file yet: a caller
  // following it tries again. `preset` (checked against a recording's scans) must outlive the
  // feed.
  static std::unique_ptr<ScanFeed> For(const io::SessionSpec& session,
                                       const io::ScannerPreset* preset);

  // Takes in what the log gained. A log that shrank is read from its start (restarted: what was
  // settled is forgotten). Throws io::InputError for a damaged recording.
  virtual FeedRead Update() = 0;
  // Every scan of the log (the first pass, before any scan is settled).
  virtual std::unique_ptr<io::ScanSource> OpenAll() = 0;
  // The scans from the first not settled on; each scan read adds its mark to *marks.
  virtual std::unique_ptr<io::ScanSource> OpenUnsettled(std::vector<ScanMark>* marks) = 0;
  // The first `settled` of the scans `marks` lists are read for good: the next OpenUnsettled
  // starts at marks[settled] (settled < marks.size()).
  virtual void Settle(const std::vector<ScanMark>& marks, size_t settled) = 0;
};

}  // namespace wallcal::guide
