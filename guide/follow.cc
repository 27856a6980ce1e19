// SPDX-License-Identifier: Apache-2.0
#include "guide/follow.h"

#include <chrono>
#include <filesystem>
#include <set>
#include <thread>

#include "io/config/session_reader.h"
#include "io/types.h"

namespace wallcal::guide {
namespace {

namespace fs = std::filesystem;

// A file's size and modification time, "path:size:time;".
std::string FileSignature(const fs::path& path) {
  std::error_code ec;
  const auto size = fs::file_size(path, ec);
  const auto time = fs::last_write_time(path, ec);
  return path.string() + ":" + std::to_string(ec ? 0 : size) + ":" +
         std::to_string(time.time_since_epoch().count()) + ";";
}

// What the session's logs look like now: their sizes and modification times; a folder's (a
// rosbag2 folder's) those of the files in it, whose writes leave the folder's own time as it is.
std::string LogSignature(const io::SessionSpec& session) {
  std::string signature;
  for (const std::string& path : {session.scanner_log, session.gnss_log, session.heading_log}) {
    signature += FileSignature(path);
    std::error_code ec;
    if (!fs::is_directory(path, ec)) continue;
    std::set<fs::path> files;
    for (const fs::directory_entry& entry : fs::directory_iterator(path, ec)) {
      files.insert(entry.path());
    }
    for (const fs::path& file : files) signature += FileSignature(file);
  }
  return signature;
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
  const auto start = std::chrono::steady_clock::now();
  const auto period = std::chrono::duration<double>(follow.period_s > 0.0 ? follow.period_s : 1.0);
  std::string seen;
  while (true) {
    const std::string now = LogSignature(spec);
    if (now != seen) {
      seen = now;
      try {
        const GuideReport report = session->Refresh();
        show(report);
        if (report.enough) return FollowEnd::kEnough;
      } catch (const io::InputError& e) {
        waiting(e.what());
      }
    }
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (follow.max_seconds >= 0.0 && elapsed >= follow.max_seconds) return FollowEnd::kTimeLimit;
    std::this_thread::sleep_for(period);
  }
}

}  // namespace wallcal::guide
