// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: rosbag2's metadata.yaml parser. It must return storage files to read (at
// least one, none empty) or throw io::InputError: a yaml-cpp exception escaping, a crash or a
// sanitizer report is a bug.

#include <cstdint>
#include <cstdlib>
#include <string>

#include "io/config/rosbag2_metadata.h"
#include "io/types.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    const wallcal::io::Rosbag2Metadata meta = wallcal::io::ParseRosbag2Metadata(
        std::string(reinterpret_cast<const char*>(data), size), "metadata.yaml");
    if (meta.relative_file_paths.empty()) std::abort();
    for (const std::string& f : meta.relative_file_paths) {
      if (f.empty()) std::abort();
    }
    for (const auto& t : meta.topics) {
      if (t.name.empty()) std::abort();
    }
  } catch (const wallcal::io::InputError&) {
  }
  return 0;
}
