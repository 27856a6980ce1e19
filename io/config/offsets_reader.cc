// SPDX-License-Identifier: Apache-2.0
#include "io/config/offsets_reader.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>

namespace wallcal::io {
namespace {

int LineOf(const YAML::Node& node) { return node.Mark().line >= 0 ? node.Mark().line + 1 : 0; }

double FiniteNumber(const std::string& file, const YAML::Node& parent, const char* key) {
  const YAML::Node value = parent[key];
  double number = 0.0;
  if (!value.IsDefined() || !value.IsScalar() || !YAML::convert<double>::decode(value, number) ||
      !std::isfinite(number)) {
    throw InputError(Where(file, value.IsDefined() ? LineOf(value) : LineOf(parent),
                           std::string("scanner_mount.") + key +
                               ": expected a finite number (an offsets.yaml written by calibrate)"));
  }
  return number;
}

}  // namespace

PreviousOffsets ReadPreviousOffsets(const std::string& file) {
  if (!std::ifstream(file)) {
    throw InputError(Where(file, 0, "cannot open the file; expected an earlier offsets.yaml"));
  }
  YAML::Node root;
  try {
    root = YAML::LoadFile(file);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(file, e.mark.line + 1, "YAML syntax error: " + e.msg));
  } catch (const YAML::Exception& e) {
    throw InputError(Where(file, 0, std::string("cannot read YAML: ") + e.what()));
  }
  const YAML::Node mount = root.IsMap() ? root["scanner_mount"] : YAML::Node();
  if (!mount.IsDefined() || !mount.IsMap()) {
    throw InputError(Where(file, 0,
                           "no scanner_mount map; expected an offsets.yaml written by calibrate"));
  }
  PreviousOffsets previous;
  previous.file = file;
  previous.x_m = FiniteNumber(file, mount, "x");
  previous.y_m = FiniteNumber(file, mount, "y");
  previous.yaw_rad = FiniteNumber(file, mount, "yaw");
  const YAML::Node covariance = mount["covariance"];
  if (covariance.IsDefined() && covariance.IsSequence()) {
    if (covariance.size() != 9) {
      throw InputError(Where(file, LineOf(covariance),
                             "scanner_mount.covariance: expected 9 numbers (3x3 row-major)"));
    }
    for (size_t i = 0; i < 9; ++i) {
      double value = 0.0;
      if (!covariance[i].IsScalar() || !YAML::convert<double>::decode(covariance[i], value) ||
          !std::isfinite(value)) {
        throw InputError(Where(file, LineOf(covariance),
                               "scanner_mount.covariance: expected 9 finite numbers"));
      }
      previous.covariance[i] = value;
    }
    previous.sigma_known = previous.covariance[0] >= 0.0 && previous.covariance[4] >= 0.0 &&
                           previous.covariance[8] >= 0.0;
  }
  const YAML::Node source = root["source"];
  if (source.IsDefined() && source.IsMap()) {
    const YAML::Node created = source["created_utc"];
    if (created.IsDefined() && created.IsScalar()) previous.created_utc = created.Scalar();
  }
  return previous;
}

}  // namespace wallcal::io
