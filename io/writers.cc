#include "io/writers.h"

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
#include <utility>

#include "io/config_fields.h"
#include "io/input_file.h"
#include "common/angles.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
// printf into a std::string; YAML spells non-finite numbers .nan / .inf.
template <class... Args>
std::string Format(const char* format, Args... args) {
  char buffer[128];
  const int n = std::snprintf(buffer, sizeof(buffer), format, args...);
  if (n < 0) return std::string();
  if (static_cast<size_t>(n) < sizeof(buffer)) return std::string(buffer, static_cast<size_t>(n));
  std::string text(static_cast<size_t>(n) + 1, '\0');
  std::snprintf(text.data(), text.size(), format, args...);
  text.resize(static_cast<size_t>(n));
  return text;
}

std::string YamlNumber(const char* format, double value) {
  if (std::isnan(value)) return ".nan";
  if (std::isinf(value)) return value > 0 ? ".inf" : "-.inf";
  return Format(format, value);
}

// Shortest text that reads back to the same double (configs written for machines and people).
std::string ShortestNumber(double value) {
  if (!std::isfinite(value)) return YamlNumber("%g", value);
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof(buffer), value);
  std::string text(buffer, result.ptr);
  // "8e-04" is a float in YAML 1.2 but a string to YAML 1.1 readers (PyYAML): add the ".0".
  const size_t exponent = text.find('e');
  if (exponent != std::string::npos && text.find('.') == std::string::npos) {
    text.insert(exponent, ".0");
  }
  return text;
}

bool IsPlainYamlText(const std::string& text) {
  if (text.empty()) return false;
  if (!(std::isalpha(static_cast<unsigned char>(text[0])) || text[0] == '_')) return false;
  for (char c : text) {
    const bool ok =
        std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.' || c == '/';
    if (!ok) return false;
  }
  // Words YAML would read as booleans or null.
  std::string lower(text);
  std::transform(lower.begin(), lower.end(), lower.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  static const char* const kReserved[] = {"true", "false", "yes", "no", "on",
                                          "off",  "null",  "y",   "n"};
  for (const char* word : kReserved) {
    if (lower == word) return false;
  }
  return true;
}

// A YAML scalar for `text`: plain when that reads back as the same text, else double-quoted.
std::string YamlText(const std::string& text) {
  if (IsPlainYamlText(text)) return text;
  std::string quoted = "\"";
  for (size_t i = 0; i < text.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    if (c >= 0x80) {
      // offsets.yaml is UTF-8: a valid sequence goes as it is, any other byte (a folder name in
      // Latin-1) as \xNN, which a YAML reader turns into that code point.
      const size_t n = Utf8SequenceLength(text, i);
      if (n == 0) {
        quoted += Format("\\x%02X", static_cast<unsigned>(c));
      } else {
        quoted.append(text, i, n);
        i += n - 1;
      }
      continue;
    }
    switch (c) {
      case '"':
        quoted += "\\\"";
        break;
      case '\\':
        quoted += "\\\\";
        break;
      case '\n':
        quoted += "\\n";
        break;
      case '\t':
        quoted += "\\t";
        break;
      case '\r':
        quoted += "\\r";
        break;
      default:
        if (c < 0x20 || c == 0x7f) {
          quoted += Format("\\x%02X", static_cast<unsigned>(c));
        } else {
          quoted += static_cast<char>(c);
        }
    }
  }
  quoted += "\"";
  return quoted;
}

// Always a double-quoted YAML scalar (free text: paths, command-line words, times).
std::string YamlQuoted(const std::string& text) {
  // Always double-quoted, escaped as YamlText escapes (control characters, bytes that are not
  // UTF-8 as \xNN).
  const std::string quoted = YamlText(text);
  return quoted.front() == '"' ? quoted : "\"" + quoted + "\"";
}

// The writing visitor of config_fields.h: collects `key: value` pairs; lists become one flow
// map per item.
class FieldWriter {
 public:
  struct Entry {
    std::string key;
    std::string value;               // scalar text, or empty for a list
    std::vector<std::string> items;  // flow maps of a list
    bool is_list = false;
  };

  void Number(const std::string& key, double& value) { Add(key, ShortestNumber(value)); }
  void Scaled(const std::string& key, double& value, double file_per_unit) {
    Add(key, ShortestNumber(value * file_per_unit));
  }
  void Integer(const std::string& key, int& value) { Add(key, std::to_string(value)); }
  void Boolean(const std::string& key, bool& value) { Add(key, value ? "true" : "false"); }
  void Text(const std::string& key, std::string& value) { Add(key, YamlText(value)); }
  template <class T, class F>
  void List(const std::string& key, std::vector<T>& items, F visit_item) {
    Entry entry;
    entry.key = key;
    entry.is_list = true;
    for (T& item : items) {
      FieldWriter item_writer;
      visit_item(item_writer, item);
      entry.items.push_back(item_writer.Flow());
    }
    entries_.push_back(std::move(entry));
  }

  void Add(const std::string& key, const std::string& value) {
    Entry entry;
    entry.key = key;
    entry.value = value;
    entries_.push_back(std::move(entry));
  }

  // "{a: 1, b: 2}" (lists inside are not expected here).
  std::string Flow() const {
    std::string text = "{";
    for (size_t i = 0; i < entries_.size(); ++i) {
      if (i > 0) text += ", ";
      text += entries_[i].key + ": " + entries_[i].value;
    }
    return text + "}";
  }

  // One key a line at `indent` spaces.
  std::string Block(int indent) const {
    const std::string pad(static_cast<size_t>(indent), ' ');
    std::string text;
    for (const Entry& entry : entries_) {
      if (!entry.is_list) {
        text += pad + entry.key + ": " + entry.value + "\n";
      } else if (entry.items.empty()) {
        text += pad + entry.key + ": []\n";
      } else {
        text += pad + entry.key + ":\n";
        for (const std::string& item : entry.items) text += pad + "  - " + item + "\n";
      }
    }
    return text;
  }

 private:
  std::vector<Entry> entries_;
};

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

// WriteFileAtomically lives in io/output_file.cc with the other output-safety rules.

std::string FormatOffsetsYaml(const OffsetsDocument& doc) {
  const double* c = doc.covariance;
  auto stddev = [](double variance) { return variance >= 0.0 ? std::sqrt(variance) : kNaN; };
  const double yaw_deg = doc.yaw_rad * kRadToDeg;
  std::string out;
  out +=
      "# Mount of the scanner in the vehicle (GNSS antenna) frame: x forward, y left, yaw ccw.\n";
  out += "scanner_mount:\n";
  out += "  parent_frame: " + YamlText(doc.parent_frame) + "\n";
  out += "  child_frame: " + YamlText(doc.child_frame) + "\n";
  out += "  x: " + YamlNumber("%.6f", doc.x_m) + "  # m\n";
  out += "  y: " + YamlNumber("%.6f", doc.y_m) + "  # m\n";
  out += "  yaw: " + YamlNumber("%.8f", doc.yaw_rad) + "  # rad\n";
  out += "  yaw_deg: " + YamlNumber("%.4f", yaw_deg) + "\n";
  if (doc.sigma_known) {
    out += "  stddev: {x: " + YamlNumber("%.6f", stddev(c[0])) +
           ", y: " + YamlNumber("%.6f", stddev(c[4])) +
           ", yaw_deg: " + YamlNumber("%.4f", stddev(c[8]) * kRadToDeg) + "}\n";
    out += "  covariance: [";
    for (int i = 0; i < 9; ++i) {
      if (i > 0) out += ", ";
      out += YamlNumber("%.6e", c[i]);
    }
    out += "]  # 3x3 row-major, order x, y, yaw (m, m, rad)\n";
  } else {
    out += "  stddev: null  # not computed by this method: see warnings\n";
    out += "  covariance: null\n";
  }
  // Barawid et al. 2007 put x lateral to the right and y forward: a = -y, b = x, delta = yaw.
  out += "barawid_2007_notation: {a: " + YamlNumber("%.6f", -doc.y_m) +
         ", b: " + YamlNumber("%.6f", doc.x_m) + ", delta_deg: " + YamlNumber("%.4f", yaw_deg) +
         "}\n";
  out += "quality:\n";
  out += "  scans_total: " + std::to_string(doc.scans_total) + "\n";
  out += "  scans_used: " + std::to_string(doc.scans_used) + "\n";
  out += "  headings_deg: {min: " + YamlNumber("%.4f", doc.heading_min_deg) +
         ", max: " + YamlNumber("%.4f", doc.heading_max_deg) + "}\n";
  out += "  residual_rms_m: " + YamlNumber("%.6f", doc.residual_rms_m) + "\n";
  for (const auto& [key, value] : doc.quality_extra) {
    out += "  " + YamlText(key) + ": " + value + "\n";
  }
  if (doc.warnings.empty()) {
    out += "warnings: []\n";
  } else {
    out += "warnings:\n";
    for (const std::string& warning : doc.warnings) {
      // Always quoted: a warning is free text and may hold ':' or '#'.
      std::string quoted = YamlText(warning);
      if (quoted.front() != '"') quoted = "\"" + quoted + "\"";
      out += "  - " + quoted + "\n";
    }
  }
  for (const auto& [key, value] : doc.sections) out += YamlText(key) + ": " + value + "\n";
  out += "method: " + YamlText(doc.method) + "\n";
  out += "source:\n";
  out += "  session: " + YamlQuoted(doc.session) + "\n";
  out += "  tool_version: " + YamlQuoted(doc.tool_version) + "\n";
  if (!doc.created_utc.empty()) out += "  created_utc: " + YamlQuoted(doc.created_utc) + "\n";
  if (!doc.command_line.empty()) {
    out += "  command_line: [";
    for (size_t i = 0; i < doc.command_line.size(); ++i) {
      out += (i ? ", " : "") + YamlQuoted(doc.command_line[i]);
    }
    out += "]\n";
  }
  if (!doc.inputs.empty()) {
    out += "  inputs:\n";
    for (const InputFileDigest& input : doc.inputs) {
      out += "    - {role: " + YamlQuoted(input.role) + ", path: " + YamlQuoted(input.path) +
             ", sha256: " + (input.sha256.empty() ? std::string("null") : input.sha256) + "}\n";
    }
  }
  return out;
}

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

std::string FormatSurveyCsv(const std::vector<SurveyPoint>& points) {
  std::string out = "id,x,y,z,code\n";
  for (const SurveyPoint& point : points) {
    out +=
        point.id + Format(",%.4f,%.4f,%.4f,", point.x_m, point.y_m, point.z_m) + point.code + "\n";
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
  out += "scanner:\n";
  out += "  model: " + YamlText(spec.scanner_model) + "\n";
  out += "  log: " + YamlText(RelativeTo(spec.dir, spec.scanner_log)) + "\n";
  out += "  time_offset_s: " + ShortestNumber(spec.scanner_time_offset_s) + "\n";
  if (spec.mount_guess) {
    out += "  mount_guess: {x: " + ShortestNumber(spec.mount_guess->x_m) +
           ", y: " + ShortestNumber(spec.mount_guess->y_m) +
           ", yaw_deg: " + ShortestNumber(spec.mount_guess->yaw_rad * kRadToDeg) + "}\n";
  }
  out += "gnss:\n";
  out += "  log: " + YamlText(RelativeTo(spec.dir, spec.gnss_log)) + "\n";
  out += "  min_fix_quality: " + std::to_string(spec.min_fix_quality) + "\n";
  out += "heading:\n";
  out += "  log: " + YamlText(RelativeTo(spec.dir, spec.heading_log)) + "\n";
  out += std::string("  reference: ") +
         (spec.heading_reference == HeadingReference::kGridNorth ? "grid_north" : "true_north") +
         "\n";
  out += "survey:\n";
  out += "  points: " + YamlText(RelativeTo(spec.dir, spec.survey_points)) + "\n";
  out += "  control:\n";
  for (const ControlPoint& point : spec.control) {
    out += "    - {id: " + YamlText(point.id) + ", lat: " + ShortestNumber(point.lat_deg) +
           ", lon: " + ShortestNumber(point.lon_deg) + ", h: " + ShortestNumber(point.h_m) + "}\n";
  }
  if (spec.survey_rotation_rad) {
    out += "  rotation_deg: " + ShortestNumber(*spec.survey_rotation_rad * kRadToDeg) + "\n";
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

std::string FormatTruthYaml(const SimulationConfig& config, uint64_t seed) {
  SimulationConfig copy = config;  // the visitor takes mutable references
  FieldWriter simulation;
  fields::VisitSimulation(simulation, copy);
  std::string out;
  out += "# The true mount and every setting the simulator used (wallcal simulate).\n";
  out += "truth:  # scanner in the vehicle frame: x forward, y left (m), yaw ccw\n";
  out += "  x: " + ShortestNumber(config.mount_x_m) + "\n";
  out += "  y: " + ShortestNumber(config.mount_y_m) + "\n";
  out += "  yaw: " + ShortestNumber(config.mount_yaw_rad) + "\n";
  out += "  yaw_deg: " + ShortestNumber(config.mount_yaw_rad * kRadToDeg) + "\n";
  out += "seed: " + std::to_string(seed) + "\n";
  out += "simulation:\n";
  out += simulation.Block(2);
  // The per-stream delays and the characterisation keys only when set: older scenarios'
  // truth.yaml stays as it was.
  for (const auto& [key, value] :
       {std::pair<const char*, double>{"gnss_latency_s", config.gnss_latency_s},
        {"gnss_jitter_s", config.gnss_jitter_s},
        {"heading_latency_s", config.heading_latency_s},
        {"scanner_latency_s", config.scanner_latency_s}}) {
    if (value != 0.0) out += std::string("  ") + key + ": " + ShortestNumber(value) + "\n";
  }
  if (config.station_distance_far_m != 0.0) {
    out += "  station_distance_far_m: " + ShortestNumber(config.station_distance_far_m) + "\n";
  }
  if (config.drive_reverse_m != 0.0) {
    out += "  drive_reverse_m: " + ShortestNumber(config.drive_reverse_m) + "\n";
  }
  if (config.weave_turn_rad != 0.0) {
    out += "  weave_turn_deg: " + ShortestNumber(config.weave_turn_rad * kRadToDeg) + "\n";
  }
  if (config.HasScannerTruth()) {
    std::string truth;
    auto add = [&truth](const char* key, double value) {
      if (std::isnan(value)) return;
      truth += std::string(truth.empty() ? "" : ", ") + key + ": " + ShortestNumber(value);
    };
    add("n", config.truth_scale_n);
    add("c_m", config.truth_offset_c_m);
    add("sigma_m", config.truth_sigma_m);
    add("resolution_m", config.truth_resolution_m);
    add("max_incidence_deg", config.truth_max_incidence_rad * kRadToDeg);
    truth += std::string(truth.empty() ? "" : ", ") +
             "drift: {amplitude_m: " + ShortestNumber(config.truth_drift_amplitude_m) +
             ", time_constant_s: " + ShortestNumber(config.truth_drift_time_constant_s) + "}";
    out += "  scanner_truth: {" + truth + "}\n";
  }
  return out;
}

std::string NmeaChecksum(const std::string& body) {
  unsigned char sum = 0;
  for (char c : body) sum ^= static_cast<unsigned char>(c);
  return Format("%02X", static_cast<unsigned>(sum));
}

std::string FormatScannerPreset(const ScannerPreset& preset,
                                const std::vector<std::string>& comment_lines) {
  std::string out;
  for (const std::string& line : comment_lines) out += "# " + line + "\n";
  auto number = [&out](const char* key, double value) {
    out += std::string(key) + ": " + ShortestNumber(value) + "\n";
  };
  out += "name: " + YamlText(preset.name) + "\n";
  out += "source: " + YamlText(preset.source) + "\n";
  out += "num_beams: " + std::to_string(preset.num_beams) + "\n";
  number("start_angle_deg", preset.start_angle_rad * kRadToDeg);
  number("angular_step_deg", preset.angular_step_rad * kRadToDeg);
  number("rate_hz", preset.rate_hz);
  number("min_range_m", preset.min_range_m);
  number("max_range_m", preset.max_range_m);
  number("error_codes_below_m", preset.error_codes_below_m);
  out += std::string("max_range_is_no_return: ") +
         (preset.max_range_is_no_return ? "true" : "false") + "\n";
  number("range_resolution_m", preset.range_resolution_m);
  out += "range_correction: {k: " + ShortestNumber(preset.range_scale_k) +
         ", b_m: " + ShortestNumber(preset.range_offset_b_m) + "}\n";
  out += "simulation: {n: " + ShortestNumber(preset.sim_scale_n) +
         ", c_m: " + ShortestNumber(preset.sim_offset_c_m) +
         ", sigma_m: " + ShortestNumber(preset.range_sigma_m) + "}\n";
  number("max_incidence_deg", preset.max_incidence_rad * kRadToDeg);
  return out;
}

}  // namespace wallcal::io
