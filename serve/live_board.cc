// SPDX-License-Identifier: Apache-2.0
#include "serve/live_board.h"

#include <cmath>
#include <utility>

#include "common/angles.h"
#include "common/format.h"
#include "common/json_text.h"
#include "guide/guide_text.h"

namespace wallcal::serve {
namespace {

std::string PointJson(const HistoryPoint& p) {
  const std::string sigma =
      p.known ? Format("\"x_m\": %.6f, \"y_m\": %.6f, \"yaw_deg\": %.5f", p.sigma_x_m, p.sigma_y_m,
                       p.sigma_yaw_rad * kRadToDeg)
              : std::string("\"x_m\": null, \"y_m\": null, \"yaw_deg\": null");
  return Format("{\"t_s\": %.1f, ", p.logged_s) + sigma +
         Format(", \"stations\": %d, \"enough\": %s}", p.stations, p.enough ? "true" : "false");
}

bool SamePoint(const HistoryPoint& a, const HistoryPoint& b) {
  return a.logged_s == b.logged_s && a.known == b.known && a.sigma_x_m == b.sigma_x_m &&
         a.sigma_y_m == b.sigma_y_m && a.sigma_yaw_rad == b.sigma_yaw_rad &&
         a.stations == b.stations && a.enough == b.enough;
}

}  // namespace

const char* GuideEndName(GuideEnd end) {
  switch (end) {
    case GuideEnd::kRunning: return "running";
    case GuideEnd::kEnough: return "enough";
    case GuideEnd::kTimeLimit: return "time limit";
  }
  return "";
}

LiveBoard::LiveBoard(size_t max_history) : max_history_(max_history < 2 ? 2 : max_history) {
  Rebuild();
}

void LiveBoard::PublishReport(const guide::GuideReport& report, int64_t scan_log_bytes) {
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  std::string json = guide::GuideJson(report);
  while (!json.empty() && (json.back() == '\n' || json.back() == '\r')) json.pop_back();
  report_json_ = std::move(json);
  has_waiting_ = false;
  waiting_.clear();
  scan_log_bytes_ = scan_log_bytes;
  if (!report.plan) {
    HistoryPoint point;
    point.logged_s = report.logged_s;
    point.known = report.predicted.known;
    if (point.known) {
      point.sigma_x_m = report.predicted.sigma_x_m();
      point.sigma_y_m = report.predicted.sigma_y_m();
      point.sigma_yaw_rad = report.predicted.sigma_yaw_rad();
    }
    point.stations = static_cast<int>(report.stations.size());
    point.enough = report.enough;
    // A report shown again (its warnings changed) adds no point.
    if (history_.empty() || !SamePoint(history_.back(), point)) history_.push_back(point);
    if (history_.size() > max_history_) {
      std::vector<HistoryPoint> thinned;
      for (size_t i = 0; i < history_.size(); i += 2) thinned.push_back(history_[i]);
      if (!SamePoint(thinned.back(), history_.back())) thinned.push_back(history_.back());
      history_ = std::move(thinned);
    }
  }
  Rebuild();
}

void LiveBoard::PublishWaiting(const std::string& message) {
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  has_waiting_ = true;
  waiting_ = message;
  Rebuild();
}

void LiveBoard::PublishEnd(GuideEnd end) {
  std::lock_guard<std::mutex> publishing(publish_mutex_);
  end_ = end;
  Rebuild();
}

void LiveBoard::Rebuild() {
  ++published_;
  std::string live = Format("{\"seq\": %lld, \"ended\": ", static_cast<long long>(published_)) +
                     JsonString(GuideEndName(end_)) +
                     ", \"waiting\": " + (has_waiting_ ? JsonString(waiting_) : "null") +
                     ", \"scan_log_bytes\": " +
                     (scan_log_bytes_ >= 0 ? std::to_string(scan_log_bytes_) : "null") +
                     ", \"report\": " + report_json_ + ", \"history\": [";
  for (size_t i = 0; i < history_.size(); ++i) {
    if (i > 0) live += ", ";
    live += PointJson(history_[i]);
  }
  live += "]}";
  auto live_ptr = std::make_shared<const std::string>(std::move(live));
  auto report_ptr = std::make_shared<const std::string>(report_json_);
  std::lock_guard<std::mutex> lock(mutex_);
  live_ = std::move(live_ptr);
  report_ = std::move(report_ptr);
  seq_ = published_;
}

LiveSnapshot LiveBoard::Live() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return LiveSnapshot{live_, seq_};
}

std::shared_ptr<const std::string> LiveBoard::ReportJson() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return report_;
}

int64_t LiveBoard::seq() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return seq_;
}

}  // namespace wallcal::serve
