// SPDX-License-Identifier: Apache-2.0
// A ROS 1 bag, an MCAP file and a rosbag2 .db3 file read on as they grow (recording::ScanTail over RecordingTail):
// the file is handed over in pieces that end anywhere (inside a record header, inside a chunk,
// between records), and the scans read piece by piece are those a reader of the whole file
// gives, each once, in the same order. A file that shrinks is read from its start.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/types.h"
#include "recording/recording_streams.h"
#include "recording/ros/ros_messages.h"
#include "recording/writers/mcap_writer.h"
#include "recording/writers/rosbag1_writer.h"
#include "recording/writers/rosbag2_sqlite_writer.h"
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
  for (int i = 0; i < kScans; ++i) {
    EXPECT_EQ(read[static_cast<size_t>(i)].stamp_s, Scan(i).header.stamp_s) << "scan " << i;
    EXPECT_EQ(read[static_cast<size_t>(i)].line, i + 1) << "scan " << i;
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

}  // namespace
}  // namespace wallcal::recording
