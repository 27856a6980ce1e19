// SPDX-License-Identifier: Apache-2.0
#pragma once
// simulate --format: the simulated session as a robot recording instead of text logs.

#include <cstdint>
#include <optional>
#include <string>

#include "sim/simulation_config.h"
#include "sim/simulated_session.h"

namespace wallcal::sim {

// The container the session's streams are written in. ROS 1 bags: chunks uncompressed, bz2 or
// lz4; MCAP: zstd (the ros2 default) or lz4; rosbag2 sqlite3: one .db3 file (Iron layout).
enum class SessionFormat { kText, kRos1, kRos1Bz2, kRos1Lz4, kMcap, kMcapLz4, kDb3 };

// "text", "ros1", "ros1-bz2", "ros1-lz4", "mcap" (zstd), "mcap-lz4", "db3"; nullopt otherwise.
std::optional<SessionFormat> ParseSessionFormat(const std::string& name);
// The names ParseSessionFormat takes, for messages: "text, ros1, ros1-bz2, ...".
const char* SessionFormatNames();

// Writes the simulated session as WriteSimulatedSession does, then, for a recording format,
// moves the three streams into one recording in `dir` (session.bag, session.mcap or
// session.db3; the text logs are removed) and rewrites session.yaml to name it and its topics:
//   /scan     sensor_msgs/LaserScan (the CARMEN scans, range_max = the log's maximum)
//   /fix      sensor_msgs/NavSatFix (status GBAS fix; position_covariance diagonal from the
//             simulated GST σ, type 2 "diagonal known"; height = the GGA height)
//   /heading  geometry_msgs/QuaternionStamped (ENU yaw = π/2 − heading)
//   /imu/data sensor_msgs/Imu, when the session has an attitude stream: the orientation from
//             each sample's roll and pitch and the yaw of the heading log at its time
//             (interpolated), orientation_covariance diagonal (σ_roll², σ_pitch², 0; 0 where
//             the sample gives no σ); session.yaml's attitude: names it
// Header stamps and receive times are the text logs' logger stamps.
SimulateSummary WriteSimulatedSession(const sim::SimulationConfig& config, uint64_t seed,
                                      const std::string& dir, SessionFormat format);

// Converts the text session in `dir` (as simulate writes it) to `format` in place (see above).
void ConvertSessionToRecording(const std::string& dir, SessionFormat format);

}  // namespace wallcal::sim
