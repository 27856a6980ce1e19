// SPDX-License-Identifier: Apache-2.0
#pragma once
// The calibrated mount in the forms navigation stacks read: a ROS 2
// static_transform_publisher command line, a URDF <joint>, and a JSON object.
//
// Frames: the mount is parent_T_child with parent = the GNSS antenna frame (x forward, y left,
// z up, no rotation relative to the vehicle) and child = the scanner. Units: metres and radians
// (ROS and URDF conventions); the JSON also carries degrees for the yaw, named as such. The
// scan plane is treated as horizontal, so z, roll and pitch of the scanner relative to the
// antenna are 0: the 2-D calibration does not see them.
//
// base_link: when the session gives the antenna's position in base_link
// (io::SessionSpec::antenna_in_base), base_T_antenna is emitted too (the antenna frame is not
// rotated relative to base_link): one tree base -> antenna -> laser. The scanner's height
// relative to the antenna comes from session.yaml `scanner.z_m`; the calibration does not
// measure it, and when it is not given every form says so.

#include <optional>
#include <string>
#include <vector>

#include "io/types.h"
#include "pipeline/verdict.h"
#include "solvers/mount_solver.h"

namespace wallcal::outputs {

enum class EmitFormat { kRos2StaticTf, kUrdf, kJson };

// "ros2-static-tf", "urdf", "json" -> the format; false for anything else.
bool ParseEmitFormat(const std::string& name, EmitFormat* format);

struct EmitFrames {
  std::string parent = "gnss_antenna";  // the antenna frame (the mount's parent)
  std::string child = "laser";          // the scanner frame
  std::string base = "base_link";       // the vehicle frame, used with antenna_in_base
};

// A frame name as tf2 takes it, and safe on a shell command line, in XML attributes and JSON
// strings without quoting: 1..128 characters of [A-Za-z0-9_./-], not starting with '-' or
// '/' (tf2 rejects a leading '/'), not ending with '/', no "//" and no "--".
bool IsValidFrameName(const std::string& name);
// Why `name` is not valid ("" when it is), for the user.
std::string FrameNameProblem(const std::string& name);

// A rigid 2-D-on-3-D transform, parent_T_child, metres and radians (roll = pitch = 0).
struct PlanarTransform {
  std::string parent, child;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0, yaw_rad = 0.0;
  // The child's tilt (session.yaml scanner.pitch_deg / roll_deg): pitch positive nose up, roll
  // positive right side down; child axes = Rz(yaw) · Ry(−pitch) · Rx(roll) in the parent's, i.e.
  // ROS roll-pitch-yaw (roll, −pitch, yaw).
  double pitch_rad = 0.0, roll_rad = 0.0;
};

// antenna_T_laser from the mount; z = scanner_z_m (session.yaml scanner.z_m), 0 when unknown.
PlanarTransform AntennaToLaser(const solvers::Mount& mount, const EmitFrames& frames,
                               double scanner_z_m = 0.0);

// base_T_antenna: the antenna_in_base translation (the antenna frame has base_link's axes).
PlanarTransform BaseToAntenna(const io::AntennaInBase& antenna, const EmitFrames& frames);

// base_T_laser = base_T_antenna · antenna_T_laser: translation antenna_in_base + (x, y),
// z = antenna z, yaw = mount yaw.
PlanarTransform BaseToLaser(const solvers::Mount& mount, const io::AntennaInBase& antenna,
                            const EmitFrames& frames);

// One `ros2 run tf2_ros static_transform_publisher ...` line (ends with a newline).
std::string Ros2StaticTfLine(const PlanarTransform& transform);
// A whole URDF document with one <link> per frame and one fixed <joint> per transform; z_known
// false adds the note that z is 0 because the height is not known.
std::string UrdfTree(const std::vector<PlanarTransform>& joints, bool z_known);
// --emit json's last member: `  "base_link": {...}` for base_T_antenna, or null without
// antenna_in_base (ends with a newline).
std::string JsonBaseLinkMember(const PlanarTransform* base_t);
// A verdict as offsets.yaml's `verdict:` map writes it: {"verdict": "ACCEPT"|"REVIEW"|"REJECT",
// "reasons": ["...", ...]} (no newline).
std::string JsonDecision(const pipeline::Decision& decision);

// The emitted text (ends with a newline). One tree: with antenna_in_base the transforms are
// base -> parent (base_T_antenna) and parent -> child (the mount); a frame never has two
// parents. When scanner_z_m is unknown, parent -> child carries z = 0 and the text says so
// (a `#` line, an XML comment, a JSON "z_note").
//  kRos2StaticTf  `ros2 run tf2_ros static_transform_publisher --x X --y Y --z Z --yaw YAW
//                 --pitch 0 --roll 0 --frame-id P --child-frame-id C` lines, base -> antenna
//                 first when given.
//  kUrdf          a whole well-formed URDF document: <?xml?>, <robot name="wallcal_mount">
//                 with one <link> per frame and one fixed <joint name="P_to_C"> per transform
//                 (<parent link>, <child link>, <origin xyz="X Y Z" rpy="0 0 YAW"/>); copy the
//                 joints into the vehicle's URDF.
//  kJson          one object: {"method", "parent_frame", "child_frame", "mount": {x_m, y_m, z_m,
//                 yaw_rad, yaw_deg}, "z_known", "sigma": {x_m, y_m, yaw_rad, yaw_deg} or null,
//                 "covariance": {"order": [...], "matrix": [[...], [...], [...]]} or null,
//                 "verdict": {"verdict", "reasons"} (JsonDecision of `verdict`; null when not
//                 given), "base_link": null or {"parent_frame", "child_frame", x_m, y_m, z_m,
//                 yaw_rad, yaw_deg} (base_T_antenna)}.
// Numbers are printed with 9 significant digits. σ is null when the covariance is not finite
// (a method without an error model). Frame names must satisfy IsValidFrameName (invalid names
// throw std::invalid_argument here).
std::string FormatEmit(EmitFormat format, const solvers::MountEstimate& estimate,
                       const std::optional<io::AntennaInBase>& antenna_in_base,
                       const EmitFrames& frames,
                       const std::optional<double>& scanner_z_m = std::nullopt,
                       const pipeline::Decision* verdict = nullptr,
                       const io::ScannerTilt& tilt = io::ScannerTilt());

}  // namespace wallcal::outputs
