// SPDX-License-Identifier: Apache-2.0
// A rosbag2 folder read on as it is recorded (recording/recording_tail.h): its storage files in
// split order (rosbag2_folder.h), each read on through the .db3 or MCAP tail.
//
// A split is not atomic: rosbag2 opens the next file before it has closed the one it leaves
// (the last rows committed, an MCAP file's summary written). So a file is read on at every read
// until it is done: a later file existed at the previous read and this read found the file as
// it was then (the same size). Rows it gains after the next file's first messages were passed
// on come after them, as the whole reader passes a seam's messages in file order.
//
// A folder replaced by a new recording under the same name is told by a storage file read
// before that is gone, no longer at its place in the split order, or shorter than it was; the
// folder is then read from its start (TailRead::restarted), as a file that shrank is. A new
// recording that is at least as long as the old one in each file read cannot be told apart.

#include <filesystem>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "io/types.h"
#include "recording/recording_tail.h"
#include "recording/rosbag2/internal/rosbag2_folder.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;

// The bytes that tell SQLite from MCAP (SQLite's magic, the longer one).
constexpr uint64_t kTellingBytes = 16;

class Rosbag2FolderTail : public RecordingTail {
 public:
  explicit Rosbag2FolderTail(std::string folder) : RecordingTail(std::move(folder)) {}

  RecordingFormat format() const override { return format_; }

  TailRead ReadOn(const std::set<std::string>& topic_names, const MessageFn& fn) override;

 private:
  // One storage file.
  struct Part {
    std::string path;
    std::unique_ptr<RecordingTail> tail;  // made once its first bytes tell its kind
    uint64_t size = 0;                    // its size at the last read
    uint64_t read_to = 0;                 // where its next read starts (TailRead::to_byte)
    bool later_seen = false;              // a later file existed at its last read
    bool done = false;                    // read to its end: not read again
    std::map<std::string, int64_t> counted;  // its topics' counts taken into the folder's
  };

  void Reset() {
    parts_.clear();
    topics_.clear();
    resume_byte_ = 0;
  }
  // True when a file read before is gone, elsewhere in the split order, or shorter.
  bool Replaced(const std::vector<std::string>& paths) const;
  // The tail of `part`'s storage file, or null while it is too short to tell its kind.
  std::unique_ptr<RecordingTail> OpenPart(const Part& part, bool later) const;
  // Reads `part` on; false when the file changed under the read (the folder is read anew).
  bool ReadPart(Part* part, bool later, const std::set<std::string>& topic_names,
                const MessageFn& fn, TailRead* read);

  std::vector<Part> parts_;
  RecordingFormat format_ = RecordingFormat::kRosbag2Sqlite;
  uint64_t resume_byte_ = 0;
  bool restart_pending_ = false;  // a read found a file changed under it: the next is anew
};

uint64_t SizeOf(const std::string& path, bool* gone) {
  std::error_code error;
  const uintmax_t size = fs::file_size(path, error);
  *gone = static_cast<bool>(error);
  return error ? 0 : static_cast<uint64_t>(size);
}

bool Rosbag2FolderTail::Replaced(const std::vector<std::string>& paths) const {
  if (paths.size() < parts_.size()) return true;
  for (size_t i = 0; i < parts_.size(); ++i) {
    bool gone = false;
    if (paths[i] != parts_[i].path || SizeOf(paths[i], &gone) < parts_[i].size || gone) {
      return true;
    }
  }
  return false;
}

std::unique_ptr<RecordingTail> Rosbag2FolderTail::OpenPart(const Part& part, bool later) const {
  bool gone = false;
  const uint64_t size = SizeOf(part.path, &gone);
  if (!gone && size < kTellingBytes && !later) return nullptr;  // just created: wait
  std::unique_ptr<RecordingTail> tail = OpenRecordingTail(part.path);
  if (!tail || (tail->format() != RecordingFormat::kRosbag2Sqlite &&
                tail->format() != RecordingFormat::kMcap)) {
    throw io::InputError(part.path +
                         ":byte 0: not a rosbag2 storage file (neither SQLite's magic nor "
                         "MCAP's); expected an SQLite database (.db3) or an MCAP file (.mcap)");
  }
  return tail;
}

bool Rosbag2FolderTail::ReadPart(Part* part, bool later, const std::set<std::string>& topic_names,
                                 const MessageFn& fn, TailRead* read) {
  // The folder's count of each topic before this read: a message's index on the folder is that
  // plus its place among the file's messages read now.
  std::map<std::string, int64_t> before;
  const TailRead got = part->tail->ReadOn(topic_names, [&](const RecordedMessage& m) {
    TopicInfo* topic = Topic(m.topic->name, m.topic->type, m.topic->md5sum, m.topic->encoding);
    const auto it = before.try_emplace(m.topic->name, topic->count).first;
    RecordedMessage out = m;
    out.topic = topic;
    out.index = it->second + (m.index - part->counted[m.topic->name]);
    ++read->messages;
    fn(out);
  });
  if (got.restarted) return false;
  for (const auto& [name, info] : part->tail->topics()) {
    TopicInfo* topic = Topic(name, info.type, info.md5sum, info.encoding);
    const auto was = before.find(name);
    int64_t& counted = part->counted[name];
    topic->count = (was != before.end() ? was->second : topic->count) + info.count - counted;
    counted = info.count;
  }
  const bool same = got.file_bytes == part->size;
  part->done = later && part->later_seen && same;
  part->later_seen = later;
  part->size = got.file_bytes;
  part->read_to = got.to_byte;
  return true;
}

TailRead Rosbag2FolderTail::ReadOn(const std::set<std::string>& topic_names,
                                   const MessageFn& fn) {
  const Rosbag2Files files = FindRosbag2Files(path_);
  TailRead read;
  if (restart_pending_ || Replaced(files.paths)) {
    Reset();
    read.restarted = true;
    restart_pending_ = false;
  }
  for (size_t i = parts_.size(); i < files.paths.size(); ++i) {
    parts_.push_back(Part{});
    parts_.back().path = files.paths[i];
  }
  if (files.has_metadata && files.metadata.storage_identifier == "mcap") {
    format_ = RecordingFormat::kMcap;
  }
  read.from_byte = resume_byte_;
  for (size_t i = 0; i < parts_.size(); ++i) {
    Part& part = parts_[i];
    if (part.done) continue;
    const bool later = i + 1 < parts_.size();
    if (!part.tail) {
      part.tail = OpenPart(part, later);
      if (!part.tail) break;  // the later files wait behind it
      if (i == 0) format_ = part.tail->format();
    }
    if (!ReadPart(&part, later, topic_names, fn, &read)) {
      // A file shrank between the check above and its read: what was passed on is not the
      // folder's as one read sees it. The caller is told, and the next read starts anew.
      const std::string what = part.path + ":byte " + std::to_string(part.size) +
                               ": the file ends before the bytes read from it at the last read "
                               "(a new recording in the folder?); expected it to grow: the "
                               "folder is read again from its start";
      Reset();
      restart_pending_ = true;
      throw io::InputError(what);
    }
  }
  for (const Part& part : parts_) {
    read.file_bytes += part.size;
    read.to_byte += part.read_to;
  }
  resume_byte_ = read.to_byte;
  return read;
}

}  // namespace

std::unique_ptr<RecordingTail> OpenRosbag2FolderTail(const std::string& folder) {
  return std::make_unique<Rosbag2FolderTail>(folder);
}

}  // namespace wallcal::recording
