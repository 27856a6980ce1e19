// SPDX-License-Identifier: Apache-2.0
// A ROS 1 bag, an MCAP file, a rosbag2 .db3 file and a rosbag2 folder read on as they grow
// (recording::ScanTail over RecordingTail): the file is handed over in pieces that end anywhere
// (inside a record header, inside a chunk, between records; a .db3 file at a row), and the
// scans read piece by piece are those a reader of the whole file gives, each once, in the same
// order. A file that shrinks is read from its start.
//
// A rosbag2 folder (.db3 or .mcap storage, with and without metadata.yaml) grows as a recorder
// writes it (test/support/rosbag2_folders.h): its last storage file cut, split files appearing.
// After each step the messages read on so far are those a whole read of the folder gives.

#include <gtest/gtest.h>

#include <cctype>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "io/types.h"
#include "recording/recording_streams.h"
#include "recording/ros/ros_messages.h"
#include "recording/writers/mcap_writer.h"
#include "recording/writers/rosbag1_writer.h"
#include "recording/writers/rosbag2_sqlite_writer.h"
#include "test/support/expect_text.h"
#include "test/support/recorded_messages.h"
#include "test/support/rosbag2_folders.h"
#include "test/support/scratch_dir.h"
#include "test/support/scratch_files.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;

constexpr int kScans = 400;

LaserScanMsg Scan(int i) {
  LaserScanMsg m;
  m.header.stamp_s = 1000.0 + 0.0133 * i;
  m.header.frame_id = "laser";
  m.angle_min_rad = -1.5f;
  m.angle_increment_rad = 0.01f;
  m.angle_max_rad = -1.5f + 0.01f * 299;
  m.range_min_m = 0.1f;
  m.range_max_m = 80.0f;
  for (int b = 0; b < 300; ++b) m.ranges_m.push_back(5.0f + 0.001f * static_cast<float>(i + b));
  return m;
}

NavSatFixMsg Fix(int i) {
  NavSatFixMsg m;
  m.header.stamp_s = 1000.0 + 0.2 * i;
  m.latitude_deg = 43.0;
  m.longitude_deg = 141.0;
  return m;
}

void WriteBag(const std::string& path, ChunkCompression compression) {
  Ros1BagWriter writer(path, compression, /*chunk_bytes=*/64 * 1024);
  const int scan = writer.AddConnection("/scan", RosType::kLaserScan);
  const int fix = writer.AddConnection("/fix", RosType::kNavSatFix);
  for (int i = 0; i < kScans; ++i) {
    const LaserScanMsg m = Scan(i);
    writer.Write(scan, m.header.stamp_s + 0.002, EncodeLaserScan(m, WireFormat::kRos1));
    if (i % 15 == 0) {
      const NavSatFixMsg f = Fix(i / 15);
      writer.Write(fix, f.header.stamp_s + 0.01, EncodeNavSatFix(f, WireFormat::kRos1));
    }
  }
  writer.Close();
}

void WriteMcap(const std::string& path, ChunkCompression compression) {
  McapWriter writer(path, compression, /*chunk_bytes=*/64 * 1024);
  const uint16_t scan = writer.AddChannel("/scan", "sensor_msgs/msg/LaserScan",
                                          RosTypeDefinition(RosType::kLaserScan));
  const uint16_t fix = writer.AddChannel("/fix", "sensor_msgs/msg/NavSatFix",
                                         RosTypeDefinition(RosType::kNavSatFix));
  for (int i = 0; i < kScans; ++i) {
    const LaserScanMsg m = Scan(i);
    writer.Write(scan, m.header.stamp_s + 0.002, m.header.stamp_s,
                 EncodeLaserScan(m, WireFormat::kCdr));
    if (i % 15 == 0) {
      const NavSatFixMsg f = Fix(i / 15);
      writer.Write(fix, f.header.stamp_s + 0.01, f.header.stamp_s,
                   EncodeNavSatFix(f, WireFormat::kCdr));
    }
  }
  writer.Close();
}

// The kScans scans of Scan(i), each once, in order, numbered from line 1.
void ExpectEveryScanOnce(const std::vector<io::ScanRecord>& read) {
  ASSERT_EQ(read.size(), static_cast<size_t>(kScans));
  for (int i = 0; i < kScans; ++i) {
    EXPECT_EQ(read[static_cast<size_t>(i)].stamp_s, Scan(i).header.stamp_s) << "scan " << i;
    EXPECT_EQ(read[static_cast<size_t>(i)].line, i + 1) << "scan " << i;
  }
}

struct Case {
  const char* name;
  bool mcap;
  ChunkCompression compression;
};

class RecordingTailTest : public testing::TestWithParam<Case> {};

TEST_P(RecordingTailTest, ReadsInPiecesWhatAWholeReadGives) {
  const testing_support::ScratchDir scratch("wallcal_recording_tail_");
  const fs::path whole_path = scratch.path() / (GetParam().mcap ? "whole.mcap" : "whole.bag");
  if (GetParam().mcap) {
    WriteMcap(whole_path.string(), GetParam().compression);
  } else {
    WriteBag(whole_path.string(), GetParam().compression);
  }
  io::SessionSpec spec;
  spec.scanner_log = whole_path.string();
  spec.scanner_topic = "/scan";
  std::vector<io::ScanRecord> whole;
  {
    const std::unique_ptr<io::ScanSource> source = MakeScanOpener(spec, nullptr)();
    io::ScanRecord scan;
    while (source->Next(&scan)) whole.push_back(scan);
  }
  ASSERT_EQ(whole.size(), static_cast<size_t>(kScans));

  const std::string content = testing_support::ReadFile(whole_path);
  const fs::path growing = scratch.path() / (GetParam().mcap ? "growing.mcap" : "growing.bag");
  spec.scanner_log = growing.string();
  testing_support::WriteFirstBytes(growing, content, 16);  // the magic, not yet a whole header record
  ASSERT_TRUE(ScanTail::Supports(growing.string()));
  ScanTail tail(spec, nullptr);
  std::vector<io::ScanRecord> read;
  EXPECT_EQ(tail.ReadOn(&read).to_byte, 0u);
  // 37 pieces of odd sizes: their ends fall anywhere.
  uint64_t last_to = 0;
  for (size_t piece = 1; piece <= 37; ++piece) {
    testing_support::WriteFirstBytes(growing, content, content.size() * piece / 37);
    const TailRead step = tail.ReadOn(&read);
    EXPECT_FALSE(step.restarted);
    EXPECT_EQ(step.from_byte, last_to);
    EXPECT_LE(step.to_byte, step.file_bytes);
    last_to = step.to_byte;
  }
  ASSERT_EQ(read.size(), whole.size());
  for (size_t i = 0; i < whole.size(); ++i) {
    EXPECT_EQ(read[i].stamp_s, whole[i].stamp_s) << "scan " << i;
    EXPECT_EQ(read[i].line, whole[i].line) << "scan " << i;
    EXPECT_EQ(read[i].ranges_m, whole[i].ranges_m) << "scan " << i;
  }
  EXPECT_EQ(tail.ReadOn(&read).messages, 0);  // nothing new: nothing read

  // Shorter than what was read: from the start.
  testing_support::WriteFirstBytes(growing, content, content.size() / 2);
  std::vector<io::ScanRecord> again;
  const TailRead restart = tail.ReadOn(&again);
  EXPECT_TRUE(restart.restarted);
  EXPECT_EQ(restart.from_byte, 0u);
  ASSERT_GT(again.size(), 0u);
  EXPECT_LT(again.size(), whole.size());
  EXPECT_EQ(again.front().line, 1);
}

INSTANTIATE_TEST_SUITE_P(
    Containers, RecordingTailTest,
    testing::Values(Case{"Ros1Bag", false, ChunkCompression::kNone},
                    Case{"Ros1BagBz2", false, ChunkCompression::kBz2},
                    Case{"Ros1BagLz4", false, ChunkCompression::kLz4},
                    Case{"Mcap", true, ChunkCompression::kNone},
                    Case{"McapZstd", true, ChunkCompression::kZstd}),
    [](const testing::TestParamInfo<Case>& param_info) { return param_info.param.name; });

// A .db3 file grows by rows: each step is the file with more of the same messages (as SQLite
// shows a database whose writer committed more), the rows after the last one read are read.
TEST(RecordingTailTest, ReadsTheRowsADb3FileGained) {
  const testing_support::ScratchDir scratch("wallcal_recording_tail_");
  const fs::path growing = scratch.path() / "growing.db3";
  const auto write_first = [&](int scans) {
    const fs::path step = scratch.path() / "step.db3";
    {
      Rosbag2SqliteWriter writer(step.string(), Rosbag2Layout::kIron);
      const int64_t scan = writer.AddTopic("/scan", "sensor_msgs/msg/LaserScan",
                                           RosTypeDefinition(RosType::kLaserScan));
      const int64_t fix = writer.AddTopic("/fix", "sensor_msgs/msg/NavSatFix",
                                          RosTypeDefinition(RosType::kNavSatFix));
      for (int i = 0; i < scans; ++i) {
        const LaserScanMsg m = Scan(i);
        writer.Write(scan, m.header.stamp_s + 0.002, EncodeLaserScan(m, WireFormat::kCdr));
        if (i % 15 == 0) {
          const NavSatFixMsg f = Fix(i / 15);
          writer.Write(fix, f.header.stamp_s + 0.01, EncodeNavSatFix(f, WireFormat::kCdr));
        }
      }
      writer.Close();
    }
    fs::rename(step, growing);
  };
  io::SessionSpec spec;
  spec.scanner_log = growing.string();
  spec.scanner_topic = "/scan";
  write_first(0);
  ScanTail tail(spec, nullptr);
  std::vector<io::ScanRecord> read;
  for (const int scans : {0, 40, 120, 121, kScans}) {
    write_first(scans);
    tail.ReadOn(&read);
    ASSERT_EQ(read.size(), static_cast<size_t>(scans));
  }
  ExpectEveryScanOnce(read);
}

// Rows whose timestamps are not in id order (a recorder's cache written out of order): a read
// passes them on in timestamp order, as the whole reader does.
TEST(RecordingTailTest, PassesADb3FilesRowsOnInTimestampOrder) {
  const testing_support::ScratchDir scratch("wallcal_recording_tail_");
  const fs::path path = scratch.path() / "shuffled.db3";
  {
    Rosbag2SqliteWriter writer(path.string(), Rosbag2Layout::kHumble);
    const int64_t scan = writer.AddTopic("/scan", "sensor_msgs/msg/LaserScan",
                                         RosTypeDefinition(RosType::kLaserScan));
    for (int i = 0; i < 40; ++i) {
      const int k = i % 2 == 0 ? i + 1 : i - 1;  // pairs swapped: 1, 0, 3, 2, ...
      const LaserScanMsg m = Scan(k);
      writer.Write(scan, m.header.stamp_s, EncodeLaserScan(m, WireFormat::kCdr));
    }
    writer.Close();
  }
  io::SessionSpec spec;
  spec.scanner_log = path.string();
  spec.scanner_topic = "/scan";
  ScanTail tail(spec, nullptr);
  std::vector<io::ScanRecord> read;
  tail.ReadOn(&read);
  ASSERT_EQ(read.size(), 40u);
  for (size_t i = 0; i < read.size(); ++i) {
    EXPECT_EQ(read[i].stamp_s, Scan(static_cast<int>(i)).header.stamp_s) << "scan " << i;
  }
}

TEST(RecordingTailTest, OtherContainersHaveNoTail) {
  const testing_support::ScratchDir scratch("wallcal_recording_tail_");
  const fs::path text = scratch.path() / "scans.clf";
  std::ofstream(text) << "# CARMEN\n";
  EXPECT_FALSE(ScanTail::Supports(text.string()));
  io::SessionSpec spec;
  spec.scanner_log = text.string();
  EXPECT_THROW(ScanTail(spec, nullptr), io::InputError);
}

// ---- rosbag2 folders ---------------------------------------------------------------------

using testing_support::GotMessage;
using testing_support::GrowingRosbag2Folder;
using testing_support::Rosbag2Storage;
using testing_support::SplitFolder;

const std::set<std::string> kScanAndFix = {"/scan", "/fix"};

// Reads `tail` on, appending what it passes on to *got; checks the read's offsets against
// the last one's.
TailRead ReadOnInto(RecordingTail& tail, const std::set<std::string>& topics,
                    std::vector<GotMessage>* got) {
  return tail.ReadOn(topics, [got](const RecordedMessage& m) {
    got->push_back({m.topic->name, m.receive_s, std::vector<uint8_t>(m.data, m.data + m.size),
                    m.index, m.file_offset, m.wire});
  });
}

// What a whole read of the folder gives; false when the whole reader refuses it as it stands
// (a storage file too short yet to tell its kind or to hold its MCAP header).
bool WholeRead(const std::string& folder, const std::set<std::string>& topics,
               std::vector<GotMessage>* whole) {
  try {
    std::unique_ptr<Recording> recording = OpenRecording(folder);
    for (const std::string& t : topics) {
      bool present = false;
      for (const TopicInfo& info : recording->topics()) present = present || info.name == t;
      if (!present) return false;
    }
    *whole = testing_support::CollectMessages(*recording, topics);
    return true;
  } catch (const io::InputError&) {
    return false;
  }
}

void ExpectSameMessages(const std::vector<GotMessage>& got, const std::vector<GotMessage>& whole,
                        const std::string& where) {
  ASSERT_EQ(got.size(), whole.size()) << where;
  for (size_t i = 0; i < whole.size(); ++i) {
    ASSERT_EQ(got[i].topic, whole[i].topic) << where << ", message " << i;
    EXPECT_EQ(got[i].index, whole[i].index) << where << ", message " << i;
    EXPECT_EQ(got[i].receive_s, whole[i].receive_s) << where << ", message " << i;
    EXPECT_EQ(got[i].data, whole[i].data) << where << ", message " << i;
  }
}

// The scans and fixes of WriteMcap split into storage files of 90 messages (5 files), in
// 16 kB chunks when the storage is MCAP.
SplitFolder SplitSample(const fs::path& scratch, Rosbag2Storage storage) {
  const fs::path source = scratch / "source.mcap";
  WriteMcap(source.string(), ChunkCompression::kNone);
  return testing_support::SplitIntoRosbag2Folder(source.string(), scratch / "complete" / "bag",
                                                 storage, 90, 16 * 1024);
}

struct FolderCase {
  const char* name;
  Rosbag2Storage storage;
  bool metadata;
};

class Rosbag2FolderTailTest : public testing::TestWithParam<FolderCase> {};

TEST_P(Rosbag2FolderTailTest, ReadsAGrowingFolderAsAWholeReadOfEachStep) {
  const testing_support::ScratchDir scratch("wallcal_rosbag2_folder_tail_");
  const SplitFolder complete = SplitSample(scratch.path(), GetParam().storage);
  ASSERT_EQ(complete.files.size(), 5u);
  GrowingRosbag2Folder folder(complete, scratch.path() / "growing" / "bag", GetParam().metadata);
  const std::string path = folder.path().string();
  EXPECT_EQ(OpenRecordingTail(path), nullptr);  // nothing in it yet: not a rosbag2 folder
  folder.WriteUpTo(0.01);
  const std::unique_ptr<RecordingTail> tail = OpenRecordingTail(path);
  ASSERT_NE(tail, nullptr);
  std::vector<GotMessage> got, whole;
  uint64_t last_to = 0;
  int compared = 0;
  // 41 steps of odd sizes: the cuts fall anywhere in the files, a split file appears between
  // two steps and within one.
  for (int step = 1; step <= 41; ++step) {
    const double share = step == 41 ? 1.0 : 0.01 + 0.99 * step * step / (41.0 * 41.0);
    folder.WriteUpTo(share);
    const TailRead read = ReadOnInto(*tail, kScanAndFix, &got);
    EXPECT_FALSE(read.restarted) << "step " << step;
    EXPECT_EQ(read.from_byte, last_to) << "step " << step;
    EXPECT_LE(read.to_byte, read.file_bytes) << "step " << step;
    last_to = read.to_byte;
    if (!WholeRead(path, kScanAndFix, &whole)) continue;
    ++compared;
    ExpectSameMessages(got, whole, "step " + std::to_string(step));
  }
  EXPECT_GE(compared, 35);
  ASSERT_EQ(got.size(), static_cast<size_t>(kScans + (kScans + 14) / 15));
  EXPECT_EQ(tail->topics().at("/scan").count, kScans);
  EXPECT_EQ(tail->format(), GetParam().storage == Rosbag2Storage::kMcap
                                ? RecordingFormat::kMcap
                                : RecordingFormat::kRosbag2Sqlite);
  EXPECT_EQ(ReadOnInto(*tail, kScanAndFix, &got).messages, 0);  // nothing new: nothing read

  // The scans through ScanTail, read on from a fresh folder in three steps: those of a whole
  // read, lines numbered across the files.
  folder.Restart();
  io::SessionSpec spec;
  spec.scanner_log = path;
  spec.scanner_topic = "/scan";
  folder.WriteUpTo(0.3);
  ASSERT_TRUE(ScanTail::Supports(path));
  ScanTail scans(spec, nullptr);
  std::vector<io::ScanRecord> read;
  for (const double share : {0.3, 0.62, 1.0}) {
    folder.WriteUpTo(share);
    scans.ReadOn(&read);
  }
  ExpectEveryScanOnce(read);
}

// A split file appearing: the file before it is read to its end, then the new one on.
TEST_P(Rosbag2FolderTailTest, MovesOnToASplitFileWhenItAppears) {
  const testing_support::ScratchDir scratch("wallcal_rosbag2_folder_tail_");
  const SplitFolder complete = SplitSample(scratch.path(), GetParam().storage);
  GrowingRosbag2Folder folder(complete, scratch.path() / "growing" / "bag", GetParam().metadata);
  const std::string path = folder.path().string();
  // The first file whole, nothing of the second yet; then a little of the second.
  const double first_file = GetParam().storage == Rosbag2Storage::kMcap
                                ? static_cast<double>(fs::file_size(complete.folder /
                                                                    complete.files[0]))
                                : static_cast<double>(complete.messages[0]);
  double total = 0;
  for (size_t k = 0; k < complete.files.size(); ++k) {
    total += GetParam().storage == Rosbag2Storage::kMcap
                 ? static_cast<double>(fs::file_size(complete.folder / complete.files[k]))
                 : static_cast<double>(complete.messages[k]);
  }
  folder.WriteUpTo(first_file / total);
  EXPECT_FALSE(fs::exists(folder.path() / complete.files[1]));
  const std::unique_ptr<RecordingTail> tail = OpenRecordingTail(path);
  std::vector<GotMessage> got;
  ReadOnInto(*tail, kScanAndFix, &got);
  EXPECT_EQ(got.size(), static_cast<size_t>(complete.messages[0]));
  folder.WriteUpTo((first_file + 0.5 * (total / 5)) / total);
  ASSERT_TRUE(fs::exists(folder.path() / complete.files[1]));
  const TailRead read = ReadOnInto(*tail, kScanAndFix, &got);
  EXPECT_GT(read.messages, 0);
  EXPECT_LT(got.size(), static_cast<size_t>(complete.messages[0] + complete.messages[1]));
  folder.WriteUpTo(1.0);
  ReadOnInto(*tail, kScanAndFix, &got);
  std::vector<GotMessage> whole;
  ASSERT_TRUE(WholeRead(path, kScanAndFix, &whole));
  ExpectSameMessages(got, whole, "whole");
}

// A folder replaced by a shorter recording (the same name recorded again): read from its start.
TEST_P(Rosbag2FolderTailTest, ReadsAReplacedFolderFromItsStart) {
  const testing_support::ScratchDir scratch("wallcal_rosbag2_folder_tail_");
  const SplitFolder complete = SplitSample(scratch.path(), GetParam().storage);
  GrowingRosbag2Folder folder(complete, scratch.path() / "growing" / "bag", GetParam().metadata);
  const std::string path = folder.path().string();
  folder.WriteUpTo(0.8);
  const std::unique_ptr<RecordingTail> tail = OpenRecordingTail(path);
  std::vector<GotMessage> got;
  ReadOnInto(*tail, kScanAndFix, &got);
  ASSERT_GT(got.size(), 300u);

  folder.Restart();
  folder.WriteUpTo(0.3);
  got.clear();
  const TailRead read = ReadOnInto(*tail, kScanAndFix, &got);
  EXPECT_TRUE(read.restarted);
  EXPECT_EQ(read.from_byte, 0u);
  std::vector<GotMessage> whole;
  ASSERT_TRUE(WholeRead(path, kScanAndFix, &whole));
  ExpectSameMessages(got, whole, "the new recording");
  EXPECT_EQ(got.front().index, 0);
  EXPECT_EQ(tail->topics().at("/scan").count + tail->topics().at("/fix").count,
            static_cast<int64_t>(got.size()));
}

// A split file that is damaged: an InputError naming the file and what was expected, at every
// read, and the files before it read.
TEST_P(Rosbag2FolderTailTest, DamagedSplitFileIsAnInputError) {
  const testing_support::ScratchDir scratch("wallcal_rosbag2_folder_tail_");
  const SplitFolder complete = SplitSample(scratch.path(), GetParam().storage);
  GrowingRosbag2Folder folder(complete, scratch.path() / "growing" / "bag", GetParam().metadata);
  const std::string path = folder.path().string();
  folder.WriteUpTo(0.5);
  const fs::path damaged = folder.path() / complete.files[1];
  ASSERT_TRUE(fs::exists(damaged));
  // Bytes overwritten: in the middle of the first chunk of an MCAP file (walked record by
  // record from the header: opcode, then a 64-bit length), over the second page of a .db3 file.
  std::string bytes = testing_support::ReadFile(damaged.string());
  size_t from = 4096;
  if (GetParam().storage == Rosbag2Storage::kMcap) {
    for (size_t at = 8; at + 9 <= bytes.size();) {
      uint64_t len = 0;
      std::memcpy(&len, bytes.data() + at + 1, sizeof len);
      if (bytes[at] == 0x06) {
        from = at + 9 + len / 2;
        break;
      }
      at += 9 + len;
    }
  }
  ASSERT_LT(from + 512, bytes.size());
  for (size_t i = from; i < from + 512; ++i) bytes[i] = '\x5a';
  testing_support::WriteFile(damaged.string(), bytes);
  const std::unique_ptr<RecordingTail> tail = OpenRecordingTail(path);
  std::vector<GotMessage> got;
  for (int attempt = 0; attempt < 2; ++attempt) {
    const std::string error = testing_support::ThrownMessage<io::InputError>(
        [&] { ReadOnInto(*tail, kScanAndFix, &got); });
    // "<file>:<byte>: ..." (MCAP) or "<file>: reading the rosbag2 database: ...; expected ..."
    ASSERT_EQ(error.rfind(damaged.string() + ":", 0), 0u) << error;
    EXPECT_TRUE(std::isdigit(static_cast<unsigned char>(error[damaged.string().size() + 1])) ||
                error.find("expected the tables") != std::string::npos)
        << error;
  }
  EXPECT_EQ(got.size(), static_cast<size_t>(complete.messages[0]));  // the file before, once

  // A storage file that is neither SQLite nor MCAP.
  testing_support::WriteFile(damaged.string(), std::string(4096, 'x'));
  const std::unique_ptr<RecordingTail> fresh = OpenRecordingTail(path);
  const std::string error = testing_support::ThrownMessage<io::InputError>(
      [&] { ReadOnInto(*fresh, kScanAndFix, &got); });
  EXPECT_NE(error.find(damaged.string() + ":byte 0: not a rosbag2 storage file"),
            std::string::npos)
      << error;
}

INSTANTIATE_TEST_SUITE_P(
    Storages, Rosbag2FolderTailTest,
    testing::Values(FolderCase{"Db3", Rosbag2Storage::kSqlite3, false},
                    FolderCase{"Db3WithMetadata", Rosbag2Storage::kSqlite3, true},
                    FolderCase{"Mcap", Rosbag2Storage::kMcap, false},
                    FolderCase{"McapWithMetadata", Rosbag2Storage::kMcap, true}),
    [](const testing::TestParamInfo<FolderCase>& param_info) { return param_info.param.name; });

// The real rosbag2 files of the shared test data as a folder of two storage files (the file and
// a copy of it as the split after it), grown in steps: a .db3 row by row, an MCAP file 97 bytes
// at a time. After each step, the messages read on are those of a whole read.
TEST(Rosbag2FolderTailTest, ReadsRealRosbag2FilesOnAsAFolder) {
  if (!fs::exists(testing_support::kRealRos2)) {
    GTEST_SKIP() << "no shared test data at " << testing_support::kRealRos2;
  }
  const testing_support::ScratchDir scratch("wallcal_rosbag2_folder_real_");
  const std::set<std::string> topics = {"/test_topic", "/array_topic"};
  for (const Rosbag2Storage storage : {Rosbag2Storage::kSqlite3, Rosbag2Storage::kMcap}) {
    const bool mcap = storage == Rosbag2Storage::kMcap;
    const std::string real =
        testing_support::kRealRos2 + (mcap ? "/rosbag2-cdr_test_0.mcap" : "/rosbag2-cdr_test_0.db3");
    SplitFolder complete;
    complete.folder = scratch.path() / (mcap ? "mcap" : "db3") / "cdr_test";
    complete.storage = storage;
    fs::create_directories(complete.folder);
    const std::unique_ptr<Recording> one = OpenRecording(real);
    complete.topics = one->topics();
    for (int k = 0; k < 2; ++k) {
      complete.files.push_back("cdr_test_" + std::to_string(k) + (mcap ? ".mcap" : ".db3"));
      fs::copy_file(real, complete.folder / complete.files.back());
      complete.messages.push_back(7);
    }
    for (TopicInfo& t : complete.topics) t.count *= 2;
    GrowingRosbag2Folder folder(complete, scratch.path() / "growing" / (mcap ? "mcap" : "db3"),
                                /*metadata=*/mcap);
    const std::string path = folder.path().string();
    const double steps = mcap ? 2.0 * static_cast<double>(fs::file_size(real)) / 97.0 : 14.0;
    std::unique_ptr<RecordingTail> tail;
    std::vector<GotMessage> got, whole;
    int compared = 0;
    for (int step = 1; step <= static_cast<int>(steps) + 1; ++step) {
      folder.WriteUpTo(std::min(1.0, step / steps));
      if (!tail) tail = OpenRecordingTail(path);
      ASSERT_NE(tail, nullptr);
      ReadOnInto(*tail, topics, &got);
      if (!WholeRead(path, topics, &whole)) continue;
      ++compared;
      ExpectSameMessages(got, whole, real + ", step " + std::to_string(step));
    }
    EXPECT_GE(compared, mcap ? 10 : 14) << real;
    EXPECT_EQ(got.size(), 14u) << real;
  }
}

}  // namespace
}  // namespace wallcal::recording
