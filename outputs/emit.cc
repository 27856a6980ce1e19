// SPDX-License-Identifier: Apache-2.0
#include "outputs/emit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <vector>

#include "common/angles.h"
#include "outputs/json_text.h"

namespace wallcal::outputs {
namespace {
double Sigma(const Eigen::Matrix3d& covariance, int i) {
  return std::sqrt(std::max(0.0, covariance(i, i)));
}

const char* kHeightNote =
    "z = 0: the scanner's height relative to the GNSS antenna is not known (give it as "
    "scanner.z_m in session.yaml); the 2-D calibration does not measure it";

// An angle of ROS's roll-pitch-yaw: "0" when untilted.
std::string RosAngle(double angle_rad) { return angle_rad == 0.0 ? "0" : Num(angle_rad); }

std::string Ros2Line(const PlanarTransform& t) {
  return "ros2 run tf2_ros static_transform_publisher --x " + Num(t.x_m) + " --y " + Num(t.y_m) +
         " --z " + Num(t.z_m) + " --yaw " + Num(t.yaw_rad) + " --pitch " +
         RosAngle(0.0 - t.pitch_rad) + " --roll " + RosAngle(t.roll_rad) + " --frame-id " +
         t.parent + " --child-frame-id " + t.child + "\n";
}

std::string UrdfJoint(const PlanarTransform& t) {
  return "<joint name=\"" + t.parent + "_to_" + t.child + "\" type=\"fixed\">\n" +
         "  <parent link=\"" + t.parent + "\"/>\n" + "  <child link=\"" + t.child + "\"/>\n" +
         "  <origin xyz=\"" + Num(t.x_m) + " " + Num(t.y_m) + " " + Num(t.z_m) +
         "\" rpy=\"" + RosAngle(t.roll_rad) + " " + RosAngle(0.0 - t.pitch_rad) + " " + Num(t.yaw_rad) +
         "\"/>\n" + "</joint>\n";
}

void CheckFrames(const EmitFrames& frames) {
  for (const std::string* name : {&frames.parent, &frames.child, &frames.base}) {
    if (!IsValidFrameName(*name)) {
      throw std::invalid_argument("invalid frame name '" + *name + "'");
    }
  }
  if (frames.parent == frames.child || frames.parent == frames.base ||
      frames.child == frames.base) {
    throw std::invalid_argument("the frames must have three different names");
  }
}

std::string UrdfDocument(const std::vector<PlanarTransform>& joints, bool z_known) {
  std::string out = "<?xml version=\"1.0\"?>\n";
  out += "<!-- The calibrated scanner mount (wallcal). Copy the joints into the vehicle's URDF. -->\n";
  if (!z_known) out += std::string("<!-- ") + kHeightNote + " -->\n";
  out += "<robot name=\"wallcal_mount\">\n";
  std::vector<std::string> links;
  for (const PlanarTransform& t : joints) {
    for (const std::string* name : {&t.parent, &t.child}) {
      if (std::find(links.begin(), links.end(), *name) == links.end()) links.push_back(*name);
    }
  }
  for (const std::string& link : links) out += "  <link name=\"" + link + "\"/>\n";
  for (const PlanarTransform& t : joints) {
    std::string joint = UrdfJoint(t);
    // Indent the joint's lines inside <robot>.
    std::string indented;
    size_t start = 0;
    while (start < joint.size()) {
      const size_t end = joint.find('\n', start);
      indented += "  " + joint.substr(start, end - start + 1);
      start = end + 1;
    }
    out += indented;
  }
  return out + "</robot>\n";
}

}  // namespace

std::string Ros2StaticTfLine(const PlanarTransform& transform) { return Ros2Line(transform); }

std::string UrdfTree(const std::vector<PlanarTransform>& joints, bool z_known) {
  return UrdfDocument(joints, z_known);
}

std::string JsonBaseLinkMember(const PlanarTransform* base_t) {
  if (base_t == nullptr) return "  \"base_link\": null\n";
  return "  \"base_link\": {\"parent_frame\": " + JsonString(base_t->parent) +
         ", \"child_frame\": " + JsonString(base_t->child) + ", \"x_m\": " + Num(base_t->x_m) +
         ", \"y_m\": " + Num(base_t->y_m) + ", \"z_m\": " + Num(base_t->z_m) +
         ", \"yaw_rad\": 0, \"yaw_deg\": 0}\n";
}

std::string JsonDecision(const pipeline::Decision& decision) {
  std::string out = std::string("{\"verdict\": \"") + pipeline::VerdictName(decision.verdict) +
                    "\", \"reasons\": [";
  for (size_t i = 0; i < decision.reasons.size(); ++i) {
    out += (i ? ", " : "") + JsonString(decision.reasons[i]);
  }
  return out + "]}";
}

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

std::string FrameNameProblem(const std::string& name) {
  if (name.empty()) return "empty";
  if (name.size() > 128) return "longer than 128 characters";
  if (name[0] == '/') return "starts with '/' (tf2 rejects frame ids with a leading slash)";
  if (name[0] == '-') return "starts with '-'";
  if (name.back() == '/') return "ends with '/'";
  if (name.find("//") != std::string::npos) return "has an empty segment ('//')";
  if (name.find("--") != std::string::npos) return "has '--'";
  for (char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '/' || c == '-';
    if (!ok) return "has characters other than letters, digits, '_', '.', '/', '-'";
  }
  return std::string();
}

bool IsValidFrameName(const std::string& name) { return FrameNameProblem(name).empty(); }

PlanarTransform AntennaToLaser(const solvers::Mount& mount, const EmitFrames& frames,
                               double scanner_z_m) {
  PlanarTransform t;
  t.parent = frames.parent;
  t.child = frames.child;
  t.x_m = mount.x_m;
  t.y_m = mount.y_m;
  t.z_m = scanner_z_m;
  t.yaw_rad = mount.yaw_rad;
  return t;
}

PlanarTransform BaseToAntenna(const io::AntennaInBase& antenna, const EmitFrames& frames) {
  PlanarTransform t;
  t.parent = frames.base;
  t.child = frames.parent;
  t.x_m = antenna.x_m;
  t.y_m = antenna.y_m;
  t.z_m = antenna.z_m;
  t.yaw_rad = 0.0;
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
                       const EmitFrames& frames, const std::optional<double>& scanner_z_m,
                       const pipeline::Decision* verdict, const io::ScannerTilt& tilt) {
  CheckFrames(frames);
  const bool z_known = scanner_z_m.has_value();
  PlanarTransform antenna_t = AntennaToLaser(estimate.mount, frames, scanner_z_m.value_or(0.0));
  antenna_t.pitch_rad = tilt.pitch_rad;
  antenna_t.roll_rad = tilt.roll_rad;
  std::optional<PlanarTransform> base_t;
  if (antenna_in_base) base_t = BaseToAntenna(*antenna_in_base, frames);
  std::string out;
  switch (format) {
    case EmitFormat::kRos2StaticTf:
      if (base_t) out += Ros2Line(*base_t);
      if (!z_known) out += std::string("# ") + frames.parent + " -> " + frames.child + ": " + kHeightNote + "\n";
      out += Ros2Line(antenna_t);
      break;
    case EmitFormat::kUrdf: {
      std::vector<PlanarTransform> joints;
      if (base_t) joints.push_back(*base_t);
      joints.push_back(antenna_t);
      out += UrdfDocument(joints, z_known);
      break;
    }
    case EmitFormat::kJson: {
      const Eigen::Matrix3d& c = estimate.covariance;
      const bool sigma_known = c.allFinite();
      out += "{\n";
      out += "  \"method\": " + JsonString(solvers::MethodText(estimate)) + ",\n";
      out += "  \"parent_frame\": " + JsonString(frames.parent) + ",\n";
      out += "  \"child_frame\": " + JsonString(frames.child) + ",\n";
      out += "  \"mount\": {\"x_m\": " + Num(antenna_t.x_m) + ", \"y_m\": " + Num(antenna_t.y_m) +
             ", \"z_m\": " + Num(antenna_t.z_m) + ", \"yaw_rad\": " + Num(antenna_t.yaw_rad) +
             ", \"yaw_deg\": " + Num(antenna_t.yaw_rad * kRadToDeg) +
             (tilt.given ? ", \"pitch_rad\": " + Num(tilt.pitch_rad) + ", \"roll_rad\": " +
                               Num(tilt.roll_rad)
                         : std::string()) +
             "},\n";
      out += std::string("  \"z_known\": ") + (z_known ? "true" : "false") + ",\n";
      if (!z_known) out += "  \"z_note\": " + JsonString(kHeightNote) + ",\n";
      if (sigma_known) {
        out += "  \"sigma\": {\"x_m\": " + JsonNum(Sigma(c, 0)) + ", \"y_m\": " + JsonNum(Sigma(c, 1)) +
               ", \"yaw_rad\": " + JsonNum(Sigma(c, 2)) +
               ", \"yaw_deg\": " + JsonNum(Sigma(c, 2) * kRadToDeg) + "},\n";
        out += "  \"covariance\": {\"order\": [\"x_m\", \"y_m\", \"yaw_rad\"], \"matrix\": [";
        for (int r = 0; r < 3; ++r) {
          out += r ? ", [" : "[";
          for (int col = 0; col < 3; ++col) out += (col ? ", " : "") + JsonNum(c(r, col));
          out += "]";
        }
        out += "]},\n";
      } else {
        out += "  \"sigma\": null,\n  \"covariance\": null,\n";
      }
      out += "  \"verdict\": " + (verdict ? JsonDecision(*verdict) : std::string("null")) + ",\n";
      out += JsonBaseLinkMember(base_t ? &*base_t : nullptr);
      out += "}\n";
      break;
    }
  }
  return out;
}

}  // namespace wallcal::outputs
