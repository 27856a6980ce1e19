// SPDX-License-Identifier: Apache-2.0
#include "guide/follow.h"

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <map>
#include <optional>
#include <set>
#include <thread>
#include <utility>
#include <vector>

#include "common/format.h"
#include "io/config/session_reader.h"
#include "io/types.h"

namespace wallcal::guide {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double SecondsBetween(Clock::time_point a, Clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

// One log as it looks now: its size and modification time.
struct LogLook {
  std::string path;
  uintmax_t size = 0;
  fs::file_time_type::rep time = 0;
  bool operator==(const LogLook& o) const {
    return path == o.path && size == o.size && time == o.time;
  }
};

// The session's logs (each once: the GNSS and heading logs, or all three streams, may be one
// file).
std::vector<std::string> LogPaths(const io::SessionSpec& session) {
  std::vector<std::string> paths;
  for (const std::string& path : {session.scanner_log, session.gnss_log, session.heading_log}) {
    if (!path.empty() && std::find(paths.begin(), paths.end(), path) == paths.end()) {
      paths.push_back(path);
    }
  }
  return paths;
}

// A log's look: a file's size and modification time; a folder's (a rosbag2 folder's) the sum of
// its files' sizes and the latest of their times, since writes into its files leave the folder's
// own time as it is.
LogLook LookAt(const std::string& path) {
  LogLook look;
  look.path = path;
  std::error_code ec;
  if (fs::is_directory(path, ec)) {
    for (const fs::directory_entry& entry : fs::directory_iterator(path, ec)) {
      std::error_code entry_ec;
      const auto size = entry.file_size(entry_ec);
      if (!entry_ec) look.size += size;
      const auto time = entry.last_write_time(entry_ec);
      if (!entry_ec) look.time = std::max(look.time, time.time_since_epoch().count());
    }
    return look;
  }
  const auto size = fs::file_size(path, ec);
  look.size = ec ? 0 : size;
  const auto time = fs::last_write_time(path, ec);
  look.time = ec ? 0 : time.time_since_epoch().count();
  return look;
}

std::vector<LogLook> LookAt(const std::vector<std::string>& paths) {
  std::vector<LogLook> looks;
  for (const std::string& path : paths) looks.push_back(LookAt(path));
  return looks;
}

// What the logs did over time, for the warnings a report cannot know from one read: a log that
// stopped growing, a GNSS log that grows without fixes of accepted quality.
class LogWatch {
 public:
  LogWatch(std::vector<std::string> paths, std::string gnss_log, double stale_after_s)
      : paths_(std::move(paths)), gnss_log_(std::move(gnss_log)), stale_after_s_(stale_after_s) {}

  // Looks at the logs; true when any changed since the last look.
  bool Look(Clock::time_point now) {
    std::vector<LogLook> looks = LookAt(paths_);
    const bool changed = looks != looks_;
    for (size_t i = 0; i < looks.size(); ++i) {
      if (i >= looks_.size() || !(looks[i] == looks_[i])) grown_at_[looks[i].path] = now;
    }
    looks_ = std::move(looks);
    return changed;
  }

  // After a refresh: the fixes of accepted quality the GNSS log holds now.
  void Refreshed(Clock::time_point now, int64_t fixes_used) {
    if (!fixes_seen_ || fixes_used > fixes_used_) {
      fixes_seen_ = true;
      fixes_used_ = fixes_used;
      fixes_at_ = now;
      gnss_size_at_fix_ = GnssSize();
    }
  }

  std::vector<GuideWarning> Warnings(Clock::time_point now) const {
    std::vector<GuideWarning> warnings;
    for (const LogLook& look : looks_) {
      const auto it = grown_at_.find(look.path);
      const double quiet_s = it == grown_at_.end() ? 0.0 : SecondsBetween(it->second, now);
      if (quiet_s >= stale_after_s_) {
        warnings.push_back({GuideWarningKind::kLogStale, look.path,
                            Format("%s has not grown for %.0f s", fs::path(look.path).filename().c_str(),
                                   quiet_s)});
      }
    }
    const double no_fix_s = SecondsBetween(fixes_at_, now);
    if (fixes_seen_ && no_fix_s >= stale_after_s_ && GnssSize() > gnss_size_at_fix_) {
      warnings.push_back(
          {GuideWarningKind::kFixesNotAccepted, gnss_log_,
           Format("no GNSS fix of accepted quality (gnss.min_fix_quality) for %.0f s while %s "
                  "grew: RTK float or worse",
                  no_fix_s, fs::path(gnss_log_).filename().c_str())});
    }
    return warnings;
  }

 private:
  uintmax_t GnssSize() const {
    for (const LogLook& look : looks_) {
      if (look.path == gnss_log_) return look.size;
    }
    return 0;
  }

  std::vector<std::string> paths_;
  std::string gnss_log_;
  double stale_after_s_;
  std::vector<LogLook> looks_;
  std::map<std::string, Clock::time_point> grown_at_;
  bool fixes_seen_ = false;
  int64_t fixes_used_ = 0;
  Clock::time_point fixes_at_;
  uintmax_t gnss_size_at_fix_ = 0;
};

// The warnings' kinds and subjects: a report is shown again when they change (not when only the
// seconds in a message do).
std::set<std::pair<int, std::string>> Keys(const std::vector<GuideWarning>& warnings) {
  std::set<std::pair<int, std::string>> keys;
  for (const GuideWarning& w : warnings) keys.insert({static_cast<int>(w.kind), w.subject});
  return keys;
}

}  // namespace

FollowEnd Follow(GuideSession* session, const FollowOptions& follow,
                 const std::function<void(const GuideReport&)>& show,
                 const std::function<void(const std::string&)>& waiting) {
  const GuideOptions& options = session->options();
  const io::SessionSpec spec =
      options.scanner_id.empty()
          ? io::ReadSession(options.session_path)
          : io::SessionForScannerId(io::ReadSession(options.session_path), options.scanner_id);
  const auto start = Clock::now();
  const auto period = std::chrono::duration<double>(follow.period_s > 0.0 ? follow.period_s : 1.0);
  LogWatch watch(LogPaths(spec), spec.gnss_log,
                 follow.stale_after_s > 0.0 ? follow.stale_after_s : 10.0);
  std::optional<GuideReport> last;  // the last report, shown again when the warnings change
  std::set<std::pair<int, std::string>> shown_keys;
  bool first = true;
  while (true) {
    const auto now = Clock::now();
    const bool changed = watch.Look(now);
    if (changed || first) {
      first = false;
      try {
        last = session->Refresh();
        watch.Refreshed(Clock::now(), session->last_read().fixes_used);
        std::vector<GuideWarning> extra = watch.Warnings(Clock::now());
        shown_keys = Keys(extra);
        GuideReport shown = *last;
        shown.warnings.insert(shown.warnings.end(), extra.begin(), extra.end());
        show(shown);
        if (shown.enough) return FollowEnd::kEnough;
      } catch (const io::InputError& e) {
        last.reset();
        waiting(e.what());
      }
    } else if (last) {
      std::vector<GuideWarning> extra = watch.Warnings(now);
      if (Keys(extra) != shown_keys) {
        shown_keys = Keys(extra);
        GuideReport shown = *last;
        shown.warnings.insert(shown.warnings.end(), extra.begin(), extra.end());
        show(shown);
      }
    }
    const double elapsed = SecondsBetween(start, Clock::now());
    if (follow.max_seconds >= 0.0 && elapsed >= follow.max_seconds) return FollowEnd::kTimeLimit;
    std::this_thread::sleep_for(period);
  }
}

}  // namespace wallcal::guide
