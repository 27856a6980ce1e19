// SPDX-License-Identifier: Apache-2.0
#pragma once
// Fixtures for the recording readers' tests: where the shared ROS 2 recordings are, a fresh
// scratch folder per case, and the messages a Recording hands out, copied out of its callback.

#include <cstdint>
#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include "recording/recording.h"
#include "test/support/scratch_files.h"

namespace wallcal::testing_support {

// The ROS 2 recordings of the real test data (absent on machines without it: tests skip).
inline const std::string kRealRos2 = WALLCAL_SOURCE_DIR "/../shared/testdata/real/ros2";

// One message as the callback saw it.
struct GotMessage {
  std::string topic;
  double receive_s = 0;
  std::vector<uint8_t> data;
  int64_t index = 0;
  uint64_t file_offset = 0;
  recording::WireFormat wire = recording::WireFormat::kCdr;
};

// Every message of `topics`, in the order the recording hands them out.
inline std::vector<GotMessage> CollectMessages(recording::Recording& rec,
                                               const std::set<std::string>& topics) {
  std::vector<GotMessage> out;
  rec.ForEach(topics, [&](const recording::RecordedMessage& m) {
    out.push_back({m.topic->name, m.receive_s, std::vector<uint8_t>(m.data, m.data + m.size),
                   m.index, m.file_offset, m.wire});
  });
  return out;
}

}  // namespace wallcal::testing_support
