// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the ROS message decoders, every type on both wires. The first input byte
// picks the type (its value modulo 5) and the wire (bit 3 set: CDR); the rest is the payload. A
// decode either fails with an offset inside the payload, or succeeds; then re-encoding and decoding
// again must succeed and give the same message (compared by its encoding with the stamp zeroed:
// stamps pass through a double and may move by a rounding step). An Imu's attitude keeps the
// attitude stream's promises (recording/attitude_stream.h).

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "recording/attitude_stream.h"
#include "recording/ros/ros_messages.h"

namespace {

using namespace wallcal::recording;

template <class M, class Decode, class Encode>
void Check(const uint8_t* data, size_t size, WireFormat wire, Decode decode, Encode encode) {
  M first;
  const DecodeResult r = decode(data, size, wire, &first);
  if (r.offset > size) std::abort();
  if (!r.ok()) return;
  const std::vector<uint8_t> bytes = encode(first, wire);
  M second;
  if (!decode(bytes.data(), bytes.size(), wire, &second).ok()) std::abort();
  first.header.stamp_s = second.header.stamp_s = 0.0;
  if (encode(first, wire) != encode(second, wire)) std::abort();
}

// An Imu that decodes gives an attitude sample within ±io::kMaxVehicleTiltRad with σ positive
// or NaN, or a typed reason to skip it.
void CheckImuAttitude(const uint8_t* data, size_t size, WireFormat wire) {
  QuaternionMsg msg;
  if (!DecodeImu(data, size, wire, &msg).ok()) return;
  wallcal::io::AttitudeSample sample;
  if (AttitudeFromImu(msg, &sample) != ImuAttitude::kSample) return;
  const double limit = wallcal::io::kMaxVehicleTiltRad;
  const auto sigma_ok = [](double sigma) { return std::isnan(sigma) || sigma > 0.0; };
  if (!(std::abs(sample.roll_rad) <= limit) || !(std::abs(sample.pitch_rad) <= limit) ||
      !sigma_ok(sample.roll_sigma_rad) || !sigma_ok(sample.pitch_sigma_rad)) {
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const WireFormat wire = (data[0] & 8) != 0 ? WireFormat::kCdr : WireFormat::kRos1;
  const uint8_t* payload = data + 1;
  const size_t n = size - 1;
  // The payload in its own allocation, so that any read past it is an ASan report.
  const std::vector<uint8_t> copy(payload, payload + n);
  switch (data[0] % 5) {
    case 0: Check<LaserScanMsg>(copy.data(), n, wire, DecodeLaserScan, EncodeLaserScan); break;
    case 1: Check<NavSatFixMsg>(copy.data(), n, wire, DecodeNavSatFix, EncodeNavSatFix); break;
    case 2:
      Check<NmeaSentenceMsg>(copy.data(), n, wire, DecodeNmeaSentence, EncodeNmeaSentence);
      break;
    case 3:
      Check<QuaternionMsg>(copy.data(), n, wire, DecodeQuaternionStamped, EncodeQuaternionStamped);
      break;
    default:
      Check<QuaternionMsg>(copy.data(), n, wire, DecodeImu, EncodeImu);
      CheckImuAttitude(copy.data(), n, wire);
      break;
  }
  return 0;
}
