// SPDX-License-Identifier: Apache-2.0
#include "guide/guide_text.h"

#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "common/format.h"
#include "common/json_text.h"

namespace wallcal::guide {
namespace {

std::string SigmaLine(const Prediction& p, const pipeline::AcceptanceOptions& a) {
  if (!p.known) return "not determined yet";
  return Format("x %.4f m  y %.4f m  yaw %.3f deg   (tolerance %.4f m, %.3f deg)", p.sigma_x_m(),
                p.sigma_y_m(), p.sigma_yaw_rad() * kRadToDeg, a.max_sigma_xy_m,
                a.max_sigma_yaw_rad * kRadToDeg);
}

std::string StopLine(const GuideReport& r, const StopSpec& s) {
  std::string wall = r.wall_ids.size() > 1 ? " at wall " + r.wall_ids[s.wall_index] : "";
  return Format("vehicle-to-wall %+.0f deg, %.1f m from the wall%s, stand %.0f s; go %.0f s after the previous stop ended (stand on there until then)",
                s.vehicle_to_wall_rad * kRadToDeg, s.distance_m, wall.c_str(), s.dwell_s, s.wait_s);
}

std::string Number(double v, const char* format) {
  return std::isfinite(v) ? Format(format, v) : std::string("null");
}

// Shorter than these, a move's part is not worth saying (a driver cannot place a car closer).
constexpr double kSayDistanceM = 0.25;
constexpr double kSayTurnRad = 1.0 / kRadToDeg;

std::string JsonPose(const SitePose& p) {
  return Format("{\"x_m\": %.3f, \"y_m\": %.3f, \"yaw_deg\": %.2f}", p.antenna_local_m.x(),
                p.antenna_local_m.y(), p.yaw_rad * kRadToDeg);
}

std::string JsonSigma(const Prediction& p) {
  if (!p.known) return "null";
  return "{\"x_m\": " + Number(p.sigma_x_m(), "%.6f") + ", \"y_m\": " +
         Number(p.sigma_y_m(), "%.6f") + ", \"yaw_deg\": " +
         Number(p.sigma_yaw_rad() * kRadToDeg, "%.5f") + "}";
}

// One stop: its spec, then (when the report has them) its wall, its target pose, the move to it
// and the instruction in words, and the σ once made.
std::string JsonStop(const GuideReport& r, size_t i, const StopSpec& s, const Prediction* after) {
  std::string out = Format("{\"vehicle_to_wall_deg\": %.1f, \"distance_m\": %.2f, \"dwell_s\": %.0f, "
                           "\"wait_s\": %.0f",
                           s.vehicle_to_wall_rad * kRadToDeg, s.distance_m, s.dwell_s, s.wait_s);
  if (s.wall_index >= 0 && s.wall_index < static_cast<int>(r.wall_ids.size())) {
    out += ", \"wall\": " + JsonString(r.wall_ids[s.wall_index]);
  }
  if (i < r.targets.size()) {
    const StopTarget& t = r.targets[i];
    out += ", \"target\": " + JsonPose(t.pose) + ", \"move\": ";
    out += t.has_move ? Format("{\"forward_m\": %.2f, \"left_m\": %.2f, \"turn_deg\": %.1f}",
                               t.move.forward_m, t.move.left_m, t.move.turn_rad * kRadToDeg)
                      : std::string("null");
    out += ", \"instruction\": " + JsonString(StopInstruction(r, i));
  }
  if (after != nullptr) out += ", \"sigma_after\": " + JsonSigma(*after);
  return out + "}";
}

// The map's part of the object: the walls, the stations' poses, the vehicle and scanner, the
// dwells without a wall.
std::string JsonSite(const GuideReport& r) {
  std::string out = ", \"walls\": [";
  for (size_t w = 0; w < r.walls.size(); ++w) {
    const calib::WallGeometry& wall = r.walls[w];
    out += Format("%s{\"id\": %s, \"a\": [%.3f, %.3f], \"b\": [%.3f, %.3f]}", w ? ", " : "",
                  JsonString(wall.id).c_str(), wall.end_a_local.x(), wall.end_a_local.y(),
                  wall.end_b_local.x(), wall.end_b_local.y());
  }
  out += "], \"station_poses\": [";
  for (size_t i = 0; i < r.stations.size(); ++i) {
    const StationSummary& st = r.stations[i];
    out += Format("%s{\"x_m\": %.3f, \"y_m\": %.3f, \"yaw_deg\": %.2f, \"wall\": %s, "
                  "\"vehicle_to_wall_deg\": %.1f, \"distance_m\": %.2f, \"start_s\": %.1f, "
                  "\"end_s\": %.1f, \"scans\": %lld}",
                  i ? ", " : "", st.pose.antenna_local_m.x(), st.pose.antenna_local_m.y(),
                  st.pose.yaw_rad * kRadToDeg,
                  st.wall_index >= 0 && st.wall_index < static_cast<int>(r.wall_ids.size())
                      ? JsonString(r.wall_ids[st.wall_index]).c_str()
                      : "null",
                  st.vehicle_to_wall_rad * kRadToDeg, st.distance_m, st.start_s, st.end_s,
                  static_cast<long long>(st.scans));
  }
  out += "], \"stops_without_wall\": [";
  for (size_t i = 0; i < r.stops_without_wall.size(); ++i) {
    out += (i ? ", " : "") + JsonPose(r.stops_without_wall[i]);
  }
  out += "], \"vehicle\": ";
  out += r.vehicle ? Format("{\"t_s\": %.1f, ", r.vehicle_s) + JsonPose(*r.vehicle).substr(1)
                   : std::string("null");
  out += ", \"mount\": ";
  out += r.mount ? Format("{\"x_m\": %.4f, \"y_m\": %.4f, \"yaw_deg\": %.3f}", r.mount->x_m,
                          r.mount->y_m, r.mount->yaw_rad * kRadToDeg)
                 : std::string("null");
  out += ", \"scanner_pose\": ";
  out += r.scanner ? Format("{\"x_m\": %.3f, \"y_m\": %.3f, \"yaw_deg\": %.2f}",
                            r.scanner->p_local_m.x(), r.scanner->p_local_m.y(),
                            r.scanner->yaw_rad * kRadToDeg)
                   : std::string("null");
  return out;
}

}  // namespace

std::string MoveWords(const VehicleMove& move) {
  std::string words;
  const auto add = [&words](const std::string& part) { words += (words.empty() ? "" : ", ") + part; };
  if (std::abs(move.forward_m) >= kSayDistanceM) {
    add(Format("%s %.1f m", move.forward_m > 0.0 ? "forward" : "back", std::abs(move.forward_m)));
  }
  if (std::abs(move.left_m) >= kSayDistanceM) {
    add(Format("%.1f m to the %s", std::abs(move.left_m), move.left_m > 0.0 ? "left" : "right"));
  }
  if (std::abs(move.turn_rad) >= kSayTurnRad) {
    add(Format("turn %.0f° %s", std::abs(move.turn_rad) * kRadToDeg,
               move.turn_rad > 0.0 ? "left" : "right"));
  }
  return words.empty() ? "stay where you are" : words;
}

std::string StopInstruction(const GuideReport& r, size_t i) {
  const std::vector<StopSpec>* stops = nullptr;
  std::vector<StopSpec> next;
  if (r.plan) {
    stops = &r.plan->stops;
  } else {
    for (const Advice& a : r.next) next.push_back(a.stop);
    stops = &next;
  }
  if (i >= stops->size()) return "";
  const StopSpec& s = (*stops)[i];
  std::string words;
  if (s.wait_s >= 1.0) words = Format("after %.0f s: ", s.wait_s);
  if (i < r.targets.size() && r.targets[i].has_move) {
    words += MoveWords(r.targets[i].move);
  } else {
    const std::string wall = r.wall_ids.size() > 1 && s.wall_index >= 0 &&
                                     s.wall_index < static_cast<int>(r.wall_ids.size())
                                 ? " " + r.wall_ids[s.wall_index]
                                 : "";
    words += Format("%+.0f° to the wall%s, %.1f m from it", s.vehicle_to_wall_rad * kRadToDeg,
                    wall.c_str(), s.distance_m);
  }
  return words + Format(", stand %.0f s", s.dwell_s);
}

std::string NotEnoughReason(const GuideReport& r) {
  if (r.enough) return "";
  const std::string scanner = r.scanner_id.empty() ? "" : " (scanner " + r.scanner_id + ")";
  if (!r.predicted.known) {
    return "σ not determined yet" + scanner + (r.message.empty() ? "" : ": " + r.message);
  }
  if (r.worst_ratio <= 1.0 || r.forced) {
    // The σ is met, or cannot be trusted: calibrate would refuse (the note says why).
    return "calibrate would refuse" + scanner + (r.message.empty() ? "" : ": " + r.message);
  }
  const Prediction& p = r.predicted;
  switch (r.worst_axis) {
    case SigmaAxis::kX:
      return Format("σ x %.1f mm is over the %.1f mm tolerance", p.sigma_x_m() * 1e3,
                    r.acceptance.max_sigma_xy_m * 1e3) + scanner;
    case SigmaAxis::kY:
      return Format("σ y %.1f mm is over the %.1f mm tolerance", p.sigma_y_m() * 1e3,
                    r.acceptance.max_sigma_xy_m * 1e3) + scanner;
    case SigmaAxis::kYaw:
      return Format("σ yaw %.3f° is over the %.3f° tolerance", p.sigma_yaw_rad() * kRadToDeg,
                    r.acceptance.max_sigma_yaw_rad * kRadToDeg) + scanner;
  }
  return "";
}

std::string GuideText(const GuideReport& r) {
  std::ostringstream out;
  out << "wallcal guide: session '" << r.session_name << "'"
      << (r.scanner_id.empty() ? "" : ", scanner '" + r.scanner_id + "'") << "\n";
  if (r.plan) {
    out << Format("  plan       %.0f min budget: %zu stops, %.0f min\n", r.plan_budget_s / 60.0,
                  r.plan->stops.size(), r.plan->seconds / 60.0);
    for (size_t i = 0; i < r.plan->stops.size(); ++i) {
      out << Format("    %2zu  ", i + 1) << StopLine(r, r.plan->stops[i]) << "\n";
    }
    out << "  predicted  " << SigmaLine(r.predicted, r.acceptance) << "\n";
    if (!r.message.empty()) out << "  note       " << r.message << "\n";
    out << "  enough     " << (r.enough ? "yes" : "no") << "\n";
    return out.str();
  }
  out << Format("  stations   %zu so far over %.0f s", r.stations.size(), r.logged_s);
  if (r.moving_scans > 0) out << Format(" (and %lld scans while driving)", static_cast<long long>(r.moving_scans));
  out << "\n";
  if (!r.stations.empty()) {
    out << "      #   time s   vehicle-to-wall deg   distance m   scans with wall\n";
    for (size_t i = 0; i < r.stations.size(); ++i) {
      const StationSummary& s = r.stations[i];
      out << Format("    %3zu  %7.0f   %19.1f   %10.2f   %15lld\n", i + 1, s.start_s,
                    s.vehicle_to_wall_rad * kRadToDeg, s.distance_m,
                    static_cast<long long>(s.scans));
    }
  }
  out << "  σ now      " << SigmaLine(r.predicted, r.acceptance) << "\n";
  if (!r.message.empty()) out << "  note       " << r.message << "\n";
  for (const GuideWarning& w : r.warnings) out << "  warning    " << w.message << "\n";
  out << "  enough     " << (r.enough ? "yes: calibrate this session" : "no") << "\n";
  for (size_t i = 0; i < r.next.size(); ++i) {
    out << (i == 0 ? "  next       " : "             ") << StopLine(r, r.next[i].stop);
    if (r.next[i].after.known) {
      out << Format("  -> σ x %.4f m, y %.4f m, yaw %.3f deg", r.next[i].after.sigma_x_m(),
                    r.next[i].after.sigma_y_m(), r.next[i].after.sigma_yaw_rad() * kRadToDeg);
    }
    out << "\n";
    if (i < r.targets.size() && r.targets[i].has_move) {
      out << "               " << (i == 0 ? "from here: " : "then: ") << StopInstruction(r, i) << "\n";
    }
  }
  return out.str();
}

std::string GuideJson(const GuideReport& r) {
  std::ostringstream out;
  out << "{\"stations\": " << (r.plan ? r.plan->stops.size() : r.stations.size())
      << ", \"predicted_sigma\": {\"x_m\": " << Number(r.predicted.sigma_x_m(), "%.6f")
      << ", \"y_m\": " << Number(r.predicted.sigma_y_m(), "%.6f")
      << ", \"yaw_deg\": " << Number(r.predicted.sigma_yaw_rad() * kRadToDeg, "%.5f")
      << "}, \"forced\": " << (r.forced ? "true" : "false")
      << ", \"enough\": " << (r.enough ? "true" : "false") << ", \"next\": [";
  if (r.plan) {
    for (size_t i = 0; i < r.plan->stops.size(); ++i) {
      out << (i ? ", " : "") << JsonStop(r, i, r.plan->stops[i], nullptr);
    }
  } else {
    for (size_t i = 0; i < r.next.size(); ++i) {
      out << (i ? ", " : "") << JsonStop(r, i, r.next[i].stop, &r.next[i].after);
    }
  }
  out << "], \"session\": " << JsonString(r.session_name)
      << ", \"scanner\": " << (r.scanner_id.empty() ? "null" : JsonString(r.scanner_id))
      << Format(", \"tolerance\": {\"xy_m\": %.6f, \"yaw_deg\": %.5f}",
                r.acceptance.max_sigma_xy_m, r.acceptance.max_sigma_yaw_rad * kRadToDeg)
      << ", \"worst_axis\": " << (r.predicted.known ? JsonString(SigmaAxisName(r.worst_axis)) : "null")
      << ", \"worst_ratio\": " << Number(r.worst_ratio, "%.4f")
      << ", \"reason\": " << JsonString(NotEnoughReason(r))
      << ", \"message\": " << JsonString(r.message)
      << Format(", \"logged_s\": %.1f", r.logged_s)
      << ", \"sigma_ellipse\": "
      << (r.predicted.known ? Format("{\"major_m\": %.6f, \"minor_m\": %.6f, \"angle_deg\": %.2f}",
                                     r.ellipse.major_m, r.ellipse.minor_m,
                                     r.ellipse.angle_rad * kRadToDeg)
                            : std::string("null"))
      << JsonSite(r) << ", \"warnings\": [";
  for (size_t i = 0; i < r.warnings.size(); ++i) {
    const GuideWarning& w = r.warnings[i];
    out << (i ? ", " : "") << "{\"kind\": " << JsonString(GuideWarningKindName(w.kind))
        << ", \"subject\": " << JsonString(w.subject) << ", \"message\": " << JsonString(w.message)
        << "}";
  }
  out << "], \"plan\": ";
  if (r.plan) {
    out << Format("{\"budget_min\": %.2f, \"minutes\": %.2f}", r.plan_budget_s / 60.0,
                  r.plan->seconds / 60.0);
  } else {
    out << "null";
  }
  out << "}\n";
  return out.str();
}

}  // namespace wallcal::guide
