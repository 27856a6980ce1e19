// SPDX-License-Identifier: Apache-2.0
#include "io/writers/writers.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <optional>
#include <utility>

#include "io/config/yaml_text.h"
#include "io/input_file.h"
#include "common/format.h"
#include "common/angles.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;

std::string RelativeTo(const std::string& dir, const std::string& path) {
  const fs::path p(path);
  const fs::path relative = p.lexically_relative(dir.empty() ? fs::path(".") : fs::path(dir));
  if (relative.empty()) return path;
  return relative.string();
}

// hhmmss.ss of the UTC time of day of a UNIX time, rounded to 10 ms.
std::string UtcTimeField(double stamp_s) {
  const long long centiseconds = std::llround(stamp_s * 100.0);
  const long long of_day = ((centiseconds % 8640000LL) + 8640000LL) % 8640000LL;
  const long long seconds = of_day / 100;
  return Format("%02lld%02lld%02lld.%02lld", seconds / 3600, (seconds / 60) % 60, seconds % 60,
                of_day % 100);
}

// ddmm.mmmmmmm (or dddmm.mmmmmmm): 7 decimals of minutes = 1.7e-9 deg, rounded as a whole so
// that 59.99999999' carries into the degrees.
std::string NmeaAngle(double angle_deg, int degree_digits) {
  const long long units_per_minute = 10000000LL;
  const long long total = std::llround(std::abs(angle_deg) * 60.0 * units_per_minute);
  const long long degrees = total / (60 * units_per_minute);
  const long long minute_units = total % (60 * units_per_minute);
  return Format("%0*lld%02lld.%07lld", degree_digits, degrees, minute_units / units_per_minute,
                minute_units % units_per_minute);
}

std::string Sentence(double stamp_s, const std::string& body) {
  return Format("%.3f", stamp_s) + " $" + body + "*" + NmeaChecksum(body);
}

}  // namespace

std::string FormatCarmenRawlaser(const ScanRecord& scan) {
  const size_t n = scan.ranges_m.size();
  const double fov_rad = n > 0 ? scan.angular_step_rad * static_cast<double>(n - 1) : 0.0;
  std::string line = "RAWLASER1 0 " + ShortestNumber(scan.start_angle_rad) + " " +
                     ShortestNumber(fov_rad) + " " + ShortestNumber(scan.angular_step_rad) + " " +
                     ShortestNumber(scan.max_range_m) + " 0.01 0 " + std::to_string(n);
  line.reserve(line.size() + n * 8 + 64);
  char buffer[32];
  for (float range_m : scan.ranges_m) {
    const int length = std::snprintf(buffer, sizeof(buffer), " %.3f", static_cast<double>(range_m));
    line.append(buffer, static_cast<size_t>(std::max(length, 0)));
  }
  const std::string stamp = Format("%.6f", scan.stamp_s);
  line += " 0 " + stamp + " wallcal-sim " + stamp;
  return line;
}

std::string FormatGgaLine(const GnssFix& fix) {
  const std::string hdop = std::isfinite(fix.hdop) ? Format("%.1f", fix.hdop) : std::string();
  const double utc_s = std::isfinite(fix.utc_epoch_s) ? fix.utc_epoch_s : fix.stamp_s;
  const std::string body = "GNGGA," + UtcTimeField(utc_s) + "," + NmeaAngle(fix.lat_deg, 2) +
                           (fix.lat_deg < 0 ? ",S," : ",N,") + NmeaAngle(fix.lon_deg, 3) +
                           (fix.lon_deg < 0 ? ",W," : ",E,") + std::to_string(fix.quality) + "," +
                           Format("%02d", fix.satellites) + "," + hdop + "," +
                           Format("%.4f", fix.height_m) + ",M,0.000,M,,";
  return Sentence(fix.stamp_s, body);
}

std::string FormatGstLine(const GnssFix& fix) {
  auto sigma = [](double value) {
    return std::isfinite(value) ? Format("%.4f", value) : std::string();
  };
  const double major_m = std::max(fix.sigma_lat_m, fix.sigma_lon_m);
  const double minor_m = std::min(fix.sigma_lat_m, fix.sigma_lon_m);
  // Orientation of the major axis from true north: along latitude (0) or longitude (90).
  const double orientation_deg = fix.sigma_lat_m >= fix.sigma_lon_m ? 0.0 : 90.0;
  const double utc_s = std::isfinite(fix.utc_epoch_s) ? fix.utc_epoch_s : fix.stamp_s;
  const std::string body = "GNGST," + UtcTimeField(utc_s) + "," +
                           sigma(std::hypot(fix.sigma_lat_m, fix.sigma_lon_m)) + "," +
                           sigma(major_m) + "," + sigma(minor_m) + "," +
                           Format("%.1f", orientation_deg) + "," + sigma(fix.sigma_lat_m) + "," +
                           sigma(fix.sigma_lon_m) + "," + sigma(2.0 * major_m);
  return Sentence(fix.stamp_s, body);
}

std::string FormatHdtLine(double stamp_s, double heading_rad) {
  double heading_deg = std::fmod(heading_rad * kRadToDeg, 360.0);
  if (heading_deg < 0.0) heading_deg += 360.0;
  std::string value = Format("%.4f", heading_deg);
  if (value == "360.0000") value = "0.0000";
  return Sentence(stamp_s, "HEHDT," + value + ",T");
}

namespace {

// An angle field in degrees with 4 decimals and its sign ("%+.4f"), or nothing for NaN.
std::string SignedDegrees(double angle_rad) {
  return std::isfinite(angle_rad) ? Format("%+.4f", angle_rad * kRadToDeg) : std::string();
}

std::string HeadingDegrees(double heading_rad, const char* format) {
  if (!std::isfinite(heading_rad)) return std::string();
  double heading_deg = std::fmod(heading_rad * kRadToDeg, 360.0);
  if (heading_deg < 0.0) heading_deg += 360.0;
  return Format(format, heading_deg);
}

}  // namespace

std::string FormatPashrLine(const AttitudeSample& sample, double heading_rad) {
  auto sigma = [](double sigma_rad) {
    return std::isfinite(sigma_rad) ? Format("%.4f", sigma_rad * kRadToDeg) : std::string();
  };
  const std::string body =
      "PASHR," + UtcTimeField(sample.stamp_s) + "," + HeadingDegrees(heading_rad, "%.2f") + ",T," +
      SignedDegrees(sample.roll_rad) + "," + SignedDegrees(sample.pitch_rad) + ",0.00," +
      sigma(sample.roll_sigma_rad) + "," + sigma(sample.pitch_sigma_rad) + ",,1,0";
  return Sentence(sample.stamp_s, body);
}

std::string FormatAvrLine(const AttitudeSample& sample, double heading_rad) {
  const bool tilt = std::isfinite(sample.pitch_rad), roll = std::isfinite(sample.roll_rad);
  const std::string body =
      "PTNL,AVR," + UtcTimeField(sample.stamp_s) + "," + HeadingDegrees(heading_rad, "%+.4f") +
      ",Yaw," + SignedDegrees(sample.pitch_rad) + (tilt ? ",Tilt," : ",,") +
      SignedDegrees(sample.roll_rad) + (roll ? ",Roll," : ",,") + "1.000,3,1.5,12";
  return Sentence(sample.stamp_s, body);
}

std::string FormatSurveyCsv(const std::vector<SurveyPoint>& points) {
  std::string out = "id,x,y,z,code\n";
  for (const SurveyPoint& point : points) {
    out +=
        point.id + Format(",%.4f,%.4f,%.4f,", point.x_m, point.y_m, point.z_m) + point.code + "\n";
  }
  return out;
}

std::string FormatRoverSurveyCsv(const std::vector<SurveyPoint>& points) {
  std::string out = "Name,Latitude,Longitude,Ellipsoidal height,Code\n";
  for (const SurveyPoint& point : points) {
    out += point.id + Format(",%.9f,%.9f,%.4f,", point.lat_deg, point.lon_deg, point.z_m) +
           point.code + "\n";
  }
  return out;
}

std::string FormatSessionYaml(const SessionSpec& spec) {
  std::string out;
  out += "name: " + YamlText(spec.name) + "\n";
  if (spec.utm_zone) {
    out += "utm_zone: " + std::to_string(spec.utm_zone->zone) + (spec.utm_zone->north ? "N" : "S") +
           "\n";
  }
  const auto scanner_keys = [&spec, &out](const std::string& indent, const ScannerSpec& scanner) {
    out += indent + "model: " + YamlText(scanner.model) + "\n";
    out += indent + "log: " + YamlText(RelativeTo(spec.dir, scanner.log)) + "\n";
    if (!scanner.topic.empty()) out += indent + "topic: " + YamlText(scanner.topic) + "\n";
    out += indent + "time_offset_s: " + ShortestNumber(scanner.time_offset_s) + "\n";
    if (const std::optional<MountGuess>& guess = scanner.mount_guess) {
      out += indent + "mount_guess: {x: " + ShortestNumber(guess->x_m) +
             ", y: " + ShortestNumber(guess->y_m) +
             ", yaw_deg: " + ShortestScaled(guess->yaw_rad, kRadToDeg) + "}\n";
    }
    if (scanner.z_m) out += indent + "z_m: " + ShortestNumber(*scanner.z_m) + "\n";
    if (scanner.z_sigma_m != kDefaultScannerZSigmaM) {
      out += indent + "z_sigma_m: " + ShortestNumber(scanner.z_sigma_m) + "\n";
    }
    if (scanner.tilt.given) {
      out += indent + "pitch_deg: " + ShortestScaled(scanner.tilt.pitch_rad, kRadToDeg) + "\n";
      out += indent + "roll_deg: " + ShortestScaled(scanner.tilt.roll_rad, kRadToDeg) + "\n";
    }
    if (scanner.tilt.sigma_rad != kDefaultScannerTiltSigmaRad) {
      out += indent + "tilt_sigma_deg: " + ShortestScaled(scanner.tilt.sigma_rad, kRadToDeg) + "\n";
    }
  };
  if (spec.scanners.empty()) {
    out += "scanner:\n";
    ScannerSpec one;
    one.model = spec.scanner_model;
    one.log = spec.scanner_log;
    one.topic = spec.scanner_topic;
    one.time_offset_s = spec.scanner_time_offset_s;
    one.mount_guess = spec.mount_guess;
    one.z_m = spec.scanner_z_m;
    one.z_sigma_m = spec.scanner_z_sigma_m;
    one.tilt = spec.scanner_tilt;
    scanner_keys("  ", one);
  } else {
    out += "scanners:\n";
    for (const ScannerSpec& scanner : spec.scanners) {
      out += "  - id: " + YamlText(scanner.id) + "\n";
      if (scanner.frame != scanner.id) out += "    frame: " + YamlText(scanner.frame) + "\n";
      scanner_keys("    ", scanner);
    }
  }
  out += "gnss:\n";
  out += "  log: " + YamlText(RelativeTo(spec.dir, spec.gnss_log)) + "\n";
  if (!spec.gnss_topic.empty()) {
    out += "  topic: " + YamlText(spec.gnss_topic) + "\n";
    out += "  max_sigma_m: " + ShortestNumber(spec.gnss_max_sigma_m) + "\n";
  }
  out += "  min_fix_quality: " + std::to_string(spec.min_fix_quality) + "\n";
  out += "heading:\n";
  out += "  log: " + YamlText(RelativeTo(spec.dir, spec.heading_log)) + "\n";
  if (!spec.heading_topic.empty()) out += "  topic: " + YamlText(spec.heading_topic) + "\n";
  out += std::string("  reference: ") +
         (spec.heading_reference == HeadingReference::kGridNorth ? "grid_north" : "true_north") +
         "\n";
  if (!spec.attitude_log.empty()) {
    out += "attitude:\n";
    out += "  log: " + YamlText(RelativeTo(spec.dir, spec.attitude_log)) + "\n";
    if (!spec.attitude_topic.empty()) out += "  topic: " + YamlText(spec.attitude_topic) + "\n";
    if (spec.attitude_stamp == StampSource::kReceive) out += "  stamp: receive\n";
    if (spec.attitude_time_offset_s != 0.0) {
      out += "  time_offset_s: " + ShortestNumber(spec.attitude_time_offset_s) + "\n";
    }
    if (spec.attitude_sigma_rad != kDefaultAttitudeSigmaRad) {
      out += "  sigma_deg: " + ShortestScaled(spec.attitude_sigma_rad, kRadToDeg) + "\n";
    }
  }
  out += "survey:\n";
  out += "  points: " + YamlText(RelativeTo(spec.dir, spec.survey_points)) + "\n";
  if (!spec.control.empty()) out += "  control:\n";
  for (const ControlPoint& point : spec.control) {
    out += "    - {id: " + YamlText(point.id) + ", lat: " + ShortestNumber(point.lat_deg) +
           ", lon: " + ShortestNumber(point.lon_deg) + ", h: " + ShortestNumber(point.h_m) + "}\n";
  }
  if (spec.survey_rotation_rad) {
    out += "  rotation_deg: " + ShortestScaled(*spec.survey_rotation_rad, kRadToDeg) + "\n";
  }
  if (spec.survey_point_sigma_m) {
    out += "  point_sigma_m: " + ShortestNumber(*spec.survey_point_sigma_m) + "\n";
  }
  out += "walls:\n";
  for (const WallSpec& wall : spec.walls) {
    out += "  - {id: " + YamlText(wall.id) + ", code: " + YamlText(wall.code) + "}\n";
  }
  if (spec.antenna_in_base) {
    out += "antenna_in_base: {x: " + ShortestNumber(spec.antenna_in_base->x_m) +
           ", y: " + ShortestNumber(spec.antenna_in_base->y_m) +
           ", z: " + ShortestNumber(spec.antenna_in_base->z_m) + "}\n";
  }
  return out;
}

std::string NmeaChecksum(const std::string& body) {
  unsigned char sum = 0;
  for (char c : body) sum ^= static_cast<unsigned char>(c);
  return Format("%02X", static_cast<unsigned>(sum));
}

}  // namespace wallcal::io
