// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the MCAP reader, through its memory entry point. Opening and a ForEach over
// every cdr topic must either work or throw io::InputError; whatever it hands out must point
// into its own topic list and carry a payload that can be read. A crash, hang, sanitizer report
// or runaway allocation is a bug.

#include <cstdint>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include "io/types.h"
#include "recording/mcap/internal/mcap_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  wallcal::recording::McapLimits limits;
  limits.max_chunk_bytes = uint64_t{64} << 20;  // well inside libFuzzer's -rss_limit_mb
  try {
    auto rec =
        wallcal::recording::OpenMcapBuffer("fuzz.mcap", std::vector<uint8_t>(data, data + size), limits);
    const auto& topics = rec->topics();
    std::set<std::string> names;
    for (size_t i = 0; i < topics.size(); ++i) {
      if (i > 0 && !(topics[i - 1].name < topics[i].name)) std::abort();  // sorted, unique
      if (topics[i].count < 0) std::abort();
      if (topics[i].encoding == "cdr") names.insert(topics[i].name);
    }
    uint64_t checksum = 0;
    rec->ForEach(names, [&](const wallcal::recording::RecordedMessage& m) {
      if (m.topic < topics.data() || m.topic >= topics.data() + topics.size()) std::abort();
      if (names.count(m.topic->name) == 0 || m.index < 0) std::abort();
      if (m.size > 0 && m.data == nullptr) std::abort();
      for (size_t i = 0; i < m.size; ++i) checksum += m.data[i];  // ASan: the bytes are live
    });
    volatile uint64_t sink = checksum;  // keeps the reads
    (void)sink;
  } catch (const wallcal::io::InputError&) {
  }
  return 0;
}
