// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the guide's page shows, published by the guide and read by the server: the newest report
// as guide --json writes it (guide::GuideJson, the same computation), what the guide is waiting
// for, whether it has ended, and the σ of every refresh so far (the page's chart).
//
// The guide's thread builds each document outside the lock and swaps it in under a mutex; a
// server thread only copies a shared pointer under it. So the guide never waits on a socket,
// and a reader never sees half a document.

#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "guide/guide.h"

namespace wallcal::serve {

// Why the guide stopped (the page says so and keeps showing the last report).
enum class GuideEnd { kRunning, kEnough, kTimeLimit };
const char* GuideEndName(GuideEnd end);  // "running", "enough", "time limit"

// One refresh on the page's σ chart.
struct HistoryPoint {
  double logged_s = 0.0;   // the report's logged_s: from the first scan used
  bool known = false;      // the σ was determined
  double sigma_x_m = 0.0, sigma_y_m = 0.0, sigma_yaw_rad = 0.0;
  int stations = 0;
  bool enough = false;
};

// A document as published, with its publication number.
struct LiveSnapshot {
  std::shared_ptr<const std::string> json;
  int64_t seq = 0;
};

class LiveBoard {
 public:
  // Keeps at most `max_history` points (> 1): beyond, every other one is let go (the chart keeps
  // its whole span at half the resolution).
  explicit LiveBoard(size_t max_history = 2000);

  // The report of a refresh (or a plan), with the scan log's size when it was read (-1: not
  // known). Ends any waiting.
  void PublishReport(const guide::GuideReport& report, int64_t scan_log_bytes = -1);
  // The logs hold too little yet (the message says what); the last report, if any, stays.
  void PublishWaiting(const std::string& message);
  void PublishEnd(GuideEnd end);

  // The page's document (one JSON object):
  //   {"seq": N, "ended": "running"|"enough"|"time limit", "waiting": "…"|null,
  //    "scan_log_bytes": N|null, "report": <guide --json's object>|null,
  //    "history": [{"t_s", "x_m", "y_m", "yaw_deg" (null when not known), "stations", "enough"}]}
  // seq counts the publications. json is never null.
  LiveSnapshot Live() const;
  // The newest report exactly as guide --json prints it (without its newline); "null" before any.
  std::shared_ptr<const std::string> ReportJson() const;
  int64_t seq() const;

 private:
  void Rebuild();  // with mutex_ not held: builds the document from the fields, then swaps

  const size_t max_history_;
  // The guide's side (only the publishing thread touches these).
  std::string report_json_ = "null";
  std::string waiting_;
  bool has_waiting_ = false;
  int64_t scan_log_bytes_ = -1;
  GuideEnd end_ = GuideEnd::kRunning;
  std::vector<HistoryPoint> history_;
  int64_t published_ = 0;
  std::mutex publish_mutex_;  // serialises publishers (one guide thread; tests may use more)

  // What readers see.
  mutable std::mutex mutex_;
  std::shared_ptr<const std::string> live_;
  std::shared_ptr<const std::string> report_;
  int64_t seq_ = 0;
};

}  // namespace wallcal::serve
