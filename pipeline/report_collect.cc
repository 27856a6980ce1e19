// SPDX-License-Identifier: Apache-2.0
// CollectReportData (pipeline/internal/steps.h) and ReportAround (pipeline/report_data.h): what the
// report shows beyond the result, gathered from what the run already read and one pass over the
// scans the report draws.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "calib/geodesy.h"
#include "calib/wall_detector.h"
#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "io/config/session_reader.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {
namespace {

namespace fs = std::filesystem;

constexpr int kMaxScanPanels = 4;       // stations whose scan is drawn, spread over the headings
constexpr size_t kMaxTrackVertices = 3000;  // the site map cannot show more

using calib::GridHeadingDeg;

// The mount the report draws with: the final estimate, else the first pass's, else the guess.
void ChooseMount(const CalibrationResult& result, ReportData* data) {
  if (result.solve.estimate.usable) {
    data->mount = result.solve.estimate.mount;
    data->mount_source = "final estimate";
    data->have_mount = true;
  } else if (result.detection.first_pass.usable) {
    data->mount = result.detection.first_pass.mount;
    data->mount_source = "first-pass estimate (the final one is not usable)";
    data->have_mount = true;
  } else if (result.loaded.session.mount_guess) {
    data->mount =
        calib::Mount{result.loaded.session.mount_guess->x_m, result.loaded.session.mount_guess->y_m,
                     result.loaded.session.mount_guess->yaw_rad};
    data->mount_source = "the session's mount guess (no estimate)";
    data->have_mount = true;
  } else {
    data->mount_source = "no estimate";
  }
}

Eigen::Vector2d ScannerAtStation(const Station& station, const calib::Mount& mount) {
  calib::VehiclePose pose;
  pose.antenna_local_m = station.antenna_local_m;
  pose.yaw_rad = station.yaw_rad;
  return calib::ScannerPositionLocal(pose, mount);
}

// Stations: the dwells the observations came from, in time order.
std::vector<Station> FindStations(const CalibrationResult& result, const calib::Mount& mount) {
  std::map<int, Station> by_segment;
  std::map<int, std::pair<double, double>> yaw_sums;
  std::map<int, double> first_stamp;
  for (size_t i = 0; i < result.solve.observations.size(); ++i) {
    const calib::WallObservation& o = result.solve.observations[i];
    if (!o.pose.stationary) continue;
    Station& s = by_segment[o.pose.segment];
    s.segment = o.pose.segment;
    s.antenna_local_m += o.pose.antenna_local_m;
    yaw_sums[o.pose.segment].first += std::cos(o.pose.yaw_rad);
    yaw_sums[o.pose.segment].second += std::sin(o.pose.yaw_rad);
    s.observations.push_back(static_cast<int>(i));
    if (!first_stamp.count(o.pose.segment)) first_stamp[o.pose.segment] = o.pose.stamp_s;
  }
  std::vector<Station> stations;
  for (auto& [segment, s] : by_segment) {
    s.antenna_local_m /= static_cast<double>(s.observations.size());
    s.yaw_rad = std::atan2(yaw_sums[segment].second, yaw_sums[segment].first);
    s.scanner_local_m = ScannerAtStation(s, mount);
    stations.push_back(s);
  }
  std::sort(stations.begin(), stations.end(), [&](const Station& a, const Station& b) {
    return first_stamp[a.segment] < first_stamp[b.segment];
  });
  return stations;
}

void CollectSiteMap(const CalibrationResult& result, const RunState& state, ReportData* data) {
  for (const io::GnssFix& fix : state.gnss.fixes) {
    if (fix.quality == 0) continue;
    data->track_local_m.push_back(calib::ToLocal(result.survey.frame, fix.lat_deg, fix.lon_deg));
  }
  if (!state.gnss.fixes.empty()) {
    data->gnss_first_s = state.gnss.fixes.front().stamp_s;
    data->gnss_last_s = state.gnss.fixes.back().stamp_s;
    data->gnss_fixes = static_cast<int64_t>(state.gnss.fixes.size());
  }
  std::vector<Eigen::Vector2d>& track = data->track_local_m;
  if (track.size() > kMaxTrackVertices) {
    const size_t stride = track.size() / kMaxTrackVertices + 1;
    std::vector<Eigen::Vector2d> thin;
    for (size_t i = 0; i < track.size(); i += stride) thin.push_back(track[i]);
    thin.push_back(track.back());
    track.swap(thin);
  }
  const calib::SurveyTie& tie = result.survey.tie;
  for (const io::SurveyPoint& p : result.survey.points) {
    const bool on_a_wall =
        std::any_of(result.loaded.session.walls.begin(), result.loaded.session.walls.end(),
                    [&p](const io::WallSpec& w) { return calib::SameSurveyCode(p.code, w.code); });
    if (on_a_wall) {
      data->wall_points_local_m.push_back(tie.local_R_survey * Eigen::Vector2d(p.x_m, p.y_m) +
                                          tie.local_t_survey);
    }
  }
  for (const io::ControlPoint& c : result.loaded.session.control) {
    for (const io::SurveyPoint& p : result.survey.points) {
      if (p.id != c.id) continue;
      data->controls.push_back(
          ControlMark{c.id, tie.local_R_survey * Eigen::Vector2d(p.x_m, p.y_m) + tie.local_t_survey,
                      calib::ToLocal(result.survey.frame, c.lat_deg, c.lon_deg)});
      break;
    }
  }
}

// Each read panel's scan detected around the report's mount with the second pass's gates.
void DetectPanels(const CalibrationResult& result, ReportData* data) {
  for (ScanPanel& panel : data->panels) {
    if (!panel.have_scan) continue;
    const calib::WallObservation& o = result.solve.observations[panel.observation];
    panel.gate =
        calib::GateFor(o, result.survey.walls[o.wall_index], data->mount, data->tight_gates);
    panel.detection = calib::DetectWall(panel.points, panel.gate, result.loaded.options.detector,
                                        result.loaded.preset.range_sigma_m, false);
  }
}

// One scan per chosen station (stations spread over the headings), re-read in one pass that
// stops after the last one needed, and detected again around the report's mount.
void CollectPanels(const CalibrationResult& result, const RunState& state, ReportData* data) {
  const std::vector<Station>& stations = data->stations;
  if (!data->have_mount || stations.empty() || result.survey.walls.empty() ||
      !state.pass.open_scans) {
    return;
  }
  std::vector<int> order(stations.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = static_cast<int>(i);
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    return GridHeadingDeg(stations[a].yaw_rad) < GridHeadingDeg(stations[b].yaw_rad);
  });
  const int want = std::min<int>(kMaxScanPanels, static_cast<int>(order.size()));
  std::set<int> chosen;
  for (int k = 0; k < want; ++k) {
    const int at = want == 1 ? static_cast<int>(order.size()) / 2
                             : static_cast<int>(std::lround(k * (order.size() - 1.0) / (want - 1.0)));
    chosen.insert(order[at]);
  }
  for (int station : chosen) {
    const std::vector<int>& obs = stations[station].observations;
    ScanPanel panel;
    panel.station = station;
    panel.observation = obs[obs.size() / 2];  // the middle of the dwell
    data->panels.push_back(panel);
  }
  std::sort(data->panels.begin(), data->panels.end(), [&](const ScanPanel& a, const ScanPanel& b) {
    return GridHeadingDeg(stations[a.station].yaw_rad) < GridHeadingDeg(stations[b.station].yaw_rad);
  });
  std::map<int, size_t> panel_of_scan;
  for (size_t i = 0; i < data->panels.size(); ++i) {
    panel_of_scan[result.solve.observations[data->panels[i].observation].scan_index] = i;
  }
  const calib::DetectorOptions& detector = result.loaded.options.detector;
  try {
    const std::unique_ptr<io::ScanSource> scans = state.pass.open_scans();
    io::ScanRecord scan;
    int index = -1;
    const int last = panel_of_scan.rbegin()->first;
    while (index < last && scans->Next(&scan)) {
      ++index;
      const auto it = panel_of_scan.find(index);
      if (it == panel_of_scan.end()) continue;
      ScanPanel& panel = data->panels[it->second];
      panel.have_scan = true;
      panel.line = scan.line;
      panel.points = calib::ToScanPoints(scan, result.loaded.preset, detector.min_range_m,
                                         detector.mixed_pixel_jump_m, nullptr);
    }
  } catch (const io::InputError& error) {
    data->notes.push_back(std::string("the scans could not be read again: ") + error.what());
  }
  DetectPanels(result, data);
}

// The accumulator of the middle panel over a window wider than the gates.
void CollectHough(const CalibrationResult& result, ReportData* data) {
  data->hough = HoughView();
  if (data->panels.empty()) return;
  const int index = static_cast<int>(data->panels.size() / 2);
  const ScanPanel& panel = data->panels[static_cast<size_t>(index)];
  if (!panel.have_scan) return;
  const calib::WallObservation& o = result.solve.observations[panel.observation];
  const calib::Gates window{std::max(4.0 * kDegToRad, data->tight_gates.angle_rad),
                            std::max(0.8, data->tight_gates.offset_m), true};
  data->hough.panel = index;
  data->hough.window = calib::GateFor(o, result.survey.walls[o.wall_index], data->mount, window);
  data->hough.detection =
      calib::DetectWall(panel.points, data->hough.window, result.loaded.options.detector,
                        result.loaded.preset.range_sigma_m, true);
  data->hough.have = true;
}

// The simulator's truth.yaml beside session.yaml, when there is one: its `truth:` mount, or for
// one scanner of several its own entry of `simulation.scanners`.
void CollectTruth(const CalibrationResult& result, ReportData* data) {
  const fs::path truth_file = fs::path(result.loaded.session.dir) / "truth.yaml";
  std::error_code error;
  if (!fs::is_regular_file(truth_file, error)) return;
  try {
    std::optional<io::TruthMount> truth;
    if (result.loaded.session.scanner_id.empty()) {
      truth = io::ReadTruthMount(truth_file.string());
    } else {
      truth = io::ReadTruthScannerMount(truth_file.string(), result.loaded.session.scanner_id);
    }
    if (truth) data->truth = calib::Mount{truth->x_m, truth->y_m, truth->yaw_rad};
  } catch (const io::InputError&) {
    // Not a simulator's truth: nothing to show.
  }
}

}  // namespace

ReportData CollectReportData(const CalibrationResult& result, const RunState& state) {
  ReportData data;
  data.collected = true;
  ChooseMount(result, &data);
  data.tight_gates = TightGates(result);
  data.stations = FindStations(result, data.mount);
  CollectSiteMap(result, state, &data);
  CollectPanels(result, state, &data);
  CollectHough(result, &data);
  CollectTruth(result, &data);
  return data;
}

ReportData ReportAround(const CalibrationResult& result, const calib::Mount& mount,
                        const std::string& mount_source) {
  ReportData data = result.report;
  if (!data.collected) return data;
  data.mount = mount;
  data.mount_source = mount_source;
  data.have_mount = true;
  for (Station& station : data.stations) station.scanner_local_m = ScannerAtStation(station, mount);
  DetectPanels(result, &data);
  CollectHough(result, &data);
  return data;
}

}  // namespace wallcal::pipeline
