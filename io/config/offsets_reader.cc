// SPDX-License-Identifier: Apache-2.0
#include "io/config/offsets_reader.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>

namespace wallcal::io {
namespace {

int LineOf(const YAML::Node& node) { return node.Mark().line >= 0 ? node.Mark().line + 1 : 0; }

// `what` names the map in messages: "scanner_mount", "scanner_mounts[2]".
double FiniteNumber(const std::string& file, const YAML::Node& parent, const std::string& what,
                    const char* key) {
  const YAML::Node value = parent[key];
  double number = 0.0;
  if (!value.IsDefined() || !value.IsScalar() || !YAML::convert<double>::decode(value, number) ||
      !std::isfinite(number)) {
    throw InputError(Where(file, value.IsDefined() ? LineOf(value) : LineOf(parent),
                           what + "." + key +
                               ": expected a finite number (an offsets.yaml written by calibrate)"));
  }
  return number;
}

std::string Text(const std::string& file, const YAML::Node& parent, const std::string& what,
                 const char* key) {
  const YAML::Node value = parent[key];
  if (!value.IsDefined() || !value.IsScalar() || value.Scalar().empty()) {
    throw InputError(Where(file, value.IsDefined() ? LineOf(value) : LineOf(parent),
                           what + "." + key + ": expected a name (an offsets.yaml written by "
                                              "calibrate)"));
  }
  return value.Scalar();
}

YAML::Node Load(const std::string& file) {
  if (!std::ifstream(file)) {
    throw InputError(Where(file, 0, "cannot open the file; expected an earlier offsets.yaml"));
  }
  try {
    return YAML::LoadFile(file);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(file, e.mark.line + 1, "YAML syntax error: " + e.msg));
  } catch (const YAML::Exception& e) {
    throw InputError(Where(file, 0, std::string("cannot read YAML: ") + e.what()));
  }
}

// x, y, yaw and the covariance of one mount map.
PreviousOffsets MountOf(const std::string& file, const YAML::Node& mount, const std::string& what) {
  PreviousOffsets previous;
  previous.file = file;
  previous.x_m = FiniteNumber(file, mount, what, "x");
  previous.y_m = FiniteNumber(file, mount, what, "y");
  previous.yaw_rad = FiniteNumber(file, mount, what, "yaw");
  const YAML::Node covariance = mount["covariance"];
  if (covariance.IsDefined() && covariance.IsSequence()) {
    if (covariance.size() != 9) {
      throw InputError(Where(file, LineOf(covariance),
                             what + ".covariance: expected 9 numbers (3x3 row-major)"));
    }
    for (size_t i = 0; i < 9; ++i) {
      double value = 0.0;
      if (!covariance[i].IsScalar() || !YAML::convert<double>::decode(covariance[i], value) ||
          !std::isfinite(value)) {
        throw InputError(Where(file, LineOf(covariance),
                               what + ".covariance: expected 9 finite numbers"));
      }
      previous.covariance[i] = value;
    }
    previous.sigma_known = previous.covariance[0] >= 0.0 && previous.covariance[4] >= 0.0 &&
                           previous.covariance[8] >= 0.0;
  }
  return previous;
}

std::string CreatedUtc(const YAML::Node& root) {
  const YAML::Node source = root["source"];
  if (source.IsDefined() && source.IsMap()) {
    const YAML::Node created = source["created_utc"];
    if (created.IsDefined() && created.IsScalar()) return created.Scalar();
  }
  return "";
}

}  // namespace

PreviousOffsets ReadPreviousOffsets(const std::string& file) {
  const YAML::Node root = Load(file);
  const YAML::Node mount = root.IsMap() ? root["scanner_mount"] : YAML::Node();
  if (!mount.IsDefined() || !mount.IsMap()) {
    if (root.IsMap() && root["scanner_mounts"].IsDefined()) {
      throw InputError(Where(file, LineOf(root["scanner_mounts"]),
                             "scanner_mounts: holds several scanners; expected the offsets.yaml "
                             "of one scanner (scanner_mount:)"));
    }
    throw InputError(Where(file, 0,
                           "no scanner_mount map; expected an offsets.yaml written by calibrate"));
  }
  PreviousOffsets previous = MountOf(file, mount, "scanner_mount");
  previous.created_utc = CreatedUtc(root);
  return previous;
}

PreviousSeveralOffsets ReadPreviousSeveralOffsets(const std::string& file) {
  const YAML::Node root = Load(file);
  PreviousSeveralOffsets previous;
  previous.file = file;
  previous.created_utc = root.IsMap() ? CreatedUtc(root) : "";
  const YAML::Node mounts = root.IsMap() ? root["scanner_mounts"] : YAML::Node();
  if (!mounts.IsDefined()) {
    const YAML::Node one = root.IsMap() ? root["scanner_mount"] : YAML::Node();
    if (!one.IsDefined() || !one.IsMap()) {
      throw InputError(Where(file, 0,
                             "neither scanner_mounts nor scanner_mount; expected an offsets.yaml "
                             "written by calibrate"));
    }
    PreviousScannerOffsets scanner;
    scanner.id = one["child_frame"].IsScalar() ? one["child_frame"].Scalar() : "laser";
    scanner.offsets = MountOf(file, one, "scanner_mount");
    scanner.offsets.created_utc = previous.created_utc;
    previous.scanners.push_back(scanner);
    return previous;
  }
  if (!mounts.IsSequence()) {
    throw InputError(Where(file, LineOf(mounts), "scanner_mounts: expected a list of maps"));
  }
  previous.several = true;
  for (size_t i = 0; i < mounts.size(); ++i) {
    const std::string what = "scanner_mounts[" + std::to_string(i + 1) + "]";
    if (!mounts[i].IsMap()) throw InputError(Where(file, LineOf(mounts[i]), what + ": expected a map"));
    PreviousScannerOffsets scanner;
    scanner.id = Text(file, mounts[i], what, "id");
    scanner.offsets = MountOf(file, mounts[i], what + " ('" + scanner.id + "')");
    scanner.offsets.created_utc = previous.created_utc;
    previous.scanners.push_back(scanner);
  }
  const YAML::Node relative = root["relative_mounts"];
  if (relative.IsDefined() && !relative.IsSequence()) {
    throw InputError(Where(file, LineOf(relative), "relative_mounts: expected a list of maps"));
  }
  for (size_t i = 0; relative.IsDefined() && i < relative.size(); ++i) {
    const std::string what = "relative_mounts[" + std::to_string(i + 1) + "]";
    if (!relative[i].IsMap()) {
      throw InputError(Where(file, LineOf(relative[i]), what + ": expected a map"));
    }
    PreviousRelativeOffsets pair;
    pair.from_id = Text(file, relative[i], what, "from");
    pair.to_id = Text(file, relative[i], what, "to");
    pair.offsets = MountOf(file, relative[i], what);
    pair.offsets.created_utc = previous.created_utc;
    previous.relative.push_back(pair);
  }
  return previous;
}

}  // namespace wallcal::io
