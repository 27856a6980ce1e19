// SPDX-License-Identifier: Apache-2.0
#include "guide/guide_text.h"

#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "common/format.h"

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

std::string JsonStop(const StopSpec& s) {
  return Format("{\"vehicle_to_wall_deg\": %.1f, \"distance_m\": %.2f, \"dwell_s\": %.0f, "
                "\"wait_s\": %.0f}",
                s.vehicle_to_wall_rad * kRadToDeg, s.distance_m, s.dwell_s, s.wait_s);
}

}  // namespace

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
  out << "  enough     " << (r.enough ? "yes: calibrate this session" : "no") << "\n";
  for (size_t i = 0; i < r.next.size(); ++i) {
    out << (i == 0 ? "  next       " : "             ") << StopLine(r, r.next[i].stop);
    if (r.next[i].after.known) {
      out << Format("  -> σ x %.4f m, y %.4f m, yaw %.3f deg", r.next[i].after.sigma_x_m(),
                    r.next[i].after.sigma_y_m(), r.next[i].after.sigma_yaw_rad() * kRadToDeg);
    }
    out << "\n";
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
  bool first = true;
  if (r.plan) {
    for (const StopSpec& s : r.plan->stops) {
      out << (first ? "" : ", ") << JsonStop(s);
      first = false;
    }
  } else {
    for (const Advice& a : r.next) {
      out << (first ? "" : ", ") << JsonStop(a.stop);
      first = false;
    }
  }
  out << "]}\n";
  return out.str();
}

}  // namespace wallcal::guide
