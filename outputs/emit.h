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
// (io::SessionSpec::antenna_in_base), the mount is also composed into base_T_laser =
// base_T_antenna · antenna_T_laser (the antenna frame is not rotated relative to base_link),
// and the scanner's z in base_link is taken to be the antenna's z: the calibration does not
// measure the height difference, and every form says so.

#include <optional>
#include <string>

#include "io/types.h"
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

// A frame name that is safe on a shell command line, in XML attributes and JSON strings
// without quoting: 1..128 characters of [A-Za-z0-9_./-], not starting with '-'.
bool IsValidFrameName(const std::string& name);

// A rigid 2-D-on-3-D transform, parent_T_child, metres and radians (roll = pitch = 0).
struct PlanarTransform {
  std::string parent, child;
  double x_m = 0.0, y_m = 0.0, z_m = 0.0, yaw_rad = 0.0;
};

// antenna_T_laser from the mount (z = 0).
PlanarTransform AntennaToLaser(const solvers::Mount& mount, const EmitFrames& frames);

// base_T_laser = base_T_antenna · antenna_T_laser: translation antenna_in_base + (x, y),
// z = antenna z, yaw = mount yaw.
PlanarTransform BaseToLaser(const solvers::Mount& mount, const io::AntennaInBase& antenna,
                            const EmitFrames& frames);

// The emitted text (ends with a newline):
//  kRos2StaticTf  one `ros2 run tf2_ros static_transform_publisher --x X --y Y --z Z --yaw YAW
//                 --pitch 0 --roll 0 --frame-id P --child-frame-id C` line for antenna -> laser,
//                 and with antenna_in_base a second one for base_link -> laser, preceded by a
//                 `#` comment line (shell comment) saying z is the antenna's height.
//  kUrdf          one `<joint name="P_to_C" type="fixed">` element with <parent link>,
//                 <child link> and <origin xyz="X Y Z" rpy="0 0 YAW"/>, per transform; with two
//                 joints, an XML comment precedes the second one.
//  kJson          one object: {"method", "parent_frame", "child_frame", "mount": {x_m, y_m, z_m,
//                 yaw_rad, yaw_deg}, "sigma": {x_m, y_m, yaw_rad, yaw_deg}, "covariance":
//                 {"order": ["x_m", "y_m", "yaw_rad"], "matrix": [[...], [...], [...]]},
//                 "base_link": null or {"parent_frame", "child_frame", x_m, y_m, z_m, yaw_rad,
//                 yaw_deg, "note"}}.
// Numbers are printed with 9 significant digits. Frame names must satisfy IsValidFrameName
// (the caller checks; invalid names throw std::invalid_argument here).
std::string FormatEmit(EmitFormat format, const solvers::MountEstimate& estimate,
                       const std::optional<io::AntennaInBase>& antenna_in_base,
                       const EmitFrames& frames);

}  // namespace wallcal::outputs
