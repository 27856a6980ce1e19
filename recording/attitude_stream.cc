// SPDX-License-Identifier: Apache-2.0
#include "recording/attitude_stream.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "common/angles.h"
#include "recording/recording_streams.h"

namespace wallcal::recording {
namespace {

// A variance of the orientation covariance as a σ: 0 -> not given (NaN); false when negative
// or not finite.
bool SigmaOfVariance(double variance_rad2, double* sigma_rad) {
  if (!std::isfinite(variance_rad2) || variance_rad2 < 0.0) return false;
  *sigma_rad = variance_rad2 > 0.0 ? std::sqrt(variance_rad2) : io::kNaN;
  return true;
}

}  // namespace

std::vector<RosType> AcceptedAttitudeTypes() { return {RosType::kImu, RosType::kNmeaSentence}; }

const char* ImuAttitudeSkipReason(ImuAttitude outcome) {
  switch (outcome) {
    case ImuAttitude::kSample:
      return "";
    case ImuAttitude::kNoOrientation:
      return "Imu without orientation (covariance[0] = -1)";
    case ImuAttitude::kBadQuaternion:
      return "quaternion not finite or zero";
    case ImuAttitude::kBadCovariance:
      return "Imu orientation covariance negative or not finite";
    case ImuAttitude::kOutOfRange:
      return io::kAttitudeOutOfRangeReason;
  }
  return "";
}

void RollPitchFromEnuQuaternion(double x, double y, double z, double w, double* roll_rad,
                                double* pitch_rad) {
  const double norm = std::sqrt(x * x + y * y + z * z + w * w);
  x /= norm;
  y /= norm;
  z /= norm;
  w /= norm;
  // R = Rz(yaw) · Ry(pitch_ros) · Rx(roll): roll and pitch from its third row.
  *roll_rad = std::atan2(2.0 * (w * x + y * z), 1.0 - 2.0 * (x * x + y * y));
  const double sin_pitch_ros = std::clamp(2.0 * (w * y - z * x), -1.0, 1.0);
  *pitch_rad = -std::asin(sin_pitch_ros);  // ROS pitch about +y (left) is nose down
}

UnitQuaternion EnuQuaternionFromAttitude(double roll_rad, double pitch_rad, double yaw_rad) {
  const double pitch_ros = -pitch_rad;
  const double cr = std::cos(0.5 * roll_rad), sr = std::sin(0.5 * roll_rad);
  const double cp = std::cos(0.5 * pitch_ros), sp = std::sin(0.5 * pitch_ros);
  const double cy = std::cos(0.5 * yaw_rad), sy = std::sin(0.5 * yaw_rad);
  UnitQuaternion q;  // qz(yaw) · qy(pitch_ros) · qx(roll)
  q.w = cr * cp * cy + sr * sp * sy;
  q.x = sr * cp * cy - cr * sp * sy;
  q.y = cr * sp * cy + sr * cp * sy;
  q.z = cr * cp * sy - sr * sp * cy;
  return q;
}

ImuAttitude AttitudeFromImu(const QuaternionMsg& msg, io::AttitudeSample* sample) {
  const double* covariance = msg.orientation_covariance;
  if (covariance[0] == -1.0) return ImuAttitude::kNoOrientation;
  const double norm = std::sqrt(msg.x * msg.x + msg.y * msg.y + msg.z * msg.z + msg.w * msg.w);
  if (!std::isfinite(norm) || norm < 1e-6) return ImuAttitude::kBadQuaternion;
  if (!SigmaOfVariance(covariance[0], &sample->roll_sigma_rad) ||
      !SigmaOfVariance(covariance[4], &sample->pitch_sigma_rad)) {
    return ImuAttitude::kBadCovariance;
  }
  RollPitchFromEnuQuaternion(msg.x, msg.y, msg.z, msg.w, &sample->roll_rad, &sample->pitch_rad);
  if (!(std::abs(sample->roll_rad) <= io::kMaxVehicleTiltRad) ||
      !(std::abs(sample->pitch_rad) <= io::kMaxVehicleTiltRad)) {
    return ImuAttitude::kOutOfRange;
  }
  return ImuAttitude::kSample;
}

io::NmeaLog AttitudeStreamOf(const io::NmeaLog& log, double time_offset_s) {
  io::NmeaLog stream;
  stream.attitudes = log.attitudes;
  for (io::AttitudeSample& sample : stream.attitudes) sample.stamp_s += time_offset_s;
  stream.attitudes_by_source = log.attitudes_by_source;
  stream.skipped = log.skipped;
  stream.lines_read = log.lines_read;
  return stream;
}

void ImuAttitudeStream::Add(const QuaternionMsg& msg, double stamp_s, int line) {
  ++log_.lines_read;
  io::AttitudeSample sample;
  const ImuAttitude outcome = AttitudeFromImu(msg, &sample);
  if (outcome != ImuAttitude::kSample) {
    if (outcome == ImuAttitude::kNoOrientation) ++without_orientation_;
    log_.skipped.Add(ImuAttitudeSkipReason(outcome), line);
    return;
  }
  if (!(stamp_s > last_stamp_s_)) {
    log_.skipped.Add("time not increasing", line);
    return;
  }
  last_stamp_s_ = stamp_s;
  sample.stamp_s = stamp_s;
  sample.line = line;
  log_.attitudes.push_back(sample);
  ++log_.attitudes_by_source["sensor_msgs/Imu"];
}

io::NmeaLog ImuAttitudeStream::Finish(const std::string& file, const std::string& topic) const {
  if (log_.lines_read > 0 && without_orientation_ == log_.lines_read) {
    throw io::InputError(io::Where(
        file, 0,
        "attitude.topic " + topic + ": every one of its " + std::to_string(log_.lines_read) +
            " sensor_msgs/Imu messages is without orientation (orientation_covariance[0] = -1); "
            "expected an Imu whose driver fills the orientation (an INS, or an IMU with an "
            "attitude filter), or attitude: removed from session.yaml"));
  }
  return log_;
}

io::NmeaLog ReadAttitudeLog(const io::SessionSpec& spec) {
  return ReadPoseLogs(spec, false, false, true).attitudes;
}

}  // namespace wallcal::recording
