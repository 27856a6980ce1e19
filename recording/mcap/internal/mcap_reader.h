// SPDX-License-Identifier: Apache-2.0
#pragma once
// MCAP recordings (mcap.dev/spec) with the ros2 profile: channels whose message_encoding is
// "cdr", schemas "ros2msg" / "ros2idl" named like "sensor_msgs/msg/LaserScan" (the topic's type).
// Chunks uncompressed, "zstd" or "lz4" (frame format).
//
// Reading: through the summary (footer -> Schema, Channel, Chunk Index, Statistics records, and
// the Message Index records after each chunk) when the file has a usable one; otherwise by
// walking the data section record by record, with a warning saying why (a crashed recorder
// leaves no footer). CRCs are checked where the file gives them (chunk uncompressed_crc,
// Data End data_section_crc, footer summary_crc; 0 means none): a mismatch throws io::InputError
// "path:offset: ...". A file cut off after usable data is read up to the cut, with a warning
// counting the bytes lost. ForEach decompresses only the chunks that hold requested channels.
// Messages whose encoding is not "cdr" are listed in topics(); ForEach on them throws.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "recording/recording.h"

namespace wallcal::recording {

struct McapLimits {
  // Largest chunk (decompressed records) accepted: a sanity cap against hostile sizes; chunks
  // that declare more throw io::InputError.
  uint64_t max_chunk_bytes = uint64_t{1} << 30;
};

// Opens the MCAP file at `path` (reads its index or walks it; messages stay on disk until
// ForEach). Throws io::InputError when it is not MCAP or is damaged before any usable data.
std::unique_ptr<Recording> OpenMcap(const std::string& path, const McapLimits& limits = {});

// An MCAP file still being written, read on record by record (recording/recording_tail.h;
// mcap_tail.cc).
class RecordingTail;
std::unique_ptr<RecordingTail> OpenMcapTail(const std::string& path);

// The same over bytes in memory (tests, fuzzing); `name` stands for the file in messages.
std::unique_ptr<Recording> OpenMcapBuffer(const std::string& name, std::vector<uint8_t> bytes,
                                          const McapLimits& limits = {});

}  // namespace wallcal::recording
