#include "io/session_reader.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "io/config_fields.h"
#include "io/input_file.h"
#include "io/yaml_strict.h"
#include "common/angles.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;
// yaml-cpp marks are 0-based; files are read by people counting from 1.
int LineOf(const YAML::Node& node) { return YamlLine(node); }

std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += separator;
    text += items[i];
  }
  return text;
}

// Reads the keys of one YAML map, remembers which ones were asked for, and rejects the others
// in Finish(): a misspelt key must not silently fall back to a default. Also the visitor of
// config_fields.h. `prefix` ("scanner.") names the map in messages.
class MapReader {
 public:
  MapReader(const YAML::Node& node, std::string file, std::string prefix, int line)
      : node_(node), file_(std::move(file)), prefix_(std::move(prefix)), line_(line) {
    if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
      const std::string what = prefix_.empty() ? "the file" : Name("");
      throw InputError(Where(file_, LineOf(node_), what + " must be a map of key: value"));
    }
  }

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  std::string Name(const std::string& key) const {
    if (prefix_.empty()) return key;
    if (key.empty()) return prefix_.substr(0, prefix_.size() - 1);
    return prefix_ + key;
  }

  // The value of `key`, or an undefined node when absent. Null values count as absent for
  // nothing: an empty `key:` is reported by the typed getters.
  YAML::Node Find(const std::string& key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
    if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == key) return it->second;
    }
    return YAML::Node(YAML::NodeType::Undefined);
  }

  YAML::Node Require(const std::string& key, const std::string& expected) {
    YAML::Node value = Find(key);
    if (!value.IsDefined()) {
      throw InputError(Where(file_, line_, Name(key) + " is missing; expected " + expected));
    }
    return value;
  }

  [[noreturn]] void Bad(const YAML::Node& value, const std::string& key,
                        const std::string& expected) const {
    // The value is the user's own text, but it is escaped and shortened: a message is one line.
    std::string shown = value.IsScalar() ? value.Scalar() : "";
    if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
    std::string got = value.IsScalar() ? "'" + EscapeControl(shown) + "'"
                      : value.IsNull() ? "nothing"
                      : value.IsMap()  ? "a map"
                                       : "a list";
    throw InputError(
        Where(file_, LineOf(value), Name(key) + ": expected " + expected + ", got " + got));
  }

  double ToNumber(const YAML::Node& value, const std::string& key) const {
    double number = 0.0;
    if (!value.IsScalar() || !YAML::convert<double>::decode(value, number) ||
        !std::isfinite(number)) {
      Bad(value, key, "a finite number");
    }
    return number;
  }
  int ToInteger(const YAML::Node& value, const std::string& key) const {
    int number = 0;
    if (!value.IsScalar() || !YAML::convert<int>::decode(value, number)) {
      Bad(value, key, "an integer");
    }
    return number;
  }
  std::string ToText(const YAML::Node& value, const std::string& key) const {
    if (!value.IsScalar() || value.Scalar().empty()) Bad(value, key, "a non-empty text");
    CheckNoControl(value, key);
    return value.Scalar();
  }
  // Names and paths go to terminals and files: no control characters (escape sequences, fake
  // lines). Bytes that are not UTF-8 are allowed (a Latin-1 file name) and escaped on output.
  void CheckNoControl(const YAML::Node& value, const std::string& key) const {
    for (const char c : value.Scalar()) {
      const unsigned char u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\t') || u == 0x7F) {
        Bad(value, key, "text without control characters");
      }
    }
  }

  // --- the visitor interface of config_fields.h (all keys optional) ---
  void Number(const std::string& key, double& out) {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToNumber(value, key);
  }
  void Scaled(const std::string& key, double& out, double file_per_unit) {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToNumber(value, key) / file_per_unit;
  }
  void Integer(const std::string& key, int& out) {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToInteger(value, key);
  }
  void Boolean(const std::string& key, bool& out) {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    bool flag = false;
    if (!value.IsScalar() || !YAML::convert<bool>::decode(value, flag)) {
      Bad(value, key, "true or false");
    }
    out = flag;
  }
  void Text(const std::string& key, std::string& out) {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    if (value.IsNull()) {
      out.clear();
      return;
    }
    if (!value.IsScalar()) Bad(value, key, "a text");
    CheckNoControl(value, key);
    out = value.Scalar();
  }
  template <class T, class F>
  void List(const std::string& key, std::vector<T>& out, F visit_item) {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    out.clear();
    if (value.IsNull()) return;
    if (!value.IsSequence()) Bad(value, key, "a list");
    for (size_t i = 0; i < value.size(); ++i) {
      const YAML::Node item = value[i];
      if (!item.IsMap()) Bad(item, key + "[" + std::to_string(i) + "]", "a map");
      MapReader item_reader(item, file_, Name(key) + "[" + std::to_string(i) + "].", LineOf(item));
      T element;
      visit_item(item_reader, element);
      item_reader.Finish();
      out.push_back(std::move(element));
    }
  }

  // Declares keys read later, so that Finish() can report a misspelt key before a later
  // "missing key" message would hide it.
  void Allow(std::initializer_list<const char*> keys) {
    for (const char* key : keys) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
    }
  }

  MapReader Child(const std::string& key, const YAML::Node& value) const {
    return MapReader(value, file_, Name(key) + ".", LineOf(value));
  }

  // Rejects every key that was not asked for.
  void Finish() const {
    if (!node_.IsMap()) return;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : "?";
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        throw InputError(
            Where(file_, LineOf(it->first),
                  "unknown key '" + Name(key) + "'; expected one of: " + Join(known_, ", ")));
      }
    }
  }

 private:
  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  int line_ = 0;
  std::vector<std::string> known_;
};

// Runs Validate() and puts the file name, and the line of the key at fault, in front of its
// message.
template <class T>
void ValidateIn(const std::string& file, const T& options, const YAML::Node& root) {
  try {
    options.Validate();
  } catch (const OptionError& e) {
    throw InputError(Where(file, LineOfKey(root, e.key()), e.what()));
  } catch (const InputError& e) {
    throw InputError(Where(file, 0, e.what()));
  }
}

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
  point.h_m = entry.ToNumber(entry.Require("h", "the ellipsoidal height in metres"), "h");
  entry.Finish();
  return point;
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

  top.Allow(
      {"name", "utm_zone", "scanner", "gnss", "heading", "survey", "walls", "antenna_in_base"});
  top.Finish();
  top.Text("name", spec.name);
  if (spec.name.empty())
    spec.name = fs::absolute(spec.dir, ec).lexically_normal().filename().string();
  if (const YAML::Node zone = top.Find("utm_zone"); zone.IsDefined()) {
    spec.utm_zone = ParseUtmZone(top, zone);
  }

  {
    const YAML::Node node = top.Require("scanner", "a map with model and log");
    MapReader scanner = top.Child("scanner", node);
    scanner.Allow({"model", "log", "time_offset_s", "mount_guess", "z_m", "topic", "stamp"});
    scanner.Finish();
    spec.scanner_model = scanner.ToText(
        scanner.Require("model", "a scanner preset name (configs/scanners/NAME.yaml)"), "model");
    spec.scanner_log = ResolvePath(
        spec.dir, scanner.ToText(scanner.Require("log", "the CARMEN scan log's path"), "log"));
    scanner.Number("time_offset_s", spec.scanner_time_offset_s);
    // Up to about 300 years: enough to move a scanner clock counting from 0 to UNIX time, and
    // small enough that stamps keep sub-microsecond resolution in a double.
    if (std::abs(spec.scanner_time_offset_s) > 1e10) {
      scanner.Bad(scanner.Find("time_offset_s"), "time_offset_s",
                  "seconds within ±1e10 (added to every scan stamp)");
    }
    ReadTopicKeys(scanner, &spec.scanner_topic, &spec.scanner_stamp);
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
      spec.mount_guess = mount;
    }
    if (const YAML::Node z = scanner.Find("z_m"); z.IsDefined()) {
      spec.scanner_z_m = scanner.ToNumber(z, "z_m");
    }
    scanner.Finish();
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
  {
    const YAML::Node node = top.Require("survey", "a map with points and control");
    MapReader survey = top.Child("survey", node);
    survey.Allow({"points", "columns", "control", "rotation_deg"});
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
    const YAML::Node control =
        survey.Require("control", "a list of {id, lat, lon, h} (at least one)");
    if (!control.IsSequence() || control.size() == 0) {
      survey.Bad(control, "control", "a list of at least one {id, lat, lon, h}");
    }
    std::set<std::string> ids;
    for (size_t i = 0; i < control.size(); ++i) {
      ControlPoint point = ReadControlPoint(survey, control[i], i);
      if (!ids.insert(point.id).second) {
        throw InputError(Where(
            f, point.line,
            "survey.control: control point '" + point.id + "' given twice; expected unique ids"));
      }
      spec.control.push_back(std::move(point));
    }
    if (const YAML::Node rotation = survey.Find("rotation_deg"); rotation.IsDefined()) {
      spec.survey_rotation_rad = survey.ToNumber(rotation, "rotation_deg") / kRadToDeg;
    }
    if (spec.control.size() == 1 && !spec.survey_rotation_rad) {
      throw InputError(Where(f, survey.line(),
                             "one control point needs survey.rotation_deg (Barawid 2007 Eq. 4-5); "
                             "expected a second control point or the rotation"));
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

ScannerPreset ReadScannerPreset(const std::string& file) {
  const YAML::Node root = LoadYamlStrict(file);
  MapReader top(root, file, "", 1);
  ScannerPreset preset;
  preset.name = fs::path(file).stem().string();
  top.Text("name", preset.name);
  top.Text("source", preset.source);
  preset.num_beams =
      top.ToInteger(top.Require("num_beams", "the number of beams a scan"), "num_beams");
  preset.start_angle_rad =
      top.ToNumber(top.Require("start_angle_deg", "the bearing of beam 0 in degrees"),
                   "start_angle_deg") /
      kRadToDeg;
  preset.angular_step_rad =
      top.ToNumber(top.Require("angular_step_deg", "the step between beams in degrees"),
                   "angular_step_deg") /
      kRadToDeg;
  top.Number("rate_hz", preset.rate_hz);
  top.Number("min_range_m", preset.min_range_m);
  preset.max_range_m =
      top.ToNumber(top.Require("max_range_m", "the maximum range in metres"), "max_range_m");
  top.Number("error_codes_below_m", preset.error_codes_below_m);
  top.Boolean("max_range_is_no_return", preset.max_range_is_no_return);
  top.Number("range_resolution_m", preset.range_resolution_m);
  if (const YAML::Node node = top.Find("range_correction"); node.IsDefined()) {
    MapReader correction = top.Child("range_correction", node);
    correction.Number("k", preset.range_scale_k);
    correction.Number("b_m", preset.range_offset_b_m);
    correction.Finish();
  }
  if (const YAML::Node node = top.Find("simulation"); node.IsDefined()) {
    MapReader sim = top.Child("simulation", node);
    sim.Number("n", preset.sim_scale_n);
    sim.Number("c_m", preset.sim_offset_c_m);
    sim.Number("sigma_m", preset.range_sigma_m);
    sim.Finish();
  }
  top.Scaled("max_incidence_deg", preset.max_incidence_rad, kRadToDeg);
  top.Finish();

  auto fail = [&file](const std::string& message) { throw InputError(Where(file, 0, message)); };
  if (preset.num_beams < 2) fail("num_beams must be >= 2, got " + std::to_string(preset.num_beams));
  if (preset.angular_step_rad == 0.0) fail("angular_step_deg must not be 0");
  if (preset.rate_hz < 0.0) fail("rate_hz must be >= 0");
  if (preset.min_range_m < 0.0) fail("min_range_m must be >= 0");
  if (!(preset.max_range_m > preset.min_range_m)) fail("max_range_m must be > min_range_m");
  if (preset.error_codes_below_m < 0.0) fail("error_codes_below_m must be >= 0");
  if (!(preset.range_resolution_m > 0.0)) fail("range_resolution_m must be > 0");
  if (!(preset.range_scale_k > 0.0)) fail("range_correction.k must be > 0");
  if (!(preset.sim_scale_n > 0.0)) fail("simulation.n must be > 0");
  if (preset.range_sigma_m < 0.0) fail("simulation.sigma_m must be >= 0");
  if (!(preset.max_incidence_rad > 0.0 && preset.max_incidence_rad * kRadToDeg <= 90.0)) {
    fail("max_incidence_deg must be in (0, 90]");
  }
  return preset;
}

ScannerPreset LoadScannerPreset(const std::string& model,
                                const std::vector<std::string>& search_dirs) {
  std::error_code ec;
  // A model is a file stem, never a path: "../x" must not escape the preset folders.
  const bool plain_name = !model.empty() && model.find('/') == std::string::npos &&
                          model.find('\\') == std::string::npos && model != "." && model != "..";
  if (plain_name) {
    for (const std::string& dir : search_dirs) {
      const fs::path candidate = fs::path(dir) / (model + ".yaml");
      if (fs::is_regular_file(candidate, ec)) return ReadScannerPreset(candidate.string());
    }
  }
  std::set<std::string> available;
  for (const std::string& dir : search_dirs) {
    if (!fs::is_directory(dir, ec)) continue;
    for (const auto& entry : fs::directory_iterator(dir, ec)) {
      if (entry.path().extension() == ".yaml") available.insert(entry.path().stem().string());
    }
  }
  const std::string names =
      available.empty() ? "none found"
                        : Join(std::vector<std::string>(available.begin(), available.end()), ", ");
  throw InputError("unknown scanner model '" + model + "'; available presets: " + names +
                   " (searched " + Join(search_dirs, ", ") + ")");
}

CalibrateOptions ReadCalibrateOptions(const std::string& file) {
  const YAML::Node root = LoadYamlStrict(file);
  MapReader top(root, file, "", 1);
  CalibrateOptions options;
  if (const YAML::Node node = top.Find("detector"); node.IsDefined()) {
    MapReader section = top.Child("detector", node);
    fields::VisitDetector(section, options.detector);
    section.Finish();
  }
  if (const YAML::Node node = top.Find("alignment"); node.IsDefined()) {
    MapReader section = top.Child("alignment", node);
    fields::VisitAlignment(section, options.alignment);
    section.Finish();
  }
  if (const YAML::Node node = top.Find("solver"); node.IsDefined()) {
    MapReader section = top.Child("solver", node);
    fields::VisitSolver(section, options.solver);
    section.Finish();
  }
  if (const YAML::Node node = top.Find("acceptance"); node.IsDefined()) {
    MapReader section = top.Child("acceptance", node);
    fields::VisitAcceptance(section, options.acceptance);
    section.Finish();
  }
  top.Integer("first_pass_max_scans", options.first_pass_max_scans);
  top.Finish();
  ValidateIn(file, options, root);
  return options;
}

SimulationConfig ReadSimulationConfig(const std::string& file) {
  const YAML::Node root = LoadYamlStrict(file);
  MapReader top(root, file, "", 1);
  SimulationConfig config;
  fields::VisitSimulation(top, config);
  top.Finish();
  ValidateIn(file, config, root);
  return config;
}

SimulationConfig ReadTruthYaml(const std::string& file) {
  const YAML::Node root = LoadYamlStrict(file);
  MapReader top(root, file, "", 1);
  const YAML::Node simulation = top.Require("simulation", "the simulation settings");
  MapReader section = top.Child("simulation", simulation);
  SimulationConfig config;
  fields::VisitSimulation(section, config);
  section.Finish();
  if (const YAML::Node truth = top.Find("truth"); truth.IsDefined()) {
    // The truth mount in radians is exact; simulation.mount_yaw_deg went through degrees.
    MapReader mount = top.Child("truth", truth);
    mount.Number("x", config.mount_x_m);
    mount.Number("y", config.mount_y_m);
    mount.Number("yaw", config.mount_yaw_rad);
    double yaw_deg = 0.0;
    mount.Number("yaw_deg", yaw_deg);
    mount.Finish();
  }
  ValidateIn(file, config, root);
  return config;
}

}  // namespace wallcal::io
