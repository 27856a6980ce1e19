#include "outputs/emit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include "common/angles.h"

namespace wallcal::outputs {
namespace {
// 9 significant digits: well below a micrometre / microradian for mounts of a few metres, and
// short enough to read. -0 is printed as 0 so a zero never looks signed.
std::string Num(double value) {
  if (value == 0.0) value = 0.0;
  char buffer[40];
  std::snprintf(buffer, sizeof(buffer), "%.9g", value);
  return buffer;
}

double Sigma(const Eigen::Matrix3d& covariance, int i) {
  return std::sqrt(std::max(0.0, covariance(i, i)));
}

const char* kHeightNote =
    "z of the laser = z of the antenna: the 2-D calibration does not measure the height "
    "difference; set it by hand if known";

std::string Ros2Line(const PlanarTransform& t) {
  return "ros2 run tf2_ros static_transform_publisher --x " + Num(t.x_m) + " --y " + Num(t.y_m) +
         " --z " + Num(t.z_m) + " --yaw " + Num(t.yaw_rad) + " --pitch 0 --roll 0 --frame-id " +
         t.parent + " --child-frame-id " + t.child + "\n";
}

std::string UrdfJoint(const PlanarTransform& t) {
  return "<joint name=\"" + t.parent + "_to_" + t.child + "\" type=\"fixed\">\n" +
         "  <parent link=\"" + t.parent + "\"/>\n" + "  <child link=\"" + t.child + "\"/>\n" +
         "  <origin xyz=\"" + Num(t.x_m) + " " + Num(t.y_m) + " " + Num(t.z_m) +
         "\" rpy=\"0 0 " + Num(t.yaw_rad) + "\"/>\n" + "</joint>\n";
}

std::string JsonString(const std::string& s) {
  // Frame names and method are plain (IsValidFrameName); notes are ours. Escape anyway.
  std::string out = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char buffer[8];
      std::snprintf(buffer, sizeof(buffer), "\\u%04x", c);
      out += buffer;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

void CheckFrames(const EmitFrames& frames) {
  for (const std::string* name : {&frames.parent, &frames.child, &frames.base}) {
    if (!IsValidFrameName(*name)) {
      throw std::invalid_argument("invalid frame name '" + *name + "'");
    }
  }
}

}  // namespace

bool ParseEmitFormat(const std::string& name, EmitFormat* format) {
  if (name == "ros2-static-tf") {
    *format = EmitFormat::kRos2StaticTf;
  } else if (name == "urdf") {
    *format = EmitFormat::kUrdf;
  } else if (name == "json") {
    *format = EmitFormat::kJson;
  } else {
    return false;
  }
  return true;
}

bool IsValidFrameName(const std::string& name) {
  if (name.empty() || name.size() > 128 || name[0] == '-') return false;
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '/' || c == '-';
    if (!ok) return false;
  }
  return true;
}

PlanarTransform AntennaToLaser(const solvers::Mount& mount, const EmitFrames& frames) {
  PlanarTransform t;
  t.parent = frames.parent;
  t.child = frames.child;
  t.x_m = mount.x_m;
  t.y_m = mount.y_m;
  t.z_m = 0.0;
  t.yaw_rad = mount.yaw_rad;
  return t;
}

PlanarTransform BaseToLaser(const solvers::Mount& mount, const io::AntennaInBase& antenna,
                            const EmitFrames& frames) {
  // base_T_antenna is a pure translation (the antenna frame shares base_link's axes), so the
  // composition adds the translations and keeps the mount's yaw.
  PlanarTransform t;
  t.parent = frames.base;
  t.child = frames.child;
  t.x_m = antenna.x_m + mount.x_m;
  t.y_m = antenna.y_m + mount.y_m;
  t.z_m = antenna.z_m;
  t.yaw_rad = mount.yaw_rad;
  return t;
}

std::string FormatEmit(EmitFormat format, const solvers::MountEstimate& estimate,
                       const std::optional<io::AntennaInBase>& antenna_in_base,
                       const EmitFrames& frames) {
  CheckFrames(frames);
  const PlanarTransform antenna_t = AntennaToLaser(estimate.mount, frames);
  std::optional<PlanarTransform> base_t;
  if (antenna_in_base) base_t = BaseToLaser(estimate.mount, *antenna_in_base, frames);
  std::string out;
  switch (format) {
    case EmitFormat::kRos2StaticTf:
      out += Ros2Line(antenna_t);
      if (base_t) {
        out += std::string("# ") + frames.base + " -> " + frames.child + ": " + kHeightNote + "\n";
        out += Ros2Line(*base_t);
      }
      break;
    case EmitFormat::kUrdf:
      out += UrdfJoint(antenna_t);
      if (base_t) {
        out += std::string("<!-- ") + frames.base + " -> " + frames.child + ": " + kHeightNote +
               " -->\n";
        out += UrdfJoint(*base_t);
      }
      break;
    case EmitFormat::kJson: {
      const Eigen::Matrix3d& c = estimate.covariance;
      out += "{\n";
      out += "  \"method\": " + JsonString(estimate.method) + ",\n";
      out += "  \"parent_frame\": " + JsonString(frames.parent) + ",\n";
      out += "  \"child_frame\": " + JsonString(frames.child) + ",\n";
      out += "  \"mount\": {\"x_m\": " + Num(antenna_t.x_m) + ", \"y_m\": " + Num(antenna_t.y_m) +
             ", \"z_m\": 0, \"yaw_rad\": " + Num(antenna_t.yaw_rad) +
             ", \"yaw_deg\": " + Num(antenna_t.yaw_rad * kRadToDeg) + "},\n";
      out += "  \"sigma\": {\"x_m\": " + Num(Sigma(c, 0)) + ", \"y_m\": " + Num(Sigma(c, 1)) +
             ", \"yaw_rad\": " + Num(Sigma(c, 2)) +
             ", \"yaw_deg\": " + Num(Sigma(c, 2) * kRadToDeg) + "},\n";
      out += "  \"covariance\": {\"order\": [\"x_m\", \"y_m\", \"yaw_rad\"], \"matrix\": [";
      for (int r = 0; r < 3; ++r) {
        out += r ? ", [" : "[";
        for (int col = 0; col < 3; ++col) out += (col ? ", " : "") + Num(c(r, col));
        out += "]";
      }
      out += "]},\n";
      if (base_t) {
        out += "  \"base_link\": {\"parent_frame\": " + JsonString(base_t->parent) +
               ", \"child_frame\": " + JsonString(base_t->child) + ", \"x_m\": " +
               Num(base_t->x_m) + ", \"y_m\": " + Num(base_t->y_m) + ", \"z_m\": " +
               Num(base_t->z_m) + ", \"yaw_rad\": " + Num(base_t->yaw_rad) +
               ", \"yaw_deg\": " + Num(base_t->yaw_rad * kRadToDeg) +
               ", \"note\": " + JsonString(kHeightNote) + "}\n";
      } else {
        out += "  \"base_link\": null\n";
      }
      out += "}\n";
      break;
    }
  }
  return out;
}

}  // namespace wallcal::outputs
