// SPDX-License-Identifier: Apache-2.0
#pragma once
// A ROS 1 bag still being recorded or an MCAP file still being written, read on from where the
// last read stopped: each read walks only the whole records the file gained since (a ROS 1
// bag's closed chunks and connection records; an MCAP data section's chunks, loose messages,
// schema and channel records), keeping the connections, channels and schemas met so far. A
// record still being written at the end (a chunk whose lengths are not yet filled in, a record
// cut off by the file's end) is left for the next read. Neither the index nor the summary is
// read (a file still being written has none); an MCAP file's Data End or Footer ends the reads.
//
// Errors (io::InputError "file:byte N: what"): a file that is not a v2.0 bag or MCAP, a record
// that does not parse, a closed chunk that does not decompress to its declared size.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "recording/recording.h"

namespace wallcal::recording {

// What one read covered.
struct TailRead {
  uint64_t from_byte = 0;   // where it started (0: the file's start)
  uint64_t to_byte = 0;     // after the last whole record read: the next read starts here
  uint64_t file_bytes = 0;  // the file's size when read
  bool restarted = false;   // the file was shorter than what was read before (a new recording
                            // under the same name): read from its start, topics forgotten
  int64_t messages = 0;     // messages passed to the callback
};

class RecordingTail {
 public:
  virtual ~RecordingTail() = default;
  virtual RecordingFormat format() const = 0;
  const std::string& path() const { return path_; }

  // Reads the whole records the file gained since the last read and calls `fn` for each message
  // on `topic_name` they hold, in receive-time order within a chunk (file order across chunks).
  // RecordedMessage::index counts the topic's messages over every read; its topic points at
  // topics().at(topic_name), which stays valid. Throws io::InputError (see above).
  TailRead ReadOn(const std::string& topic_name,
                  const std::function<void(const RecordedMessage&)>& fn);

  // The topics met so far (their connection or channel records read), by name; count = the
  // messages met on it; first_s/last_s unset.
  const std::map<std::string, TopicInfo>& topics() const { return topics_; }

 protected:
  explicit RecordingTail(std::string path) : path_(std::move(path)) {}
  // Forgets everything read (the file is read from its start next).
  virtual void Reset() = 0;
  // Walks the whole records in [from_byte, file_bytes); returns where the next read starts.
  virtual uint64_t Walk(uint64_t from_byte, uint64_t file_bytes, const std::string& topic_name,
                        const std::function<void(const RecordedMessage&)>& fn) = 0;
  // The topic `name` (added with `type`, `md5sum`, `encoding` the first time it is met).
  TopicInfo* Topic(const std::string& name, const std::string& type, const std::string& md5sum,
                   const std::string& encoding);

  std::string path_;
  std::map<std::string, TopicInfo> topics_;
  uint64_t resume_byte_ = 0;
};

// Opens a ROS 1 bag or an MCAP file for reading on (nothing read yet; the file may not hold
// its first record yet). nullptr for another container (a rosbag2 folder, an SQLite file) or
// a text log. Throws io::InputError when `path` cannot be opened.
std::unique_ptr<RecordingTail> OpenRecordingTail(const std::string& path);

}  // namespace wallcal::recording
