// SPDX-License-Identifier: Apache-2.0
#pragma once
// The part the one-file tails share (ROS 1 bag, MCAP, .db3; recording/recording_tail.h): where
// the last read stopped, and a file shorter than that read from its start.

#include <cstdint>
#include <set>
#include <string>

#include "recording/recording_tail.h"

namespace wallcal::recording {

class FileTail : public RecordingTail {
 public:
  TailRead ReadOn(const std::set<std::string>& topic_names, const MessageFn& fn) final;

 protected:
  using RecordingTail::RecordingTail;
  // Forgets everything read (the file is read from its start next).
  virtual void Reset() = 0;
  // Walks the whole records in [from_byte, file_bytes), passing the messages on `topic_names`
  // to `fn`; returns where the next read starts.
  virtual uint64_t Walk(uint64_t from_byte, uint64_t file_bytes,
                        const std::set<std::string>& topic_names, const MessageFn& fn) = 0;

 private:
  uint64_t resume_byte_ = 0;
};

}  // namespace wallcal::recording
