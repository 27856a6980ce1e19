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

void Decode(const wallcal::recording::RecordedMessage& m) {
  using namespace wallcal::io;
  using namespace wallcal::recording;
  DecodeResult r;
  switch (RosTypeFromName(m.topic->type)) {
    case RosType::kLaserScan: {
      LaserScanMsg msg;
      r = DecodeLaserScan(m.data, m.size, m.wire, &msg);
      if (r.ok() && msg.ranges_m.size() * 4 > m.size) std::abort();
      break;
    }
    case RosType::kNavSatFix: {
      NavSatFixMsg msg;
      r = DecodeNavSatFix(m.data, m.size, m.wire, &msg);
      break;
    }
    case RosType::kNmeaSentence: {
      NmeaSentenceMsg msg;
      r = DecodeNmeaSentence(m.data, m.size, m.wire, &msg);
      if (r.ok() && msg.sentence.size() > m.size) std::abort();
      break;
    }
    case RosType::kQuaternionStamped: {
      QuaternionMsg msg;
      r = DecodeQuaternionStamped(m.data, m.size, m.wire, &msg);
      break;
    }
    case RosType::kImu: {
      QuaternionMsg msg;
      r = DecodeImu(m.data, m.size, m.wire, &msg);
      break;
    }
    case RosType::kOther:
      return;
  }
  if (r.offset > m.size) std::abort();
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
