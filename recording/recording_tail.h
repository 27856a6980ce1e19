// SPDX-License-Identifier: Apache-2.0
#pragma once
// A recording still being written, read on from where the last read stopped: a ROS 1 bag, an
// MCAP file, a rosbag2 sqlite3 file (.db3) or a rosbag2 folder. Each read walks only the whole
// records the recording gained since (a ROS 1 bag's chunks and connection records; an MCAP data
// section's chunks, loose messages, schema and channel records; a .db3 file's rows after the
// last id read; a folder's storage files, each read on so), keeping the connections, channels,
// schemas and topics met so far. A record still being written at the end (an MCAP record cut
// off by the file's end, a transaction not committed) is left for the next read; a ROS 1 bag's
// open chunk (its lengths not yet filled in, or cut off) is read as far as its whole records go
// and from its start again next time, passing over the records read. Neither the index nor the
// summary is read (a file still being written has none); an MCAP file's Data End or Footer ends
// the reads.
//
// A rosbag2 folder (rosbag2/internal/rosbag2_folder.h, rosbag2_folder_tail.cc): its
// storage files (.db3 or .mcap) in split order, metadata.yaml's relative_file_paths first when
// it is there, then the storage files it does not list (a recording that went on after a split)
// by their _N suffix; each read on through the .db3 or MCAP tail, the next one read as soon as
// it appears. The folder's byte offsets count its storage files' bytes in that order.
//
// Errors (io::InputError "file:byte N: what"): a file that is not a v2.0 bag or MCAP, a record
// that does not parse, a closed chunk that does not decompress to its declared size; a .db3
// file without the tables topics and messages; in a folder, a storage file that is neither
// SQLite nor MCAP, a compressed bag, a metadata.yaml that lists a file the folder lacks.

#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <set>
#include <string>

#include "recording/recording.h"

namespace wallcal::recording {

// What one read covered.
struct TailRead {
  uint64_t from_byte = 0;   // where it started (0: the recording's start; .db3: the size last
                            // read; a folder: the sum over its storage files)
  uint64_t to_byte = 0;     // after the last whole record read: the next read starts here
                            // (.db3: the file's size)
  uint64_t file_bytes = 0;  // the recording's size when read (a folder: its storage files')
  bool restarted = false;   // the recording was shorter than what was read before (a new one
                            // under the same name; a folder: a storage file read before is
                            // gone or shorter): read from its start, topics forgotten
  int64_t messages = 0;     // messages passed to the callback
};

using MessageFn = std::function<void(const RecordedMessage&)>;

class RecordingTail {
 public:
  virtual ~RecordingTail() = default;
  virtual RecordingFormat format() const = 0;
  const std::string& path() const { return path_; }

  // Reads the whole records the recording gained since the last read and calls `fn` for each
  // message on `topic_names` they hold, in receive-time order within a chunk (file order across
  // chunks and storage files). RecordedMessage::index counts its topic's messages over every
  // read; its topic points at topics().at(name), which stays valid until a restart. Throws
  // io::InputError (see above).
  virtual TailRead ReadOn(const std::set<std::string>& topic_names, const MessageFn& fn) = 0;

  // The topics met so far (their connection or channel records read), by name; count = the
  // messages met on it; first_s/last_s unset.
  const std::map<std::string, TopicInfo>& topics() const { return topics_; }

 protected:
  explicit RecordingTail(std::string path) : path_(std::move(path)) {}
  // The topic `name` (added with `type`, `md5sum`, `encoding` the first time it is met).
  TopicInfo* Topic(const std::string& name, const std::string& type, const std::string& md5sum,
                   const std::string& encoding);

  std::string path_;
  std::map<std::string, TopicInfo> topics_;
};

// Opens a ROS 1 bag, an MCAP file, a .db3 file or a rosbag2 folder (IsRecording) for reading on
// (nothing read yet; a file may not hold its first record yet). nullptr for a text log.
std::unique_ptr<RecordingTail> OpenRecordingTail(const std::string& path);

}  // namespace wallcal::recording
