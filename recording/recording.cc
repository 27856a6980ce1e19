// SPDX-License-Identifier: Apache-2.0
#include "recording/recording.h"

#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/enum_text.h"
#include "io/types.h"
#include "recording/internal/file_tail.h"
#include "recording/mcap/internal/mcap_reader.h"
#include "recording/rosbag1/internal/rosbag1_reader.h"
#include "recording/rosbag2/internal/rosbag2_folder.h"
#include "recording/rosbag2/internal/rosbag2_sqlite_reader.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;

enum class Magic { kNone, kRos1, kMcap, kSqlite };

Magic MagicOf(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char head[16] = {0};
  in.read(head, sizeof(head));
  const std::streamsize n = in.gcount();
  if (n >= 13 && std::memcmp(head, "#ROSBAG V2.0\n", 13) == 0) return Magic::kRos1;
  if (n >= 8 && std::memcmp(head, "\x89MCAP0\r\n", 8) == 0) return Magic::kMcap;
  if (n >= 16 && std::memcmp(head, "SQLite format 3\0", 16) == 0) return Magic::kSqlite;
  return Magic::kNone;
}

}  // namespace

const char* RecordingFormatName(RecordingFormat format) {
  static const EnumText<RecordingFormat> kTexts[] = {
      {RecordingFormat::kRos1Bag, "ROS 1 bag"},
      {RecordingFormat::kMcap, "MCAP"},
      {RecordingFormat::kRosbag2Sqlite, "rosbag2 sqlite3"}};
  return TextOf(kTexts, format, "recording");
}

bool IsRecording(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) return IsRosbag2Folder(path);
  if (!fs::is_regular_file(path, error)) return false;
  return MagicOf(path) != Magic::kNone;
}

std::unique_ptr<Recording> OpenRecording(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) return OpenRosbag2(path);
  switch (MagicOf(path)) {
    case Magic::kRos1:
      return OpenRos1Bag(path);
    case Magic::kMcap:
      return OpenMcap(path);
    case Magic::kSqlite:
      return OpenRosbag2(path);
    case Magic::kNone:
      break;
  }
  throw io::InputError(
      io::Where(path, 0,
                "not a robot recording; expected a ROS 1 bag (#ROSBAG V2.0), an MCAP file "
                "or a rosbag2 sqlite3 database or folder"));
}

std::unique_ptr<RecordingTail> OpenRecordingTail(const std::string& path) {
  std::error_code error;
  if (fs::is_directory(path, error)) {
    return IsRosbag2Folder(path) ? OpenRosbag2FolderTail(path) : nullptr;
  }
  switch (MagicOf(path)) {
    case Magic::kRos1:
      return OpenRos1BagTail(path);
    case Magic::kMcap:
      return OpenMcapTail(path);
    case Magic::kSqlite:
      return OpenRosbag2SqliteTail(path);
    case Magic::kNone:
      break;
  }
  return nullptr;
}

TailRead FileTail::ReadOn(const std::set<std::string>& topic_names, const MessageFn& fn) {
  TailRead read;
  std::error_code error;
  read.file_bytes = static_cast<uint64_t>(fs::file_size(path_, error));
  if (error) throw io::InputError(io::Where(path_, 0, "cannot read its size: " + error.message()));
  if (read.file_bytes < resume_byte_) {
    Reset();
    topics_.clear();
    resume_byte_ = 0;
    read.restarted = true;
  }
  read.from_byte = resume_byte_;
  resume_byte_ = Walk(resume_byte_, read.file_bytes, topic_names, [&](const RecordedMessage& m) {
    ++read.messages;
    fn(m);
  });
  read.to_byte = resume_byte_;
  return read;
}

TopicInfo* RecordingTail::Topic(const std::string& name, const std::string& type,
                                const std::string& md5sum, const std::string& encoding) {
  auto [it, added] = topics_.try_emplace(name);
  if (added) {
    it->second.name = name;
    it->second.type = type;
    it->second.md5sum = md5sum;
    it->second.encoding = encoding;
  }
  return &it->second;
}

}  // namespace wallcal::recording
