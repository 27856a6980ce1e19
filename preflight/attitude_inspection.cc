// SPDX-License-Identifier: Apache-2.0
// The attitude stream in the inspect reports: what gives it, its rate and gaps, the range of
// roll and pitch, the σ it gives, and what was skipped.
#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/angles.h"
#include "common/statistics.h"
#include "preflight/internal/inspect_internal.h"
#include "recording/attitude_stream.h"
#include "recording/recording.h"

namespace wallcal::preflight::internal {
namespace {

// Min and max of the finite values (NaN, NaN without any).
void Range(const std::vector<double>& values, double* min, double* max) {
  *min = *max = io::kNaN;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    if (!std::isfinite(*min) || v < *min) *min = v;
    if (!std::isfinite(*max) || v > *max) *max = v;
  }
}

std::string Degrees(double angle_rad, const char* format) {
  return std::isfinite(angle_rad) ? Fmt(format, angle_rad * kRadToDeg) + "°" : std::string("-");
}

}  // namespace

AttitudeSummary SummariseAttitude(const std::string& path, const std::string& topic,
                                  const io::NmeaLog& log) {
  AttitudeSummary s;
  std::vector<double> stamps, roll, pitch, roll_sigma, pitch_sigma;
  std::vector<int> lines;
  for (const io::AttitudeSample& a : log.attitudes) {
    stamps.push_back(a.stamp_s);
    lines.push_back(a.line);
    roll.push_back(a.roll_rad);
    pitch.push_back(a.pitch_rad);
    if (std::isfinite(a.roll_sigma_rad)) roll_sigma.push_back(a.roll_sigma_rad);
    if (std::isfinite(a.pitch_sigma_rad)) pitch_sigma.push_back(a.pitch_sigma_rad);
    s.roll_samples += std::isfinite(a.roll_rad);
    s.pitch_samples += std::isfinite(a.pitch_rad);
    s.without_sigma += !std::isfinite(a.roll_sigma_rad) && !std::isfinite(a.pitch_sigma_rad);
  }
  s.stats = ComputeStreamStats("attitude", path, stamps, lines);
  for (const auto& [source, count] : log.attitudes_by_source) {
    s.source += (s.source.empty() ? "" : ", ") + source + " " + std::to_string(count);
  }
  if (!topic.empty()) s.source = "topic " + topic + (s.source.empty() ? "" : ": " + s.source);
  if (s.source.empty()) s.source = "no sample";
  Range(roll, &s.roll_min_rad, &s.roll_max_rad);
  Range(pitch, &s.pitch_min_rad, &s.pitch_max_rad);
  s.roll_sigma_median_rad = UpperMedian(roll_sigma, io::kNaN);
  s.pitch_sigma_median_rad = UpperMedian(pitch_sigma, io::kNaN);
  s.skipped = log.skipped;
  return s;
}

std::string FormatAttitude(const AttitudeSummary& s, bool with_skips) {
  std::ostringstream out;
  StreamStats stats = s.stats;
  stats.name = "attitude (" + s.source + ")";
  out << FormatStream(stats) << FormatAttitudeValues(s);
  if (with_skips) out << "    skipped   " << DescribeSkips(s.skipped) << "\n";
  return out.str();
}

std::string FormatAttitudeValues(const AttitudeSummary& s) {
  std::ostringstream out;
  if (s.stats.records > 0) {
    out << "    roll      " << Degrees(s.roll_min_rad, "%+.2f") << " .. "
        << Degrees(s.roll_max_rad, "%+.2f") << " (" << s.roll_samples
        << " samples; + right side down)\n";
    out << "    pitch     " << Degrees(s.pitch_min_rad, "%+.2f") << " .. "
        << Degrees(s.pitch_max_rad, "%+.2f") << " (" << s.pitch_samples << " samples; + nose up)\n";
    out << "    sigma     ";
    if (s.without_sigma == s.stats.records) {
      out << "none given";
    } else {
      out << "median roll " << Degrees(s.roll_sigma_median_rad, "%.3f") << ", pitch "
          << Degrees(s.pitch_sigma_median_rad, "%.3f") << " (the stream's)";
      if (s.without_sigma > 0) out << "; " << s.without_sigma << " samples without";
    }
    if (std::isfinite(s.default_sigma_rad) && s.without_sigma > 0) {
      out << "; attitude.sigma_deg " << Degrees(s.default_sigma_rad, "%.3f") << " stands in";
    }
    out << "\n";
  }
  return out.str();
}

void InspectSessionAttitude(const io::SessionSpec& spec, const SessionLogs& logs,
                            SessionInspection* result, std::ostream& out) {
  if (spec.attitude_log.empty()) {
    out << "  attitude  none (no attitude: in session.yaml)\n";
    return;
  }
  const bool recorded = recording::IsRecording(spec.attitude_log);
  io::NmeaLog log;
  try {
    log = recording::ReadAttitudeLog(spec);
  } catch (const io::InputError& e) {
    result->blockers.push_back(std::string("attitude: ") + e.what());
    out << "  attitude: unreadable: " << e.what() << "\n";
    return;
  }
  AttitudeSummary summary =
      SummariseAttitude(spec.attitude_log, recorded ? spec.attitude_topic : "", log);
  summary.default_sigma_rad = spec.attitude_sigma_rad;
  // A log shared with GNSS or heading has its skipped lines listed there already.
  const bool own_log =
      recorded || (spec.attitude_log != spec.heading_log && spec.attitude_log != spec.gnss_log);
  out << FormatAttitude(summary, own_log);
  if (own_log) {
    if (const int64_t bad = WorrisomeSkips(log.skipped); bad > 0) {
      result->warnings.push_back(FileName(spec.attitude_log) + ": " + std::to_string(bad) +
                                 " attitude lines skipped (" + DescribeSkips(log.skipped) + ")");
    }
  }
  if (logs.scans && logs.scans->stats.records > 0) {
    const Interval scan_span{logs.scans->stats.start_s, logs.scans->stats.end_s};
    const Interval overlap =
        Intersect(scan_span, Interval{summary.stats.start_s, summary.stats.end_s});
    out << "    overlap   scans & attitude " << FormatOverlap(overlap) << "\n";
    if (!overlap.Valid()) {
      result->warnings.push_back(
          "the attitude stream does not overlap the scans in time (attitude " +
          FormatStamp(summary.stats.start_s) + " .. " + FormatStamp(summary.stats.end_s) +
          "): check attitude.time_offset_s");
    }
  }
}

}  // namespace wallcal::preflight::internal
