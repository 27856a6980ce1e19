// SPDX-License-Identifier: Apache-2.0
#include "io/config/session_reader.h"

#include <cmath>
#include <map>
#include <utility>

#include "io/config/internal/yaml_map_reader.h"

namespace wallcal::io {
namespace {

using namespace yaml_detail;  // NOLINT: this file's own YAML helpers

// scanner.z_m beyond this is no scanner's height relative to the antenna on a vehicle: a value
// in millimetres, or the antenna's height above the ground.
constexpr double kMaxScannerHeightM = 10.0;
// scanner.pitch_deg / roll_deg beyond this are no mount of a scanner that looks for walls.
constexpr double kMaxScannerTiltDeg = 45.0;

// `topic:` (a recording's topic name) and `stamp: header|receive` of scanner, gnss, heading.
void ReadTopicKeys(MapReader& map, std::string* topic, StampSource* stamp) {
  if (const YAML::Node t = map.Find("topic"); t.IsDefined()) *topic = map.ToText(t, "topic");
  if (const YAML::Node st = map.Find("stamp"); st.IsDefined()) {
    const std::string text = st.IsScalar() ? st.Scalar() : "";
    if (text == "header") {
      *stamp = StampSource::kHeader;
    } else if (text == "receive") {
      *stamp = StampSource::kReceive;
    } else {
      map.Bad(st, "stamp", "header (the message's header.stamp) or receive (the recorder's time)");
    }
  }
}

std::string ResolvePath(const std::string& dir, const std::string& relative) {
  const fs::path p(relative);
  if (p.is_absolute()) return p.lexically_normal().string();
  return (fs::path(dir) / p).lexically_normal().string();
}

UtmZone ParseUtmZone(MapReader& reader, const YAML::Node& value) {
  // "54N", "33S", "54 n": zone number 1..60 and hemisphere letter.
  const std::string text = value.IsScalar() ? value.Scalar() : "";
  size_t i = 0;
  int zone = 0;
  while (i < text.size() && std::isdigit(static_cast<unsigned char>(text[i])) && zone <= 60) {
    zone = zone * 10 + (text[i] - '0');
    ++i;
  }
  const size_t digits = i;
  while (i < text.size() && text[i] == ' ') ++i;
  const char letter = i + 1 == text.size()
                          ? static_cast<char>(std::toupper(static_cast<unsigned char>(text[i])))
                          : '\0';
  if (digits == 0 || zone < 1 || zone > 60 || (letter != 'N' && letter != 'S')) {
    reader.Bad(value, "utm_zone", "a zone 1..60 and N or S, like 54N or 33S");
  }
  UtmZone utm;
  utm.zone = zone;
  utm.north = letter == 'N';
  return utm;
}

ControlPoint ReadControlPoint(MapReader& survey, const YAML::Node& item, size_t index) {
  const std::string name = "control[" + std::to_string(index) + "]";
  if (!item.IsMap()) survey.Bad(item, name, "{id, lat, lon, h}");
  MapReader entry(item, survey.file(), survey.Name(name + "."), LineOf(item));
  entry.Allow({"id", "lat", "lon", "h"});
  entry.Finish();
  ControlPoint point;
  point.line = LineOf(item);
  point.id = entry.ToText(entry.Require("id", "the survey id of the control point"), "id");
  const YAML::Node lat = entry.Require("lat", "the WGS84 latitude in degrees");
  point.lat_deg = entry.ToNumber(lat, "lat");
  // The local frame is a UTM projection, which ends at 84° N and 80° S.
  if (point.lat_deg > 84.0 || point.lat_deg < -80.0) {
    entry.Bad(lat, "lat", "a latitude in [-80, 84] degrees (the UTM grid the tool works in)");
  }
  const YAML::Node lon = entry.Require("lon", "the WGS84 longitude in degrees");
  point.lon_deg = entry.ToNumber(lon, "lon");
  if (std::abs(point.lon_deg) > 180.0) entry.Bad(lon, "lon", "a longitude in [-180, 180] degrees");
  // `inspect --suggest-session` writes lat 0, lon 0 for the user to fill in; no site is there
  // (the Gulf of Guinea), so a zero pair is a placeholder left, not a position.
  if (point.lat_deg == 0.0 && point.lon_deg == 0.0) {
    throw InputError(Where(survey.file(), LineOf(lat),
                           "survey.control: control point '" + point.id +
                               "' still has the placeholder lat: 0.0, lon: 0.0 left by inspect "
                               "--suggest-session; expected its RTK-measured WGS84 lat/lon in "
                               "degrees"));
  }
  point.h_m = entry.ToNumber(entry.Require("h", "the ellipsoidal height in metres"), "h");
  entry.Finish();
  return point;
}

// A value > 0 of `key`, when given, into *out (scaled by 1 / file_per_unit).
void PositiveKey(MapReader& map, const char* key, double file_per_unit, const char* expected,
                 double* out) {
  if (const YAML::Node value = map.Find(key); value.IsDefined()) {
    const double number = map.ToNumber(value, key);
    if (!(number > 0.0)) map.Bad(value, key, expected);
    *out = number / file_per_unit;
  }
}

// The scanner's height and tilt: z_m (checked for plausibility), z_sigma_m, pitch_deg,
// roll_deg, tilt_sigma_deg.
void ReadScannerHeightAndTilt(MapReader& scanner, ScannerSpec* out) {
  if (const YAML::Node z = scanner.Find("z_m"); z.IsDefined()) {
    out->z_m = scanner.ToNumber(z, "z_m");
    // A height in millimetres or centimetres, or the antenna's height above the ground, is not
    // the scanner's height relative to the antenna: no vehicle puts them 10 m apart.
    if (std::abs(*out->z_m) > kMaxScannerHeightM) {
      throw InputError(Where(scanner.file(), LineOf(z),
                             scanner.Name("z_m") + ": " + z.Scalar() +
                                 " m is not a plausible height of the scanner relative to the "
                                 "antenna; expected metres, e.g. -2.5 for a scanner 2.5 m below "
                                 "the antenna"));
    }
  }
  PositiveKey(scanner, "z_sigma_m", 1.0, "the tape's 1σ in metres, > 0 (default 0.02)",
              &out->z_sigma_m);
  const auto tilt_key = [&scanner, out](const char* key, double* angle_rad) {
    const YAML::Node value = scanner.Find(key);
    if (!value.IsDefined()) return;
    const double angle_deg = scanner.ToNumber(value, key);
    if (std::abs(angle_deg) > kMaxScannerTiltDeg) {
      throw InputError(Where(
          scanner.file(), LineOf(value),
          scanner.Name(key) + ": " + value.Scalar() +
              " deg is not how a scanner is mounted; expected the scanner's tilt on the vehicle "
              "in degrees within ±45 (pitch positive nose up, roll positive right side down)"));
    }
    *angle_rad = angle_deg / kRadToDeg;
    out->tilt.given = true;
  };
  tilt_key("pitch_deg", &out->tilt.pitch_rad);
  tilt_key("roll_deg", &out->tilt.roll_rad);
  PositiveKey(scanner, "tilt_sigma_deg", kRadToDeg, "the tilt's 1σ in degrees, > 0 (default 0.2)",
              &out->tilt.sigma_rad);
}

// The keys of `scanner:` (or of one `scanners:` item), read into *out.
void ReadScannerKeys(MapReader& scanner, const std::string& dir, ScannerSpec* out) {
  scanner.Allow({"model", "log", "time_offset_s", "mount_guess", "z_m", "z_sigma_m", "pitch_deg",
                 "roll_deg", "tilt_sigma_deg", "topic", "stamp"});
  scanner.Finish();
  out->model = scanner.ToText(
      scanner.Require("model", "a scanner preset name (configs/scanners/NAME.yaml)"), "model");
  out->log = ResolvePath(
      dir, scanner.ToText(scanner.Require("log", "the CARMEN scan log's path"), "log"));
  scanner.Number("time_offset_s", out->time_offset_s);
  // Up to about 300 years: enough to move a scanner clock counting from 0 to UNIX time, and
  // small enough that stamps keep sub-microsecond resolution in a double.
  if (std::abs(out->time_offset_s) > 1e10) {
    scanner.Bad(scanner.Find("time_offset_s"), "time_offset_s",
                "seconds within ±1e10 (added to every scan stamp)");
  }
  ReadTopicKeys(scanner, &out->topic, &out->stamp);
  if (const YAML::Node guess = scanner.Find("mount_guess"); guess.IsDefined()) {
    MapReader g = scanner.Child("mount_guess", guess);
    MountGuess mount;
    g.Number("x", mount.x_m);
    g.Number("y", mount.y_m);
    g.Scaled("yaw_deg", mount.yaw_rad, kRadToDeg);
    if (const YAML::Node t = g.Find("tolerance_m"); t.IsDefined()) {
      const double tolerance_m = g.ToNumber(t, "tolerance_m");
      if (!(tolerance_m > 0.0)) g.Bad(t, "tolerance_m", "a distance > 0 in metres");
      mount.tolerance_m = tolerance_m;
    }
    if (const YAML::Node t = g.Find("tolerance_yaw_deg"); t.IsDefined()) {
      const double tolerance_deg = g.ToNumber(t, "tolerance_yaw_deg");
      if (!(tolerance_deg > 0.0 && tolerance_deg <= 180.0)) {
        g.Bad(t, "tolerance_yaw_deg", "an angle in (0, 180] degrees");
      }
      mount.tolerance_yaw_rad = tolerance_deg / kRadToDeg;
    }
    g.Finish();
    out->mount_guess = mount;
  }
  ReadScannerHeightAndTilt(scanner, out);
  scanner.Finish();
}

// `attitude:`: the vehicle's roll and pitch stream. Its log is resolved as the others; whether
// it is a recording (then topic is required) is decided by its reader, by content.
void ReadAttitude(MapReader& top, const YAML::Node& node, SessionSpec& spec) {
  MapReader attitude = top.Child("attitude", node);
  attitude.Allow({"log", "topic", "stamp", "time_offset_s", "sigma_deg"});
  attitude.Finish();
  spec.attitude_log = ResolvePath(
      spec.dir, attitude.ToText(attitude.Require("log",
                                                 "the attitude log's path ($PASHR or $PTNL,AVR "
                                                 "sentences, or a recording with topic:)"),
                                "log"));
  ReadTopicKeys(attitude, &spec.attitude_topic, &spec.attitude_stamp);
  attitude.Number("time_offset_s", spec.attitude_time_offset_s);
  if (std::abs(spec.attitude_time_offset_s) > 1e10) {
    attitude.Bad(attitude.Find("time_offset_s"), "time_offset_s",
                 "seconds within ±1e10 (added to every attitude sample's time)");
  }
  PositiveKey(attitude, "sigma_deg", kRadToDeg,
              "one sample's 1σ of roll and of pitch in degrees, > 0 (default 0.1)",
              &spec.attitude_sigma_rad);
  attitude.Finish();
}

// `scanners:`, a list of scanner maps, each with an `id:` (named in every message about it)
// and optionally `frame:`. Refused: an empty list, a duplicate id or frame, two scanners
// reading the same topic of the same recording (or the same text log).
void ReadScannerList(MapReader& top, const YAML::Node& list, SessionSpec& spec) {
  if (top.Find("scanner").IsDefined()) {
    top.Bad(top.Find("scanner"), "scanner",
            "either scanner: (one scanner) or scanners: (a list), not both");
  }
  if (!list.IsSequence() || list.size() == 0) {
    top.Bad(list, "scanners", "a list of at least one {id, model, log, ...}");
  }
  const std::string& f = top.file();
  std::map<std::string, int> id_lines, frame_lines;
  std::map<std::pair<std::string, std::string>, std::string> stream_owner;
  for (size_t i = 0; i < list.size(); ++i) {
    const YAML::Node item = list[i];
    const std::string index_name = "scanners[" + std::to_string(i) + "]";
    if (!item.IsMap()) top.Bad(item, index_name, "{id, model, log, ...}");
    MapReader head(item, f, index_name + ".", LineOf(item));
    ScannerSpec scanner;
    scanner.line = LineOf(item);
    scanner.id = head.ToText(head.Require("id", "the scanner's name (also its frame)"), "id");
    MapReader entry(item, f, "scanner '" + scanner.id + "'.", LineOf(item));
    entry.Allow({"id", "frame"});
    scanner.frame = scanner.id;
    if (const YAML::Node frame = entry.Find("frame"); frame.IsDefined()) {
      scanner.frame = entry.ToText(frame, "frame");
    }
    ReadScannerKeys(entry, spec.dir, &scanner);
    if (const auto [it, added] = id_lines.emplace(scanner.id, scanner.line); !added) {
      throw InputError(Where(f, scanner.line,
                             "scanner '" + scanner.id + "' given twice (also line " +
                                 std::to_string(it->second) + "); expected unique scanner ids"));
    }
    if (const auto [it, added] = frame_lines.emplace(scanner.frame, scanner.line); !added) {
      throw InputError(Where(f, scanner.line,
                             "scanner '" + scanner.id + "': frame '" + scanner.frame +
                                 "' is another scanner's too (line " +
                                 std::to_string(it->second) + "); expected one frame each"));
    }
    const auto stream = std::make_pair(scanner.log, scanner.topic);
    if (const auto [it, added] = stream_owner.emplace(stream, scanner.id); !added) {
      const std::string what =
          scanner.topic.empty() ? "log " + scanner.log : "topic " + scanner.topic;
      throw InputError(Where(f, scanner.line,
                             "scanner '" + scanner.id + "' reads the same " + what +
                                 " as scanner '" + it->second +
                                 "'; expected each scanner its own log or topic"));
    }
    spec.scanners.push_back(std::move(scanner));
  }
}

}  // namespace

SessionSpec ReadSession(const std::string& path) {
  std::error_code ec;
  fs::path file(path);
  if (fs::is_directory(file, ec)) file /= "session.yaml";
  if (!fs::is_regular_file(file, ec)) {
    throw InputError(
        Where(path, 0, "no session.yaml here; expected a session.yaml or a folder holding one"));
  }
  SessionSpec spec;
  spec.file = file.lexically_normal().string();
  spec.dir = file.parent_path().lexically_normal().string();
  if (spec.dir.empty()) spec.dir = ".";
  const std::string& f = spec.file;

  const YAML::Node root = LoadYamlStrict(f);
  MapReader top(root, f, "", 1);
  if (!root.IsMap())
    throw InputError(Where(f, 0, "empty session; expected the keys of docs/session-format.md"));

  top.Allow({"name", "utm_zone", "scanner", "scanners", "gnss", "heading", "attitude", "survey",
             "walls", "antenna_in_base"});
  top.Finish();
  top.Text("name", spec.name);
  if (spec.name.empty())
    spec.name = fs::absolute(spec.dir, ec).lexically_normal().filename().string();
  if (const YAML::Node zone = top.Find("utm_zone"); zone.IsDefined()) {
    spec.utm_zone = ParseUtmZone(top, zone);
  }

  if (const YAML::Node list = top.Find("scanners"); list.IsDefined()) {
    ReadScannerList(top, list, spec);
  } else {
    const YAML::Node node = top.Require("scanner", "a map with model and log (or a scanners: list)");
    MapReader scanner = top.Child("scanner", node);
    ScannerSpec one;
    ReadScannerKeys(scanner, spec.dir, &one);
    spec.scanner_model = one.model;
    spec.scanner_log = one.log;
    spec.scanner_time_offset_s = one.time_offset_s;
    spec.scanner_topic = one.topic;
    spec.scanner_stamp = one.stamp;
    spec.mount_guess = one.mount_guess;
    spec.scanner_z_m = one.z_m;
    spec.scanner_z_sigma_m = one.z_sigma_m;
    spec.scanner_tilt = one.tilt;
  }
  {
    const YAML::Node node = top.Require("gnss", "a map with log");
    MapReader gnss = top.Child("gnss", node);
    gnss.Allow({"log", "min_fix_quality", "topic", "stamp", "max_sigma_m"});
    gnss.Finish();
    spec.gnss_log =
        ResolvePath(spec.dir, gnss.ToText(gnss.Require("log", "the NMEA GGA log's path"), "log"));
    if (const YAML::Node q = gnss.Find("min_fix_quality"); q.IsDefined()) {
      spec.min_fix_quality = gnss.ToInteger(q, "min_fix_quality");
      if (spec.min_fix_quality < 1 || spec.min_fix_quality > 9) {
        gnss.Bad(q, "min_fix_quality", "a GGA quality 1..9 (4 = RTK fixed, 5 = float)");
      }
    }
    ReadTopicKeys(gnss, &spec.gnss_topic, &spec.gnss_stamp);
    if (const YAML::Node sigma = gnss.Find("max_sigma_m"); sigma.IsDefined()) {
      spec.gnss_max_sigma_m = gnss.ToNumber(sigma, "max_sigma_m");
      if (!(spec.gnss_max_sigma_m > 0.0)) {
        gnss.Bad(sigma, "max_sigma_m", "a horizontal σ in metres > 0 (e.g. 0.05)");
      }
    }
    gnss.Finish();
  }
  {
    const YAML::Node node = top.Require("heading", "a map with log");
    MapReader heading = top.Child("heading", node);
    heading.Allow({"log", "reference", "topic", "stamp"});
    heading.Finish();
    spec.heading_log = ResolvePath(
        spec.dir, heading.ToText(heading.Require("log", "the NMEA HDT/THS log's path"), "log"));
    if (const YAML::Node ref = heading.Find("reference"); ref.IsDefined()) {
      const std::string text = ref.IsScalar() ? ref.Scalar() : "";
      if (text == "true_north") {
        spec.heading_reference = HeadingReference::kTrueNorth;
      } else if (text == "grid_north") {
        spec.heading_reference = HeadingReference::kGridNorth;
      } else {
        heading.Bad(ref, "reference", "true_north or grid_north");
      }
    }
    ReadTopicKeys(heading, &spec.heading_topic, &spec.heading_stamp);
    heading.Finish();
  }
  if (const YAML::Node node = top.Find("attitude"); node.IsDefined()) ReadAttitude(top, node, spec);
  {
    const YAML::Node node = top.Require("survey", "a map with points (and control)");
    MapReader survey = top.Child("survey", node);
    survey.Allow({"points", "columns", "control", "rotation_deg", "point_sigma_m"});
    survey.Finish();
    spec.survey_points = ResolvePath(
        spec.dir, survey.ToText(survey.Require("points", "the survey file's path"), "points"));
    // The columns of a CSV without a header row (docs/survey-files.md); GSI files ignore it.
    if (const YAML::Node columns = survey.Find("columns"); columns.IsDefined()) {
      std::string text = columns.IsScalar() ? columns.Scalar() : "";
      for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
      if (text == "PNEZD") {
        spec.survey_columns = SurveyColumns::kPNEZD;
      } else if (text == "PENZD") {
        spec.survey_columns = SurveyColumns::kPENZD;
      } else if (text == "HEADER") {
        spec.survey_columns = SurveyColumns::kHeader;
      } else {
        survey.Bad(columns, "columns", "PNEZD, PENZD or header");
      }
    }
    // No control: a rover survey, whose points are in the GNSS's frame already (a total-station
    // survey without control is refused by the tie, which knows what the file holds).
    const YAML::Node control = survey.Find("control");
    if (control.IsDefined() && (!control.IsSequence() || control.size() == 0)) {
      survey.Bad(control, "control", "a list of at least one {id, lat, lon, h}");
    }
    std::set<std::string> ids;
    for (size_t i = 0; control.IsDefined() && i < control.size(); ++i) {
      ControlPoint point = ReadControlPoint(survey, control[i], i);
      if (!ids.insert(point.id).second) {
        throw InputError(Where(
            f, point.line,
            "survey.control: control point '" + point.id + "' given twice; expected unique ids"));
      }
      spec.control.push_back(std::move(point));
    }
    if (const YAML::Node sigma = survey.Find("point_sigma_m"); sigma.IsDefined()) {
      const double sigma_m = survey.ToNumber(sigma, "point_sigma_m");
      if (!(sigma_m > 0.0) || sigma_m > 1.0) {
        survey.Bad(sigma, "point_sigma_m", "a rover point's horizontal 1σ in metres, in (0, 1]");
      }
      spec.survey_point_sigma_m = sigma_m;
    }
    if (const YAML::Node rotation = survey.Find("rotation_deg"); rotation.IsDefined()) {
      spec.survey_rotation_rad = survey.ToNumber(rotation, "rotation_deg") / kRadToDeg;
    }
    if (spec.control.size() == 1 && !spec.survey_rotation_rad) {
      throw InputError(Where(f, survey.line(),
                             "one control point needs survey.rotation_deg (Barawid 2007 Eq. 4-5); "
                             "expected a second control point or the rotation (a rover survey in "
                             "latitude and longitude takes no control points)"));
    }
    survey.Finish();
  }
  {
    const YAML::Node walls = top.Require("walls", "a list of {id, code} (at least one)");
    if (!walls.IsSequence() || walls.size() == 0) {
      top.Bad(walls, "walls", "a list of at least one {id, code}");
    }
    std::set<std::string> ids;
    for (size_t i = 0; i < walls.size(); ++i) {
      const YAML::Node item = walls[i];
      const std::string name = "walls[" + std::to_string(i) + "]";
      if (!item.IsMap()) top.Bad(item, name, "{id, code}");
      MapReader entry(item, f, name + ".", LineOf(item));
      entry.Allow({"id", "code"});
      entry.Finish();
      WallSpec wall;
      wall.id = entry.ToText(entry.Require("id", "a name for the wall"), "id");
      wall.code =
          entry.ToText(entry.Require("code", "the survey code of the points on this wall"), "code");
      entry.Finish();
      if (!ids.insert(wall.id).second) {
        throw InputError(
            Where(f, LineOf(item), "wall '" + wall.id + "' given twice; expected unique wall ids"));
      }
      spec.walls.push_back(std::move(wall));
    }
  }
  if (const YAML::Node antenna = top.Find("antenna_in_base"); antenna.IsDefined()) {
    MapReader a = top.Child("antenna_in_base", antenna);
    AntennaInBase in_base;
    a.Number("x", in_base.x_m);
    a.Number("y", in_base.y_m);
    a.Number("z", in_base.z_m);
    a.Finish();
    spec.antenna_in_base = in_base;
  }
  top.Finish();
  return spec;
}

std::string ScannerIds(const SessionSpec& session) {
  std::string ids;
  for (size_t k = 0; k < session.scanners.size(); ++k) {
    ids += (k > 0 ? ", " : "") + session.scanners[k].id;
  }
  return ids;
}

SessionSpec SessionForScannerId(const SessionSpec& session, const std::string& id) {
  if (session.scanners.empty()) {
    throw InputError(Where(session.file, 1,
                           "has one scanner: (no scanners: list); --scanner " + id +
                               " applies to a session with scanners:"));
  }
  for (size_t k = 0; k < session.scanners.size(); ++k) {
    if (session.scanners[k].id == id) return SessionForScanner(session, k);
  }
  throw InputError(Where(session.file, session.scanners.front().line,
                         "has no scanner '" + id + "'; expected --scanner ID with ID one of " +
                             ScannerIds(session)));
}

SessionSpec SessionForScanner(const SessionSpec& session, size_t index) {
  SessionSpec one = session;
  const ScannerSpec& scanner = session.scanners.at(index);
  one.scanner_id = scanner.id;
  one.scanner_model = scanner.model;
  one.scanner_log = scanner.log;
  one.scanner_time_offset_s = scanner.time_offset_s;
  one.scanner_topic = scanner.topic;
  one.scanner_stamp = scanner.stamp;
  one.mount_guess = scanner.mount_guess;
  one.scanner_z_m = scanner.z_m;
  one.scanner_z_sigma_m = scanner.z_sigma_m;
  one.scanner_tilt = scanner.tilt;
  one.scanners.clear();
  return one;
}

}  // namespace wallcal::io
