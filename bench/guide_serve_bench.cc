// SPDX-License-Identifier: Apache-2.0
// guide_serve_bench: how long after a log grows the page of `wallcal guide --follow --serve`
// shows it. A simulated session's text logs are appended in real time (every 0.1 s, each log up
// to the same share of its bytes as of the session's time, lines cut where the share falls, as a
// logger leaves them) while the guide follows them and serves its page; a headless Chromium
// (chromedriver) has the page open, and the page is read every 50 ms for the scan log's size
// its report was read at (the page sets it on <body> when it draws). For each append, the
// latency is the time until the page shows a report read at that size or later; also measured
// on /live.json polled directly (no browser), and from each refresh's first appearance on
// /live.json to the page's showing it. Prints median, 90th percentile and worst.
//
//   build/bench/guide_serve_bench [--sim FILE] [--seed N] [--stations N] [--dwell S]
//                                 [--every N] [--no-browser]
// Default: configs/simulate/lms291_sapporo.yaml with 12 stations of 15 s, every scan logged
// (75 Hz): about four minutes in real time.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/background_program.h"
#include "test/support/json_value.h"
#include "test/support/program_runner.h"
#include "test/support/raw_http.h"
#include "test/support/scratch_files.h"
#include "test/support/webdriver_client.h"

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using wallcal::testing_support::Json;
using wallcal::testing_support::JsonParser;

double Since(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The first and last scan stamps of a CARMEN log (s).
std::pair<double, double> ScanSpan(const std::string& log) {
  double first = 0.0, last = 0.0;
  bool any = false;
  size_t pos = 0;
  while (pos < log.size()) {
    const size_t end = log.find('\n', pos);
    const std::string line = log.substr(pos, end == std::string::npos ? std::string::npos : end - pos);
    pos = end == std::string::npos ? log.size() : end + 1;
    if (line.empty() || line[0] == '#') continue;
    std::vector<std::string> fields;
    size_t f = 0;
    while (f < line.size()) {
      const size_t space = line.find(' ', f);
      fields.push_back(line.substr(f, space == std::string::npos ? std::string::npos : space - f));
      f = space == std::string::npos ? line.size() : space + 1;
    }
    if (fields.size() < 3) continue;
    const double stamp = std::strtod(fields[fields.size() - 3].c_str(), nullptr);
    if (!any) first = stamp;
    last = stamp;
    any = true;
  }
  return {first, last};
}

struct Sample {
  double t_s;
  long long bytes;
};

// For each append (time, scan log size), the delay until `shown` first reaches that size.
std::vector<double> Latencies(const std::vector<Sample>& appends, const std::vector<Sample>& shown) {
  std::vector<double> latencies;
  size_t from = 0;  // the first sample at or after the append (appends are in time order)
  for (const Sample& a : appends) {
    while (from < shown.size() && shown[from].t_s < a.t_s) ++from;
    for (size_t k = from; k < shown.size(); ++k) {
      if (shown[k].bytes >= a.bytes) {
        latencies.push_back(shown[k].t_s - a.t_s);
        break;
      }
    }
  }
  return latencies;
}

void Print(const char* what, std::vector<double> latencies, size_t appends) {
  if (latencies.empty()) {
    std::printf("%-28s no append seen\n", what);
    return;
  }
  std::sort(latencies.begin(), latencies.end());
  const auto at = [&](double q) { return latencies[static_cast<size_t>(q * (latencies.size() - 1))]; };
  std::printf("%-28s appends %zu (seen %zu): median %.2f s, 90%% %.2f s, worst %.2f s\n", what,
              appends, latencies.size(), at(0.5), at(0.9), latencies.back());
}

}  // namespace

int main(int argc, char** argv) {
  std::string sim_path = std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/lms291_sapporo.yaml";
  int seed = 1, stations = 12, every = 1;
  double dwell_s = 15.0;
  bool browser_on = true;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool more = i + 1 < argc;
    if (arg == "--sim" && more) sim_path = argv[++i];
    else if (arg == "--seed" && more) seed = std::atoi(argv[++i]);
    else if (arg == "--stations" && more) stations = std::atoi(argv[++i]);
    else if (arg == "--dwell" && more) dwell_s = std::atof(argv[++i]);
    else if (arg == "--every" && more) every = std::atoi(argv[++i]);
    else if (arg == "--no-browser") browser_on = false;
    else {
      std::fprintf(stderr, "usage: guide_serve_bench [--sim FILE] [--seed N] [--stations N] "
                           "[--dwell S] [--every N] [--no-browser]\n");
      return 2;
    }
  }
  const fs::path dir = fs::temp_directory_path() / ("guide_serve_bench_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  wallcal::sim::SimulationConfig config = wallcal::sim::ReadSimulationConfig(sim_path);
  config.num_stations = stations;
  config.dwell_s = dwell_s;
  config.log_every_n = every;
  wallcal::sim::WriteSimulatedSession(config, seed, (dir / "full").string(),
                                      wallcal::sim::SessionFormat::kText);
  fs::create_directories(dir / "live");
  std::vector<std::pair<std::string, std::string>> logs;
  for (const fs::directory_entry& e : fs::directory_iterator(dir / "full")) {
    const std::string name = e.path().filename().string();
    const std::string content = wallcal::testing_support::ReadFile(e.path());
    if (name == "scans.clf" || name == "gnss.nmea" || name == "heading.nmea") {
      logs.emplace_back(name, content);
    } else {
      fs::copy_file(e.path(), dir / "live" / name);
    }
  }
  std::sort(logs.begin(), logs.end());  // gnss, heading, scans: the scan log written last
  const auto span = ScanSpan(logs.back().second);
  const double duration_s = span.second - span.first;
  // Never enough: the guide follows the whole session.
  std::ofstream(dir / "tight.yaml") << "acceptance:\n  max_sigma_xy_m: 0.0001\n  max_sigma_yaw_deg: 0.0001\n";
  std::vector<size_t> written(logs.size(), 0);
  const auto append_to = [&](double share) {
    long long scan_bytes = 0;
    for (size_t f = 0; f < logs.size(); ++f) {
      const std::string& content = logs[f].second;
      const size_t upto = std::min(content.size(), static_cast<size_t>(share * content.size()));
      if (upto > written[f]) {
        std::ofstream out(dir / "live" / logs[f].first, std::ios::binary | std::ios::app);
        out.write(content.data() + written[f], static_cast<std::streamsize>(upto - written[f]));
        written[f] = upto;
      }
      if (logs[f].first == "scans.clf") scan_bytes = static_cast<long long>(written[f]);
    }
    return scan_bytes;
  };
  append_to(10.0 / duration_s);  // the first 10 s, so that the guide has a start

  wallcal::testing_support::BackgroundProgram guide(
      {wallcal::testing_support::WallcalPath(), "guide", (dir / "live").string(), "--follow",
       "--json", "--serve", "127.0.0.1:0", "--max-seconds", std::to_string(duration_s + 60.0),
       "--config", (dir / "tight.yaml").string()},
      dir / "guide.out", dir / "guide.err");
  const std::string line = guide.WaitForErrLine("http://", 120.0);
  if (line.empty()) {
    std::fprintf(stderr, "the guide printed no URL:\n%s\n", guide.Err().c_str());
    return 1;
  }
  const std::string url = line.substr(line.find("http://"));
  const int port = std::atoi(url.c_str() + url.rfind(':') + 1);
  std::unique_ptr<wallcal::testing_support::Browser> browser;
  if (browser_on) {
    const std::string missing = wallcal::testing_support::BrowserMissing();
    if (!missing.empty()) {
      std::fprintf(stderr, "%s\n", missing.c_str());
      return 1;
    }
    browser = std::make_unique<wallcal::testing_support::Browser>(dir / "profile", 1280, 800);
    if (!browser->ok() || !browser->Navigate(url)) {
      std::fprintf(stderr, "browser: %s\n", browser->error().c_str());
      return 1;
    }
  }
  std::printf("session %.0f s of scans (%d stations of %.0f s, every %d. scan), real time; "
              "page %s\n", duration_s, stations, dwell_s, every, url.c_str());
  std::fflush(stdout);

  const Clock::time_point start = Clock::now();
  std::atomic<bool> done{false};
  std::mutex mutex;
  std::vector<Sample> appends, on_page, on_json;
  std::thread json_poller([&] {
    while (!done.load()) {
      const wallcal::testing_support::HttpReply reply =
          wallcal::testing_support::HttpGet(port, "/live.json", 5000);
      Json doc;
      if (reply.status == 200 && JsonParser(reply.body).Parse(&doc) &&
          doc["scan_log_bytes"].kind == Json::kNumber) {
        std::lock_guard<std::mutex> lock(mutex);
        on_json.push_back({Since(start), static_cast<long long>(doc["scan_log_bytes"].number)});
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  std::thread page_poller([&] {
    while (browser && !done.load()) {
      Json value;
      if (browser->Execute("return document.body.dataset.scanLogBytes || '';", &value) &&
          !value.text.empty()) {
        const double t = Since(start);
        std::lock_guard<std::mutex> lock(mutex);
        on_page.push_back({t, std::atoll(value.text.c_str())});
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
  });
  // Real time: the share of the session's time since the start, from the first 10 s on.
  for (double t = 0.0; 10.0 + t <= duration_s + 0.1; t += 0.1) {
    const auto when = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(t));
    std::this_thread::sleep_until(when);
    const long long bytes = append_to((10.0 + t) / duration_s);
    std::lock_guard<std::mutex> lock(mutex);
    appends.push_back({Since(start), bytes});
  }
  std::this_thread::sleep_for(std::chrono::seconds(10));  // the last appends shown
  done = true;
  json_poller.join();
  page_poller.join();
  guide.Kill();
  // Only the appends that changed the scan log count.
  std::vector<Sample> grew;
  for (size_t i = 0; i < appends.size(); ++i) {
    if (i == 0 || appends[i].bytes > appends[i - 1].bytes) grew.push_back(appends[i]);
  }
  Print("log grown -> /live.json", Latencies(grew, on_json), grew.size());
  if (browser) {
    Print("log grown -> page in Chromium", Latencies(grew, on_page), grew.size());
    // Each refresh as /live.json first had it (to 20 ms) until the page showed it: the page's
    // own part (its polling and drawing).
    std::vector<Sample> refreshes;
    for (const Sample& s : on_json) {
      if (refreshes.empty() || s.bytes > refreshes.back().bytes) refreshes.push_back(s);
    }
    Print("refresh -> page in Chromium", Latencies(refreshes, on_page), refreshes.size());
  }
  int refreshes = 0;
  for (char c : guide.Out()) refreshes += c == '\n';
  std::printf("guide refreshes: %d over %.0f s\n", refreshes, Since(start));
  browser.reset();
  fs::remove_all(dir);
  return 0;
}
