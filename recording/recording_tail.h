// SPDX-License-Identifier: Apache-2.0
#pragma once
// A ROS 1 bag still being recorded, an MCAP file or a rosbag2 sqlite3 file (.db3) still being
// written, read on from where the last read stopped: each read walks only the whole records the
// file gained since (a ROS 1 bag's chunks and connection records; an MCAP data section's chunks,
// loose messages, schema and channel records; a .db3 file's rows after the last id read),
// keeping the connections, channels, schemas and topics met so far. A record still being
// written at the end (an MCAP record cut off by the file's end, a transaction not committed) is
// left for the next read; a ROS 1 bag's open chunk (its lengths not yet filled in, or cut off)
// is read as far as its whole records go and from its start again next time, passing over the
// records read. Neither the index nor the summary is read (a file still being written has
// none); an MCAP file's Data End or Footer ends the reads.
//
// Errors (io::InputError "file:byte N: what"): a file that is not a v2.0 bag or MCAP, a record
// that does not parse, a closed chunk that does not decompress to its declared size; a .db3
// file without the tables topics and messages.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>

#include "recording/recording.h"

namespace wallcal::recording {

// What one read covered.
struct TailRead {
  uint64_t from_byte = 0;   // where it started (0: the file's start; .db3: the size last read)
  uint64_t to_byte = 0;     // after the last whole record read: the next read starts here
                            // (.db3: the file's size)
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

// Opens a ROS 1 bag, an MCAP file or a .db3 file for reading on, by its magic (nothing read
// yet; the file may not hold its first record yet). nullptr for a rosbag2 folder or a text log.
std::unique_ptr<RecordingTail> OpenRecordingTail(const std::string& path);

}  // namespace wallcal::recording
