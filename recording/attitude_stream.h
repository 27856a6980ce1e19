// SPDX-License-Identifier: Apache-2.0
#pragma once
// A session's attitude stream (session.yaml `attitude:`): the vehicle's roll and pitch as
// io::AttitudeSample, whatever holds them. recording::ReadPoseLogs (recording_streams.h) reads
// it with the GNSS and heading streams, each file once:
// - an NMEA text log: its $PASHR and $PTNL,AVR sentences (io::ReadNmea; the heading or GNSS log
//   itself when attitude.log names it, or a log of its own);
// - a recording topic (attitude.topic): sensor_msgs/Imu, or nmea_msgs/Sentence whose sentences
//   go through the NMEA reader as a logger-stamped text log would.
// Every sample's stamp has attitude.time_offset_s added.
//
// sensor_msgs/Imu -> io::AttitudeSample. REP 103: the body frame x forward, y left, z up; the
// orientation is the body's in an ENU world frame. Roll and pitch are the z-y-x Euler angles of
// the (normalised) quaternion. ROS's roll about +x turns the left side up, the right side down:
// it is AttitudeSample's roll as it is. ROS's pitch about +y (left) turns the nose down:
// pitch_rad = -(ROS pitch). σ from orientation_covariance (row-major about x, y, z; rad²):
// roll_sigma_rad = sqrt([0]), pitch_sigma_rad = sqrt([4]); a variance of 0 (the message's "all
// zeros: covariance unknown") is not given (NaN). The yaw is not used. The orientation is taken
// as the vehicle's: the message's frame_id is not looked up, so an IMU mounted turned on the
// vehicle gives its own frame's angles (one on its side: a roll near 90°, skipped as below).
// Skipped and counted: orientation_covariance[0] = -1 (the message's "no orientation"), a
// quaternion not finite or of zero length, a negative or non-finite variance, a roll or pitch
// beyond io::kMaxVehicleTiltRad (30°), a stamp not after the previous sample's.

#include <limits>
#include <string>
#include <vector>

#include "io/types.h"
#include "recording/ros/ros_messages.h"

namespace wallcal::recording {

// The types attitude.topic takes: sensor_msgs/Imu, nmea_msgs/Sentence ($PASHR, $PTNL,AVR).
std::vector<RosType> AcceptedAttitudeTypes();

// What one Imu message gives: typed, so no branch reads a message's text.
enum class ImuAttitude {
  kSample,         // the sample's roll, pitch and σ are set
  kNoOrientation,  // orientation_covariance[0] = -1
  kBadQuaternion,  // not finite, or of zero length
  kBadCovariance,  // a negative or non-finite roll or pitch variance
  kOutOfRange,     // |roll| or |pitch| beyond io::kMaxVehicleTiltRad
};
// Why a message was skipped, as the skip counts say it ("Imu without orientation ...").
const char* ImuAttitudeSkipReason(ImuAttitude outcome);

// The roll and pitch of an Imu's orientation into *sample (its stamp and line are the
// caller's), as described above.
ImuAttitude AttitudeFromImu(const QuaternionMsg& msg, io::AttitudeSample* sample);

// Roll and pitch (AttitudeSample's conventions, rad) of an ENU orientation quaternion; the
// quaternion need not be of unit length but must not be zero.
void RollPitchFromEnuQuaternion(double x, double y, double z, double w, double* roll_rad,
                                double* pitch_rad);

// The ENU orientation (REP 103) of a vehicle at roll_rad, pitch_rad (AttitudeSample's) and ENU
// yaw_rad (0 = east, counter-clockwise), as a unit quaternion.
struct UnitQuaternion {
  double x = 0.0, y = 0.0, z = 0.0, w = 1.0;
};
UnitQuaternion EnuQuaternionFromAttitude(double roll_rad, double pitch_rad, double yaw_rad);

// The attitude stream of a log already read: its attitudes with time_offset_s added, its
// skipped lines and lines read (its fixes and headings left out).
io::NmeaLog AttitudeStreamOf(const io::NmeaLog& log, double time_offset_s);

// An Imu topic as an attitude stream, message by message (one pass over a recording).
class ImuAttitudeStream {
 public:
  // One decoded message, stamped stamp_s (header or receive time); line = its index + 1.
  void Add(const QuaternionMsg& msg, double stamp_s, int line);
  // The samples, the skips and the messages read. Throws io::InputError naming `file` and
  // `topic` when the topic had messages and every one was without an orientation.
  io::NmeaLog Finish(const std::string& file, const std::string& topic) const;

 private:
  io::NmeaLog log_;
  int64_t without_orientation_ = 0;
  double last_stamp_s_ = -std::numeric_limits<double>::infinity();
};

// The attitude stream of a session alone (ReadPoseLogs reading neither GNSS nor heading): what
// inspect --dump attitude writes. Empty when the session names none. Throws io::InputError as
// ReadPoseLogs does.
io::NmeaLog ReadAttitudeLog(const io::SessionSpec& spec);

}  // namespace wallcal::recording
