// SPDX-License-Identifier: Apache-2.0
// inspect --dump: the decoded records of one log as CSV.
#include <algorithm>
#include <optional>
#include <sstream>

#include "calib/range_model.h"
#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/text/carmen_reader.h"
#include "pipeline/config_dirs.h"
#include "preflight/internal/inspect_internal.h"
#include "recording/attitude_stream.h"
#include "recording/recording.h"
#include "recording/recording_streams.h"

namespace wallcal::preflight {

using namespace internal;  // the helpers shared by the inspect files

void Dump(const std::string& path, DumpKind kind, std::ostream& out,
          const std::string& scanner_id) {
  std::string log_path = path;
  std::optional<io::SessionSpec> spec;
  std::optional<io::ScannerPreset> preset;
  if (!scanner_id.empty() && !IsSessionPath(path)) {
    throw io::InputError(path + ": --scanner names a scanner of a session with scanners:; this "
                                "is not a session");
  }
  if (IsSessionPath(path)) {
    spec = io::ReadSession(path);
    if (!scanner_id.empty()) {
      spec = io::SessionForScannerId(*spec, scanner_id);
    } else if (!spec->scanners.empty() && kind == DumpKind::kScans) {
      throw io::InputError(io::Where(spec->file, spec->scanners.front().line,
                                     "lists several scanners; expected --scanner ID with ID "
                                     "one of " + io::ScannerIds(*spec)));
    }
    if (kind == DumpKind::kAttitude && spec->attitude_log.empty()) {
      throw io::InputError(io::Where(spec->file, 0,
                                     "names no attitude stream; expected an attitude: map "
                                     "(docs/session-format.md) for --dump attitude"));
    }
    log_path = kind == DumpKind::kGnss       ? spec->gnss_log
               : kind == DumpKind::kHeading  ? spec->heading_log
               : kind == DumpKind::kAttitude ? spec->attitude_log
                                             : spec->scanner_log;
    if (kind == DumpKind::kScans) preset = pipeline::LoadSessionPreset(spec->scanner_model, spec->dir);
  }
  if (recording::IsRecording(log_path)) {
    if (!spec) return DumpRecording(log_path, kind, std::string(), out);
    WriteDumpCsv(*spec, kind, preset ? &*preset : nullptr, out);
    return;
  }
  const LogKind found = SniffLogKind(log_path);
  const LogKind wanted = kind == DumpKind::kScans ? LogKind::kCarmen : LogKind::kNmea;
  if (found != wanted) {
    const char* what = kind == DumpKind::kGnss       ? "gnss"
                       : kind == DumpKind::kHeading  ? "heading"
                       : kind == DumpKind::kAttitude ? "attitude"
                                                     : "scans";
    throw io::InputError(io::Where(
        log_path, 0,
        std::string("is ") + (found == LogKind::kNmea ? "an NMEA log" : "a CARMEN scan log") +
            "; --dump " + what + " expects " +
            (wanted == LogKind::kNmea ? "an NMEA log" : "a CARMEN scan log")));
  }
  io::SessionSpec log_spec;
  if (spec) log_spec = *spec;
  if (!spec) {
    log_spec.scanner_log = log_spec.gnss_log = log_spec.heading_log = log_path;
    log_spec.attitude_log = log_path;
  }
  WriteDumpCsv(log_spec, kind, preset ? &*preset : nullptr, out);
}

void WriteDumpCsv(const io::SessionSpec& spec, DumpKind kind, const io::ScannerPreset* preset,
                  std::ostream& out) {
  if (kind == DumpKind::kGnss) {
    const io::NmeaLog log = recording::ReadPoseLogs(spec, true, false, false).gnss;
    out << "time_s,lat_deg,lon_deg,height_m,quality,satellites,hdop,sigma_lat_m,sigma_lon_m,line\n";
    for (const io::GnssFix& f : log.fixes) {
      CsvNumber(out, "%.6f", f.stamp_s);
      out << ',';
      CsvNumber(out, "%.10f", f.lat_deg);
      out << ',';
      CsvNumber(out, "%.10f", f.lon_deg);
      out << ',';
      CsvNumber(out, "%.4f", f.height_m);
      out << ',' << f.quality << ',' << f.satellites << ',';
      CsvNumber(out, "%.10g", f.hdop);
      out << ',';
      CsvNumber(out, "%.10g", f.sigma_lat_m);
      out << ',';
      CsvNumber(out, "%.10g", f.sigma_lon_m);
      out << ',' << f.line << '\n';
    }
  } else if (kind == DumpKind::kHeading) {
    const io::NmeaLog log = recording::ReadPoseLogs(spec, false, true, false).headings;
    out << "time_s,heading_deg,line\n";
    for (const io::HeadingSample& h : log.headings) {
      CsvNumber(out, "%.6f", h.stamp_s);
      out << ',';
      CsvNumber(out, "%.9f", h.heading_rad * kRadToDeg);
      out << ',' << h.line << '\n';
    }
  } else if (kind == DumpKind::kAttitude) {
    const io::NmeaLog log = recording::ReadAttitudeLog(spec);
    out << "time_s,roll_deg,pitch_deg,roll_sigma_deg,pitch_sigma_deg,line\n";
    for (const io::AttitudeSample& a : log.attitudes) {
      CsvNumber(out, "%.6f", a.stamp_s);
      for (const double angle_rad :
           {a.roll_rad, a.pitch_rad, a.roll_sigma_rad, a.pitch_sigma_rad}) {
        out << ',';
        CsvNumber(out, "%.9f", angle_rad * kRadToDeg);
      }
      out << ',' << a.line << '\n';
    }
  } else {
    const double offset_s = spec.scanner_time_offset_s;
    const std::unique_ptr<io::ScanSource> reader = recording::MakeScanOpener(spec, preset)();
    io::ScanRecord scan;
    out << "time_s,beams,valid,min_range_m,max_range_m,line\n";
    while (reader->Next(&scan)) {
      int valid = 0;
      float lo = 1e30f, hi = -1.0f;
      if (preset) {
        // Valid per the preset: not an error code, not a no-return, not below its floor.
        calib::RangeCounts counts;
        const calib::ScanPoints points = calib::ToScanPoints(scan, *preset, 0.0, 1e9, &counts);
        valid = static_cast<int>(counts.valid);
        for (int beam : points.beam) {
          const float r = scan.ranges_m[static_cast<size_t>(beam)];
          lo = std::min(lo, r);
          hi = std::max(hi, r);
        }
      } else {
        valid = LogValid(scan, &lo, &hi);
      }
      CsvNumber(out, "%.6f", scan.stamp_s + offset_s);
      out << ',' << scan.ranges_m.size() << ',' << valid << ',';
      if (valid > 0) {
        out << Fmt("%.7g", lo) << ',' << Fmt("%.7g", hi);
      } else {
        out << ',';
      }
      out << ',' << scan.line << '\n';
    }
  }
}

}  // namespace wallcal::preflight
