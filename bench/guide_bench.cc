// SPDX-License-Identifier: Apache-2.0
// guide_bench: the guide's prediction against calibrate on cut sessions (--check), a crew that
// follows the guide stop by stop against the field guide's fixed pattern (--crew), and the time
// of one update on an hour-long session (--speed). Figures in docs/results.md, "The guide".

#include <zlib.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "common/angles.h"
#include "guide/guide.h"
#include "guide/guide_session.h"
#include "guide_crew.h"
#include "sim/recording_session.h"
#include "sim/simulation_config.h"
#include "test/support/guide_check.h"
#include "test/support/rosbag2_folders.h"

namespace {

namespace fs = std::filesystem;
using namespace wallcal;

double Quantile(std::vector<double> v, double q) {
  if (v.empty()) return NAN;
  std::sort(v.begin(), v.end());
  return v[static_cast<size_t>(std::lround(q * (v.size() - 1)))];
}

sim::SimulationConfig Scenario(const std::string& name) {
  return sim::ReadSimulationConfig(std::string(WALLCAL_SOURCE_DIR) + "/configs/simulate/" + name);
}

int Check(const std::vector<std::string>& scenarios, int seeds, int stations,
          const fs::path& scratch) {
  const std::vector<double> cuts = {0.3, 0.6, 1.0};
  const char* axes[3] = {"x", "y", "yaw"};
  std::printf("scenario                         cut  axis  ratio min  median    max  in 0.8-1.25\n");
  for (const std::string& scenario : scenarios) {
    sim::SimulationConfig config = Scenario(scenario);
    if (stations > 0) config.num_stations = stations;
    std::vector<std::vector<std::vector<double>>> ratios(cuts.size(),
                                                         std::vector<std::vector<double>>(3));
    std::vector<int> missing(cuts.size(), 0);
    for (int s = 0; s < seeds; ++s) {
      const auto checks =
          testing_support::CheckGuideOnCuts(config, 1000 + s, scratch / "check", cuts, 2);
      for (size_t k = 0; k < checks.size(); ++k) {
        if (!checks[k].calibrated || !checks[k].predicted) {
          ++missing[k];
          continue;
        }
        for (int a = 0; a < 3; ++a) ratios[k][a].push_back(checks[k].ratio(a));
      }
    }
    for (size_t k = 0; k < cuts.size(); ++k) {
      for (int a = 0; a < 3; ++a) {
        const std::vector<double>& r = ratios[k][a];
        const auto in_band = std::count_if(r.begin(), r.end(),
                                           [](double x) { return x >= 0.8 && x <= 1.25; });
        std::printf("%-32s %3.0f%%  %-4s  %9.3f  %6.3f  %6.3f  %zd/%zu%s\n", scenario.c_str(),
                    cuts[k] * 100, axes[a], Quantile(r, 0.0), Quantile(r, 0.5), Quantile(r, 1.0),
                    static_cast<std::ptrdiff_t>(in_band), r.size(),
                    missing[k] ? (" (" + std::to_string(missing[k]) + " without σ)").c_str() : "");
      }
    }
    std::fflush(stdout);
  }
  return 0;
}

std::string ReadAll(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The byte after the last line of `text` from `from` on stamped at or before t_s (the stamp: a
// scan line's last field, an NMEA line's logger prefix).
size_t EndOfLinesUpTo(const std::string& text, size_t from, double t_s, bool stamp_last) {
  size_t end = from;
  for (size_t at = from; at < text.size();) {
    size_t next = text.find('\n', at);
    next = next == std::string::npos ? text.size() : next + 1;
    size_t field = at;
    if (stamp_last) {
      const size_t space = text.rfind(' ', next - 2);
      field = space == std::string::npos || space < at ? at : space + 1;
    }
    if (std::strtod(text.c_str() + field, nullptr) > t_s) break;
    end = next;
    at = next;
  }
  return end;
}

// One log of the session, written up to a time.
// A gzip-compressed log grows by a gzip member per write (zlib reads the members as one stream).
struct GrowingLog {
  fs::path path;
  std::string text;
  bool stamp_last = false;
  size_t written = 0;
  bool gzip = false;
  void WriteUpTo(double t_s) {
    const size_t upto = EndOfLinesUpTo(text, written, t_s, stamp_last);
    if (gzip) {
      gzFile out = gzopen(path.string().c_str(), "ab6");
      if (out != nullptr) {
        gzwrite(out, text.data() + written, static_cast<unsigned>(upto - written));
        gzclose(out);
      }
    } else {
      std::ofstream out(path, std::ios::binary | std::ios::app);
      out.write(text.data() + written, static_cast<std::streamsize>(upto - written));
    }
    written = upto;
  }
};

double Seconds(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// CPU seconds of this process so far (every thread).
double CpuSeconds() { return static_cast<double>(std::clock()) / CLOCKS_PER_SEC; }

void PrintReport(const char* what, const guide::GuideReport& report, double s, double cpu_s) {
  std::printf("%-26s %2zu stations, σ x %.4f m y %.4f m yaw %.3f deg, %zu stops advised: "
              "%.2f s (CPU %.2f s)\n",
              what, report.stations.size(), report.predicted.sigma_x_m(),
              report.predicted.sigma_y_m(), report.predicted.sigma_yaw_rad() * kRadToDeg,
              report.next.size(), s, cpu_s);
}

// The hour-long session recorded while the guide follows it: the logs up to a minute before
// the end (the first read), then grown a second at a time (the updates). Twice: with the default
// tolerances (the session is enough: no stops advised) and with tolerances of 1 mm and 0.01°
// (three stops advised at each update).
// A recording (ROS 1 bag, MCAP) is grown by bytes instead, its last 60/3600 cut off for the
// first read and 1/3600 added for each update (about a second of its messages).
// --gzip: the text scan log written gzip-compressed.
// --rosbag2 (with --format db3 or mcap): the recording split into a rosbag2 folder of six storage
// files (ten minutes each), grown as a recorder writes it (test/support/rosbag2_folders.h: a
// .db3 file row by row in place, an MCAP file by bytes; each split file appearing in turn).
// --format db3 alone: one .db3 file, grown row by row in place.
// --at F: the updates end at F of the hour (the first read N seconds before, N = --updates).
int Speed(const fs::path& scratch, int updates, sim::SessionFormat format, bool gzip,
          bool rosbag2, double at) {
  sim::SimulationConfig config = Scenario("bench_lms291_hour.yaml");
  const fs::path whole = scratch / "hour";
  sim::WriteSimulatedSession(config, 7, whole.string(), format);
  std::vector<GrowingLog> original;
  std::string recording;
  double first_s = 0.0, last_s = 3600.0;
  if (format == sim::SessionFormat::kText) {
    for (const auto& [name, stamp_last] : {std::pair<const char*, bool>{"scans.clf", true},
                                           {"gnss.nmea", false}, {"heading.nmea", false}}) {
      original.push_back(GrowingLog{fs::path(name), ReadAll(whole / name), stamp_last, 0, false});
    }
    original[0].gzip = gzip;
    const std::string& gnss = original[1].text;
    first_s = std::strtod(gnss.c_str(), nullptr);
    last_s = std::strtod(gnss.c_str() + gnss.rfind('\n', gnss.size() - 2) + 1, nullptr);
  } else {
    for (const char* name : {"session.bag", "session.mcap", "session.db3"}) {
      if (fs::exists(whole / name)) recording = name;
    }
  }
  // A .db3 file cannot be cut at a byte: it grows by rows, as a one-file folder does.
  std::optional<testing_support::SplitFolder> split;
  const int split_files = rosbag2 ? 6 : 1;
  if (rosbag2 || format == sim::SessionFormat::kDb3) {
    split = testing_support::SplitIntoFiles((whole / recording).string(),
                                            whole / "split" / "session", split_files);
    fs::remove(whole / recording);
    recording.clear();
  }
  const std::string recorded = recording.empty() ? "" : ReadAll(whole / recording);
  // The recording up to t_s of its [first_s, last_s], by bytes.
  const auto write_recording = [&](const fs::path& dir, double t_s) {
    const size_t upto = static_cast<size_t>(static_cast<double>(recorded.size()) *
                                            std::min(1.0, (t_s - first_s) / (last_s - first_s)));
    std::ofstream(dir / recording, std::ios::binary | std::ios::trunc)
        .write(recorded.data(), static_cast<std::streamsize>(upto));
  };
  for (const bool tight : {false, true}) {
    const fs::path dir = scratch / "growing";
    fs::remove_all(dir);
    fs::create_directories(dir);
    for (const char* name : {"session.yaml", "survey.csv"}) fs::copy_file(whole / name, dir / name);
    std::vector<GrowingLog> logs = original;
    for (GrowingLog& log : logs) log.path = dir / log.path;
    double t_s = at > 0.0 ? first_s + at * (last_s - first_s) - updates : last_s - 60.0;
    for (GrowingLog& log : logs) log.WriteUpTo(t_s);
    if (!recording.empty()) write_recording(dir, t_s);
    std::optional<testing_support::GrowingRosbag2Folder> folder;
    const auto share = [&](double t) { return (t - first_s) / (last_s - first_s); };
    if (split) {
      folder.emplace(*split, dir / "session", /*metadata=*/false);
      folder->WriteUpTo(share(t_s));
      testing_support::PointSessionAt(
          dir, (rosbag2 ? folder->path() : folder->path() / split->files[0]).string());
    }
    guide::GuideOptions options;
    options.session_path = dir.string();
    options.threads = 2;
    if (tight) {
      options.config_path = (dir / "tight.yaml").string();
      std::ofstream(options.config_path)
          << "acceptance:\n  max_sigma_xy_m: 0.001\n  max_sigma_yaw_deg: 0.01\n";
    }
    std::printf("%s\n", tight ? "tolerances 1 mm, 0.01 deg (stops advised):"
                              : "default tolerances (enough):");
    guide::GuideSession session(options);
    auto start = std::chrono::steady_clock::now();
    double cpu_start = CpuSeconds();
    const guide::GuideReport first = session.Refresh();
    const std::string first_read =
        "first read (" + std::to_string(static_cast<int>(std::lround((t_s - first_s) / 60.0))) +
        " minutes):";
    PrintReport(first_read.c_str(), first, Seconds(start), CpuSeconds() - cpu_start);
    std::vector<double> times, cpu_times;
    for (int k = 0; k < updates; ++k) {
      t_s += 1.0;
      for (GrowingLog& log : logs) log.WriteUpTo(t_s);
      if (!recording.empty()) write_recording(dir, t_s);
      if (folder) folder->WriteUpTo(share(t_s));
      start = std::chrono::steady_clock::now();
      cpu_start = CpuSeconds();
      const guide::GuideReport report = session.Refresh();
      times.push_back(Seconds(start));
      cpu_times.push_back(CpuSeconds() - cpu_start);
      PrintReport("update (+1 s of logs):", report, times.back(), cpu_times.back());
    }
    std::printf("%.0f s of logs; updates: median %.3f s (CPU %.3f s), max %.3f s (CPU %.3f s); "
                "%s\n",
                t_s - first_s, Quantile(times, 0.5), Quantile(cpu_times, 0.5),
                Quantile(times, 1.0), Quantile(cpu_times, 1.0),
                session.last_read().incremental ? "the scan log read on from the last read"
                                                : "the scan log read whole");
    std::fflush(stdout);
  }
  fs::remove_all(whole);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::string mode;
  int seeds = 20;
  int stations = 0;
  int updates = 10;
  sim::SessionFormat format = sim::SessionFormat::kText;
  bool gzip = false;
  bool rosbag2 = false;
  double at = -1.0;
  std::vector<std::string> scenarios;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--check" || arg == "--crew" || arg == "--speed") {
      mode = arg;
    } else if (arg == "--transcript" && i + 1 < argc) {
      return bench::Transcript(argv[i + 1]);
    } else if (arg == "--seeds" && i + 1 < argc) {
      seeds = std::atoi(argv[++i]);
    } else if (arg == "--gzip") {
      gzip = true;
    } else if (arg == "--rosbag2") {
      rosbag2 = true;
    } else if (arg == "--at" && i + 1 < argc) {
      at = std::atof(argv[++i]);
    } else if (arg == "--format" && i + 1 < argc) {
      const std::optional<sim::SessionFormat> parsed = sim::ParseSessionFormat(argv[++i]);
      if (!parsed) {
        std::cerr << "guide_bench: --format takes " << sim::SessionFormatNames() << "\n";
        return 2;
      }
      format = *parsed;
    } else if (arg == "--updates" && i + 1 < argc) {
      updates = std::atoi(argv[++i]);
    } else if (arg == "--stations" && i + 1 < argc) {
      stations = std::atoi(argv[++i]);
    } else if (arg == "--help") {
      std::cout << "usage: guide_bench --check [SCENARIO.yaml ...] [--stations N] | --crew | "
                   "--speed [--updates N] [--format F [--rosbag2] | --gzip] [--at F] "
                   "[--seeds N (default 20)]\n"
                   "  --check     the guide's σ over calibrate's on sessions cut after 30, 60 and "
                   "100 % of their scans\n"
                   "              (scenarios from configs/simulate/; --stations overrides their "
                   "num_stations)\n"
                   "  --crew      a crew following the guide against the field guide's pattern\n"
                   "  --speed     an hour-long session followed as it grows: the first read of 59 minutes,\n"
                   "              then N updates (default 10), each after a second more of logs;\n"
                   "              --format ros1, mcap, ...: recorded as one recording, grown by bytes;\n"
                   "              --gzip: the CARMEN scan log gzip-compressed (a member per write);\n"
                   "              --rosbag2 (--format db3 or mcap): a rosbag2 folder of six split "
                   "files, grown in place;\n"
                   "              --at F: the updates end at F of the hour (default: the first "
                   "read a minute before its end)\n"
                   "  --transcript DIR  one guided crew, the guide's report after each stop\n";
      return 0;
    } else {
      scenarios.push_back(arg);
    }
  }
  const fs::path scratch = fs::temp_directory_path() / ("wallcal_guide_bench_" + std::to_string(getpid()));
  fs::create_directories(scratch);
  int status = 2;
  if (mode == "--check") {
    if (scenarios.empty()) scenarios = {"lms291_sapporo.yaml", "bench_lms291_two_walls.yaml"};
    status = Check(scenarios, seeds, stations, scratch);
  } else if (mode == "--crew") {
    status = bench::RunCrew(seeds, scratch);
  } else if (mode == "--speed") {
    if (rosbag2 && format != sim::SessionFormat::kDb3 && format != sim::SessionFormat::kMcap) {
      std::cerr << "guide_bench: --rosbag2 takes --format db3 or mcap\n";
      return 2;
    }
    status = Speed(scratch, updates, format, gzip, rosbag2, at);
  } else {
    std::cerr << "guide_bench: give --check, --crew or --speed\n";
  }
  fs::remove_all(scratch);
  return status;
}
