// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the ROS 1 bag reader, from bytes in memory. Any input must either open and
// deliver messages that keep the reader's promises (receive-time order, per-topic indices
// counting up, counts as listed by topics(), payloads inside the chunk) or throw InputError.
// Every message of a supported type is decoded; a decode may fail (the payload is the
// fuzzer's) but must report an offset inside the payload.

#include <cstdint>
#include <cstdlib>
#include <map>
#include <vector>

#include "io/types.h"
#include "recording/ros/ros_messages.h"
#include "recording/rosbag1/internal/rosbag1_reader.h"

namespace {

using wallcal::recording::DecodeResult;
using wallcal::recording::RecordedMessage;

// Decodes the payload as an M: a failure must point inside the payload, a success must not hold
// more than the payload could (fits(msg)).
template <class M, class DecodeFn, class Fits>
void DecodeAs(const RecordedMessage& m, DecodeFn decode, Fits fits) {
  M msg;
  const DecodeResult r = decode(m.data, m.size, m.wire, &msg);
  if (r.offset > m.size || (r.ok() && !fits(msg))) std::abort();
}

void Decode(const RecordedMessage& m) {
  using namespace wallcal::recording;
  const auto any = [](const auto&) { return true; };
  switch (RosTypeFromName(m.topic->type)) {
    case RosType::kLaserScan:
      return DecodeAs<LaserScanMsg>(m, DecodeLaserScan, [&m](const LaserScanMsg& msg) {
        return msg.ranges_m.size() * 4 <= m.size;
      });
    case RosType::kNavSatFix:
      return DecodeAs<NavSatFixMsg>(m, DecodeNavSatFix, any);
    case RosType::kNmeaSentence:
      return DecodeAs<NmeaSentenceMsg>(m, DecodeNmeaSentence, [&m](const NmeaSentenceMsg& msg) {
        return msg.sentence.size() <= m.size;
      });
    case RosType::kQuaternionStamped:
      return DecodeAs<QuaternionMsg>(m, DecodeQuaternionStamped, any);
    case RosType::kImu:
      return DecodeAs<QuaternionMsg>(m, DecodeImu, any);
    case RosType::kOther:
      return;
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace wallcal::io;
  using namespace wallcal::recording;
  try {
    const auto bag = OpenRos1BagFromMemory(std::vector<uint8_t>(data, data + size), "fuzz.bag");
    std::set<std::string> names;
    std::map<const TopicInfo*, int64_t> seen;
    for (const TopicInfo& topic : bag->topics()) names.insert(topic.name);
    double last_s = -1.0;
    bag->ForEach(names, [&](const RecordedMessage& m) {
      if (m.topic == nullptr || m.wire != WireFormat::kRos1 || m.receive_s < last_s ||
          m.index != seen[m.topic]++ || m.size > size || m.file_offset >= size) {
        std::abort();
      }
      last_s = m.receive_s;
      Decode(m);
    });
    for (const TopicInfo& topic : bag->topics()) {
      const auto it = seen.find(&topic);
      if ((it == seen.end() ? 0 : it->second) != topic.count) std::abort();
    }
  } catch (const InputError&) {
  }
  return 0;
}
