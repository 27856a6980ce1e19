// SPDX-License-Identifier: Apache-2.0
// rosbag2 sqlite3 storage and folders: the real Iron-layout .db3 (expected values from an
// independent decode with Python's sqlite3), writer round trips in the Humble and Iron layouts,
// split bags read in order, mcap-storage folders, metadata.yaml, and inputs that are not rosbag2.

#include <gtest/gtest.h>
#include <sqlite3.h>
#include <zlib.h>

#include <filesystem>
#include <fstream>

#include "io/config/rosbag2_metadata.h"
#include "io/types.h"
#include "recording/rosbag2/internal/rosbag2_sqlite_reader.h"
#include "recording/writers/mcap_writer.h"
#include "recording/writers/rosbag2_sqlite_writer.h"
#include "test/support/expect_text.h"
#include "test/support/recorded_messages.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;
using namespace testing_support;  // NOLINT: the test helpers of test/support

// A rosbag2 database holds CDR only.
std::vector<GotMessage> Collect(Recording& rec, const std::set<std::string>& topics) {
  std::vector<GotMessage> got = testing_support::CollectMessages(rec, topics);
  for (const GotMessage& g : got) EXPECT_EQ(g.wire, WireFormat::kCdr) << g.topic;
  return got;
}

std::set<std::string> Tables(const std::string& path) {
  sqlite3* db = nullptr;
  std::set<std::string> names;
  if (sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr) == SQLITE_OK) {
    sqlite3_stmt* s = nullptr;
    sqlite3_prepare_v2(db, "SELECT name FROM sqlite_master WHERE type='table'", -1, &s, nullptr);
    while (sqlite3_step(s) == SQLITE_ROW) {
      names.insert(reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
    }
    sqlite3_finalize(s);
  }
  sqlite3_close(db);
  return names;
}

TEST(Rosbag2SqliteTest, ReadsRealIronDatabase) {
  if (!fs::exists(kRealRos2)) {
    GTEST_SKIP() << "no shared test data at " << kRealRos2;
  }
  auto rec = OpenRosbag2(kRealRos2 + "/rosbag2-cdr_test_0.db3");
  EXPECT_EQ(rec->format(), RecordingFormat::kRosbag2Sqlite);
  EXPECT_TRUE(rec->warnings().empty());
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[0].name, "/array_topic");
  EXPECT_EQ(rec->topics()[0].type, "test_msgs/msg/Arrays");
  EXPECT_EQ(rec->topics()[0].encoding, "cdr");
  EXPECT_EQ(rec->topics()[0].count, 4);
  EXPECT_EQ(rec->topics()[1].name, "/test_topic");
  EXPECT_EQ(rec->topics()[1].count, 3);
  EXPECT_NEAR(rec->topics()[1].first_s, 1586406456.763032325, 1e-6);
  EXPECT_NEAR(rec->topics()[1].last_s, 1586406456.863382628, 1e-6);
  // Independent decode (Python sqlite3): messages.id, time, size, CRC-32 of the data.
  struct Want {
    uint64_t id;
    const char* topic;
    double t_s;
    size_t size;
    uint32_t crc;
  };
  const Want want[] = {
      {1, "/test_topic", 1586406456.763032325, 52, 0x2b671247},
      {2, "/array_topic", 1586406456.782683500, 696, 0xab8a469a},
      {3, "/test_topic", 1586406456.812989925, 52, 0x2b671247},
      {4, "/array_topic", 1586406456.814049600, 696, 0xab8a469a},
      {5, "/test_topic", 1586406456.863382628, 52, 0x2b671247},
      {6, "/array_topic", 1586406456.866330524, 696, 0xab8a469a},
      {7, "/array_topic", 1586406456.914169506, 696, 0xab8a469a},
  };
  const std::vector<GotMessage> got = Collect(*rec, {"/test_topic", "/array_topic"});
  ASSERT_EQ(got.size(), 7u);
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].file_offset, want[i].id);
    EXPECT_EQ(got[i].topic, want[i].topic);
    EXPECT_NEAR(got[i].receive_s, want[i].t_s, 1e-6);
    EXPECT_EQ(got[i].data.size(), want[i].size);
    EXPECT_EQ(crc32(0, got[i].data.data(), static_cast<uInt>(got[i].data.size())), want[i].crc);
  }
  EXPECT_EQ(got[6].index, 3);
}

// Writes /scan and /fix with payload {tag, k}: k counts on from `first`; times 10 + k/10 s.
std::vector<TopicInfo> WriteDb3(const std::string& path, Rosbag2Layout layout, int first, int n) {
  Rosbag2SqliteWriter w(path, layout);
  const int64_t scan = w.AddTopic("/scan", "sensor_msgs/msg/LaserScan", "float32 angle_min\n");
  const int64_t fix = w.AddTopic("/fix", "sensor_msgs/msg/NavSatFix", "float64 latitude\n");
  for (int k = first; k < first + n; ++k) {
    w.Write(scan, 10.0 + 0.1 * k, std::vector<uint8_t>{0, 1, 0, 0, 's', static_cast<uint8_t>(k)});
    if (k % 2 == 0) {
      w.Write(fix, 10.0 + 0.1 * k, std::vector<uint8_t>{0, 1, 0, 0, 'f', static_cast<uint8_t>(k)});
    }
  }
  w.Close();
  return w.topics();
}

void ExpectSequence(const std::vector<GotMessage>& got, int n) {
  int64_t scans = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    if (i > 0) {
      ASSERT_LE(got[i - 1].receive_s, got[i].receive_s);
    }
    if (got[i].topic == "/scan") {
      EXPECT_EQ(got[i].index, scans);
      EXPECT_EQ(got[i].data[5], static_cast<uint8_t>(scans));
      EXPECT_NEAR(got[i].receive_s, 10.0 + 0.1 * static_cast<double>(scans), 1e-9);
      ++scans;
    }
  }
  EXPECT_EQ(scans, n);
}

TEST(Rosbag2SqliteTest, HumbleLayoutWrittenAndRead) {
  const std::string path = FreshScratchFolder("humble") + "/bag_0.db3";
  WriteDb3(path, Rosbag2Layout::kHumble, 0, 20);
  EXPECT_EQ(Tables(path), (std::set<std::string>{"messages", "topics"}));
  auto rec = OpenRosbag2(path);
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[0].name, "/fix");
  EXPECT_EQ(rec->topics()[0].count, 10);
  EXPECT_EQ(rec->topics()[1].type, "sensor_msgs/msg/LaserScan");
  const std::vector<GotMessage> got = Collect(*rec, {"/scan", "/fix"});
  ASSERT_EQ(got.size(), 30u);
  ExpectSequence(got, 20);
  EXPECT_EQ(got[0].topic, "/scan");  // tie at 10.0 s: /scan was inserted first
  EXPECT_EQ(got[1].topic, "/fix");
}

TEST(Rosbag2SqliteTest, IronLayoutHasMessageDefinitions) {
  const std::string path = FreshScratchFolder("iron") + "/bag_0.db3";
  WriteDb3(path, Rosbag2Layout::kIron, 0, 5);
  const std::set<std::string> tables = Tables(path);
  EXPECT_EQ(tables.count("message_definitions"), 1u);
  EXPECT_EQ(tables.count("schema"), 1u);
  auto rec = OpenRosbag2(path);
  ExpectSequence(Collect(*rec, {"/scan"}), 5);
}

TEST(Rosbag2SqliteTest, FolderOfTwoFilesReadsInOrder) {
  const std::string dir = FreshScratchFolder("split");
  std::vector<TopicInfo> a = WriteDb3(dir + "/split_0.db3", Rosbag2Layout::kIron, 0, 12);
  std::vector<TopicInfo> b = WriteDb3(dir + "/split_1.db3", Rosbag2Layout::kIron, 12, 8);
  for (size_t i = 0; i < a.size(); ++i) {
    a[i].count += b[i].count;
    a[i].last_s = b[i].last_s;
  }
  WriteRosbag2Metadata(dir, "sqlite3", {"split_0.db3", "split_1.db3"}, a);
  auto rec = OpenRosbag2(dir);
  EXPECT_EQ(rec->format(), RecordingFormat::kRosbag2Sqlite);
  EXPECT_TRUE(rec->warnings().empty()) << rec->warnings().front();
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[1].count, 20);
  EXPECT_NEAR(rec->topics()[1].first_s, 10.0, 1e-9);
  EXPECT_NEAR(rec->topics()[1].last_s, 11.9, 1e-9);
  const std::vector<GotMessage> got = Collect(*rec, {"/scan", "/fix"});
  EXPECT_EQ(got.size(), 30u);
  ExpectSequence(got, 20);

  // metadata.yaml counting other numbers than the files hold: said in a warning.
  a[0].count = 99;  // /scan
  WriteRosbag2Metadata(dir, "sqlite3", {"split_0.db3", "split_1.db3"}, a);
  auto again = OpenRosbag2(dir);
  ASSERT_EQ(again->warnings().size(), 1u);
  EXPECT_NE(again->warnings()[0].find("counts 99 messages on /scan"), std::string::npos);
}

// metadata.yaml written at a split lists the files closed then: the files after them (the
// recording went on) are read after the listed ones, in number order, with a warning; a folder
// being recorded, without metadata.yaml and with storage files, is a recording.
TEST(Rosbag2SqliteTest, FolderReadsTheFilesMetadataDoesNotListAfterTheListedOnes) {
  const std::string dir = FreshScratchFolder("split_going_on");
  std::vector<TopicInfo> topics = WriteDb3(dir + "/bag_0.db3", Rosbag2Layout::kIron, 0, 10);
  EXPECT_TRUE(IsRecording(dir));
  WriteDb3(dir + "/bag_1.db3", Rosbag2Layout::kIron, 10, 10);
  WriteDb3(dir + "/bag_2.db3", Rosbag2Layout::kIron, 20, 5);
  WriteRosbag2Metadata(dir, "sqlite3", {"bag_0.db3"}, topics);
  auto rec = OpenRosbag2(dir);
  ASSERT_GE(rec->warnings().size(), 1u);  // and its counts, which are the first file's
  EXPECT_NE(rec->warnings()[0].find("does not list bag_1.db3, bag_2.db3"), std::string::npos)
      << rec->warnings()[0];
  ExpectSequence(Collect(*rec, {"/scan"}), 25);

  const std::string empty = FreshScratchFolder("not_yet");
  EXPECT_FALSE(IsRecording(empty));
}

TEST(Rosbag2SqliteTest, FolderWithoutMetadataReadsFilesInNumberOrder) {
  const std::string dir = FreshScratchFolder("crashed");
  for (int part = 0; part < 11; ++part) {
    WriteDb3(dir + "/bag_" + std::to_string(part) + ".db3", Rosbag2Layout::kHumble, 2 * part, 2);
  }
  auto rec = OpenRosbag2(dir);
  ASSERT_EQ(rec->warnings().size(), 1u);
  EXPECT_NE(rec->warnings()[0].find("no metadata.yaml"), std::string::npos);
  ExpectSequence(Collect(*rec, {"/scan"}), 22);  // bag_10 after bag_9, not after bag_1
}

TEST(Rosbag2SqliteTest, McapStorageFolderReadsThroughTheMcapReader) {
  const std::string dir = FreshScratchFolder("mcap_folder");
  std::vector<TopicInfo> topics(1);
  topics[0].name = "/scan";
  topics[0].type = "sensor_msgs/msg/LaserScan";
  topics[0].encoding = "cdr";
  for (int part = 0; part < 2; ++part) {
    McapWriter w(dir + "/b_" + std::to_string(part) + ".mcap", ChunkCompression::kLz4, 100);
    const uint16_t c = w.AddChannel("/scan", "sensor_msgs/msg/LaserScan", "float32 a\n");
    for (int k = 10 * part; k < 10 * part + 10; ++k) {
      w.Write(c, 10.0 + 0.1 * k, 10.0,
              std::vector<uint8_t>{0, 1, 0, 0, 's', static_cast<uint8_t>(k)});
    }
    w.Close();
  }
  topics[0].count = 20;
  WriteRosbag2Metadata(dir, "mcap", {"b_0.mcap", "b_1.mcap"}, topics);
  auto rec = OpenRosbag2(dir);
  EXPECT_EQ(rec->format(), RecordingFormat::kMcap);
  EXPECT_EQ(rec->compressions(), std::set<ChunkCompression>{ChunkCompression::kLz4});
  ExpectSequence(Collect(*rec, {"/scan"}), 20);
}

TEST(Rosbag2SqliteTest, DatabaseWithoutTopicsTableIsNotRosbag2) {
  const std::string path = FreshScratchFolder("other") + "/other.db3";
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  sqlite3_exec(db, "CREATE TABLE things(id INTEGER); INSERT INTO things VALUES (1);", nullptr,
               nullptr, nullptr);
  sqlite3_close(db);
  std::string error = ThrownMessage<io::InputError>([&] { OpenRosbag2(path); });
  EXPECT_NE(error.find("no 'topics' table: not a rosbag2 database"), std::string::npos) << error;

  const std::string text = FreshScratchFolder("text") + "/notes.db3";
  std::ofstream(text) << "not a database at all, just some text that is long enough\n";
  error = ThrownMessage<io::InputError>([&] { OpenRosbag2(text); });
  EXPECT_NE(error.find("not an SQLite database"), std::string::npos) << error;
}

TEST(Rosbag2SqliteTest, CutOrDamagedDatabaseThrowsOrReads) {
  const std::string dir = FreshScratchFolder("cut");
  const std::string whole = dir + "/whole.db3";
  WriteDb3(whole, Rosbag2Layout::kIron, 0, 200);
  std::ifstream in(whole, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  int thrown = 0, read = 0;
  for (size_t cut = 0; cut < bytes.size(); cut += 509) {
    for (const bool flip : {false, true}) {
      std::string damaged = bytes.substr(0, flip ? bytes.size() : cut);
      if (flip) damaged[cut] = static_cast<char>(damaged[cut] ^ 0x5A);
      const std::string path = dir + "/damaged.db3";
      std::ofstream(path, std::ios::binary | std::ios::trunc) << damaged;
      try {
        auto rec = OpenRosbag2(path);
        std::set<std::string> names;
        for (const TopicInfo& t : rec->topics()) {
          if (t.encoding == "cdr") names.insert(t.name);
        }
        EXPECT_LE(Collect(*rec, names).size(), 300u);
        ++read;
      } catch (const io::InputError&) {
        ++thrown;
      }
    }
  }
  EXPECT_GT(thrown, 0);
  EXPECT_GT(read, 0);
}

TEST(Rosbag2SqliteTest, UnknownTopicAndOtherSerializationThrow) {
  const std::string path = FreshScratchFolder("unknown") + "/bag.db3";
  {
    Rosbag2SqliteWriter w(path, Rosbag2Layout::kHumble);
    w.AddTopic("/scan", "sensor_msgs/msg/LaserScan", "");
    const int64_t json = w.AddTopic("/status", "my_msgs/msg/Status", "", "json");
    w.Write(json, 1.0, std::vector<uint8_t>{'{', '}'});
    w.Close();
  }
  auto rec = OpenRosbag2(path);
  std::string error = ThrownMessage<io::InputError>([&] { Collect(*rec, {"/imu"}); });
  EXPECT_NE(error.find("no topic /imu in the recording (topics: /scan, /status)"),
            std::string::npos)
      << error;
  error = ThrownMessage<io::InputError>([&] { Collect(*rec, {"/status"}); });
  EXPECT_NE(error.find("topic /status is serialized as 'json'"), std::string::npos) << error;
  EXPECT_TRUE(Collect(*rec, {"/scan"}).empty());
}

TEST(Rosbag2MetadataTest, ParsesRosbag2Yaml) {
  const io::Rosbag2Metadata meta = io::ParseRosbag2Metadata(
      "rosbag2_bagfile_information:\n"
      "  version: 5\n"
      "  storage_identifier: sqlite3\n"
      "  duration:\n    nanoseconds: 151137181\n"
      "  starting_time:\n    nanoseconds_since_epoch: 1586406456763032325\n"
      "  message_count: 7\n"
      "  topics_with_message_count:\n"
      "    - topic_metadata:\n        name: /test_topic\n        type: test_msgs/msg/BasicTypes\n"
      "        serialization_format: cdr\n        offered_qos_profiles: ''\n"
      "      message_count: 3\n"
      "  compression_format: ''\n  compression_mode: ''\n"
      "  relative_file_paths:\n    - cdr_test_0.db3\n",
      "metadata.yaml");
  EXPECT_EQ(meta.storage_identifier, "sqlite3");
  EXPECT_EQ(meta.relative_file_paths, std::vector<std::string>{"cdr_test_0.db3"});
  EXPECT_EQ(meta.starting_time_ns, 1586406456763032325);
  EXPECT_EQ(meta.duration_ns, 151137181);
  ASSERT_EQ(meta.topics.size(), 1u);
  EXPECT_EQ(meta.topics[0].message_count, 3);
}

TEST(Rosbag2MetadataTest, BadYamlSaysWhereAndWhat) {
  std::string error = ThrownMessage<io::InputError>([] {
    io::ParseRosbag2Metadata("rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n",
                             "m.yaml");
  });
  EXPECT_NE(error.find("relative_file_paths"), std::string::npos) << error;
  error = ThrownMessage<io::InputError>([] {
    io::ParseRosbag2Metadata(
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
        "  relative_file_paths: [a.db3]\n  message_count: lots\n",
        "m.yaml");
  });
  EXPECT_NE(error.find("m.yaml:4: 'message_count' is not an integer"), std::string::npos) << error;
  error =
      ThrownMessage<io::InputError>([] { io::ParseRosbag2Metadata("key: [unclosed\n", "m.yaml"); });
  EXPECT_NE(error.find("m.yaml:"), std::string::npos) << error;
  error = ThrownMessage<io::InputError>([] {
    io::ParseRosbag2Metadata(
        "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
        "  relative_file_paths: [a.db3]\n  topics_with_message_count:\n"
        "    - topic_metadata: {name: '', type: x}\n",
        "m.yaml");
  });
  EXPECT_NE(error.find("m.yaml:5: a topic_metadata has an empty name"), std::string::npos) << error;
  error = ThrownMessage<io::InputError>([] { io::ParseRosbag2Metadata("other: 1\n", "m.yaml"); });
  EXPECT_NE(error.find("rosbag2_bagfile_information"), std::string::npos) << error;
}

TEST(Rosbag2SqliteTest, CompressedBagIsRefused) {
  const std::string dir = FreshScratchFolder("compressed");
  std::ofstream(dir + "/metadata.yaml")
      << "rosbag2_bagfile_information:\n  storage_identifier: sqlite3\n"
         "  compression_format: zstd\n  compression_mode: FILE\n"
         "  relative_file_paths: [bag_0.db3.zstd]\n";
  const std::string error = ThrownMessage<io::InputError>([&] { OpenRosbag2(dir); });
  EXPECT_NE(error.find("compression_format 'zstd', mode 'FILE'"), std::string::npos) << error;
}

}  // namespace
}  // namespace wallcal::recording
