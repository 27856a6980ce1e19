// SPDX-License-Identifier: Apache-2.0
// ROS 1 bag v2.0: the real bags in ../shared/testdata/real/ros1 (counts and fields checked
// against an independent decoder), writer round trips for each compression, and damaged input.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <vector>

#include "common/enum_text.h"
#include "io/types.h"
#include "recording/ros/ros_messages.h"
#include "recording/rosbag1/internal/rosbag1_reader.h"
#include "recording/writers/rosbag1_writer.h"
#include "test/support/expect_text.h"
#include "test/support/scratch_files.h"

namespace wallcal::recording {
namespace {

using testing_support::ScratchPath;

const std::string kRealDir = WALLCAL_SOURCE_DIR "/../shared/testdata/real/ros1";

#define REQUIRE_REAL(file)                               \
  if (!std::filesystem::exists(kRealDir + "/" + (file))) \
  GTEST_SKIP() << "shared test data absent (" << kRealDir << "/" << (file) << ")"

struct Seen {
  std::string topic;
  double receive_s;
  std::vector<uint8_t> payload;
  int64_t index;
};

std::vector<Seen> ReadAll(Recording& bag, std::set<std::string> topics = {}) {
  if (topics.empty()) {
    for (const TopicInfo& t : bag.topics()) topics.insert(t.name);
  }
  std::vector<Seen> seen;
  bag.ForEach(topics, [&](const RecordedMessage& m) {
    seen.push_back(
        {m.topic->name, m.receive_s, std::vector<uint8_t>(m.data, m.data + m.size), m.index});
  });
  return seen;
}

const TopicInfo* Find(const Recording& bag, const std::string& name) {
  for (const TopicInfo& t : bag.topics()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

std::vector<uint8_t> Slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

TEST(Ros1BagRealTest, ScanToolsDemoLaserScans) {
  REQUIRE_REAL("scan_tools-demo.bag");
  const auto bag = OpenRos1Bag(kRealDir + "/scan_tools-demo.bag");
  ASSERT_EQ(bag->topics().size(), 1u);
  const TopicInfo& scan = bag->topics()[0];
  EXPECT_EQ(scan.name, "/scan");
  EXPECT_EQ(scan.type, "sensor_msgs/LaserScan");
  EXPECT_EQ(scan.md5sum, RosTypeMd5(RosType::kLaserScan));
  EXPECT_EQ(scan.encoding, "ros1");
  EXPECT_EQ(scan.count, 360);
  EXPECT_NEAR(scan.first_s, 1282836371.069930792, 1e-6);
  EXPECT_NEAR(scan.last_s, 1282836406.881212711, 1e-6);
  EXPECT_EQ(bag->compressions(), std::set<ChunkCompression>{ChunkCompression::kNone});
  // Found through the index, whose index-data records declare 20 bytes per 12-byte entry.
  EXPECT_TRUE(static_cast<Ros1Bag&>(*bag).index_used());
  ASSERT_EQ(bag->warnings().size(), 1u);
  EXPECT_NE(bag->warnings()[0].find("byte 792650"), std::string::npos) << bag->warnings()[0];

  int64_t n = 0;
  double last_receive = 0;
  bag->ForEach({"/scan"}, [&](const RecordedMessage& m) {
    LaserScanMsg msg;
    const DecodeResult r = DecodeLaserScan(m.data, m.size, m.wire, &msg);
    ASSERT_TRUE(r.ok()) << r.detail;
    EXPECT_EQ(m.index, n);
    EXPECT_GE(m.receive_s, last_receive);
    last_receive = m.receive_s;
    EXPECT_EQ(msg.ranges_m.size(), 681u);
    EXPECT_NEAR(msg.angle_min_rad, -2.0862138, 1e-6);
    EXPECT_NEAR(msg.range_min_m, 0.02, 1e-6);
    EXPECT_NEAR(msg.range_max_m, 5.6, 1e-6);
    if (n == 0) {  // values from the independent decoder
      EXPECT_EQ(msg.header.seq, 931u);
      EXPECT_NEAR(msg.header.stamp_s, 1282836370.970876455, 1e-6);
      EXPECT_EQ(msg.header.frame_id, "/laser");
      EXPECT_NEAR(m.receive_s, 1282836371.069930792, 1e-6);
      EXPECT_FLOAT_EQ(msg.ranges_m[0], 3.002f);
      EXPECT_FLOAT_EQ(msg.ranges_m[340], 0.942f);
      EXPECT_FLOAT_EQ(msg.angle_increment_rad, 0.006135923f);
      EXPECT_TRUE(msg.intensities.empty());
    }
    ++n;
  });
  EXPECT_EQ(n, 360);
}

// Sets the bag header's index_pos to 0, as a killed recorder leaves it.
void ZeroIndexPos(std::vector<uint8_t>* bytes) {
  const std::string field = "index_pos=";
  const auto it = std::search(bytes->begin(), bytes->begin() + 200, field.begin(), field.end());
  ASSERT_NE(it, bytes->begin() + 200);
  std::fill(it + static_cast<long>(field.size()), it + static_cast<long>(field.size()) + 8, 0);
}

TEST(Ros1BagRealTest, WalkingTheRecordsFindsWhatTheIndexFinds) {
  REQUIRE_REAL("scan_tools-demo.bag");
  std::vector<uint8_t> bytes = Slurp(kRealDir + "/scan_tools-demo.bag");
  const auto indexed = OpenRos1BagFromMemory(bytes, "demo");
  ZeroIndexPos(&bytes);
  const auto walked = OpenRos1BagFromMemory(bytes, "demo-walked");
  EXPECT_FALSE(static_cast<Ros1Bag&>(*walked).index_used());
  ASSERT_FALSE(walked->warnings().empty());
  EXPECT_NE(walked->warnings()[0].find("records walked"), std::string::npos);
  ASSERT_EQ(walked->topics().size(), 1u);
  EXPECT_EQ(walked->topics()[0].count, 360);
  const std::vector<Seen> a = ReadAll(*indexed), b = ReadAll(*walked);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].payload, b[i].payload);
    EXPECT_EQ(a[i].receive_s, b[i].receive_s);
  }
}

TEST(Ros1BagRealTest, RobotLocalizationBz2FixesAndImu) {
  REQUIRE_REAL("robot_localization-test1.bag");
  const auto bag = OpenRos1Bag(kRealDir + "/robot_localization-test1.bag");
  EXPECT_EQ(bag->compressions(), std::set<ChunkCompression>{ChunkCompression::kBz2});
  EXPECT_TRUE(bag->warnings().empty());
  ASSERT_NE(Find(*bag, "/fix"), nullptr);
  ASSERT_NE(Find(*bag, "/imu/data"), nullptr);
  ASSERT_NE(Find(*bag, "/husky_velocity_controller/odom"), nullptr);
  EXPECT_EQ(Find(*bag, "/fix")->count, 989);
  EXPECT_EQ(Find(*bag, "/imu/data")->count, 11865);
  EXPECT_EQ(Find(*bag, "/husky_velocity_controller/odom")->count, 3952);
  EXPECT_EQ(Find(*bag, "/fix")->md5sum, RosTypeMd5(RosType::kNavSatFix));
  EXPECT_EQ(Find(*bag, "/imu/data")->md5sum, RosTypeMd5(RosType::kImu));

  int64_t fixes = 0, imus = 0;
  double lat_min = 90, lat_max = -90, lon_min = 180, lon_max = -180, last = 0;
  bag->ForEach({"/fix", "/imu/data"}, [&](const RecordedMessage& m) {
    EXPECT_GE(m.receive_s, last);
    last = m.receive_s;
    if (m.topic->name == "/fix") {
      NavSatFixMsg fix;
      ASSERT_TRUE(DecodeNavSatFix(m.data, m.size, m.wire, &fix).ok());
      EXPECT_EQ(fix.position_covariance_type, 1);
      lat_min = std::min(lat_min, fix.latitude_deg);
      lat_max = std::max(lat_max, fix.latitude_deg);
      lon_min = std::min(lon_min, fix.longitude_deg);
      lon_max = std::max(lon_max, fix.longitude_deg);
      if (fixes == 0) {
        EXPECT_EQ(fix.header.frame_id, "/gps");
        EXPECT_EQ(fix.status, 1);
        EXPECT_EQ(fix.service, 1);
        EXPECT_DOUBLE_EQ(fix.latitude_deg, 42.375812);
        EXPECT_NEAR(fix.longitude_deg, -71.14739466666667, 1e-12);
        EXPECT_NEAR(fix.altitude_m, 7.3, 1e-9);
        EXPECT_NEAR(fix.header.stamp_s, 1432235498.039089918, 1e-6);
      }
      ++fixes;
    } else {
      QuaternionMsg imu;
      ASSERT_TRUE(DecodeImu(m.data, m.size, m.wire, &imu).ok());
      if (imus == 0) {
        EXPECT_EQ(imu.header.frame_id, "imu_link");
        EXPECT_NEAR(imu.x, 0.4441650138815254, 1e-15);
        EXPECT_NEAR(imu.w, 0.45001884929497193, 1e-15);
      }
      ++imus;
    }
  });
  EXPECT_EQ(fixes, 989);
  EXPECT_EQ(imus, 11865);
  // The independent decoder's extremes.
  EXPECT_NEAR(lat_min, 42.375799, 1e-6);
  EXPECT_NEAR(lat_max, 42.377113, 1e-6);
  EXPECT_NEAR(lon_min, -71.147831, 1e-6);
  EXPECT_NEAR(lon_max, -71.147132, 1e-6);
}

TEST(Ros1BagRealTest, RosbagJsExampleSameMessagesInEveryCompression) {
  REQUIRE_REAL("rosbagjs-example.bag");
  const std::map<std::string, int64_t> expected = {{"/rosout", 10},
                                                   {"/tf", 2688},
                                                   {"/tf_static", 1},
                                                   {"/turtle1/cmd_vel", 357},
                                                   {"/turtle1/color_sensor", 1351},
                                                   {"/turtle1/pose", 1344},
                                                   {"/turtle2/cmd_vel", 208},
                                                   {"/turtle2/color_sensor", 1344},
                                                   {"/turtle2/pose", 1344}};
  std::map<std::string, std::vector<Seen>> reference;
  for (const char* file :
       {"rosbagjs-example.bag", "rosbagjs-example-bz2.bag", "rosbagjs-example-lz4.bag"}) {
    SCOPED_TRACE(file);
    const auto bag = OpenRos1Bag(kRealDir + "/" + file);
    EXPECT_TRUE(bag->warnings().empty());
    std::map<std::string, int64_t> counts;
    for (const TopicInfo& t : bag->topics()) counts[t.name] = t.count;
    EXPECT_EQ(counts, expected);
    std::map<std::string, std::vector<Seen>> by_topic;
    for (Seen& s : ReadAll(*bag)) by_topic[s.topic].push_back(std::move(s));
    for (const auto& [topic, n] : expected) {
      EXPECT_EQ(static_cast<int64_t>(by_topic[topic].size()), n) << topic;
    }
    if (reference.empty()) {
      reference = std::move(by_topic);
      continue;
    }
    for (const auto& [topic, messages] : reference) {
      ASSERT_EQ(by_topic[topic].size(), messages.size()) << topic;
      for (size_t i = 0; i < messages.size(); ++i) {
        EXPECT_EQ(by_topic[topic][i].payload, messages[i].payload) << topic << " #" << i;
        EXPECT_EQ(by_topic[topic][i].receive_s, messages[i].receive_s) << topic << " #" << i;
      }
    }
  }
  EXPECT_NEAR(reference["/turtle1/pose"][0].receive_s, 1396293888.056045055, 1e-6);
}

TEST(Ros1BagRealTest, UnknownTopicListsThePresentOnes) {
  REQUIRE_REAL("scan_tools-demo.bag");
  const auto bag = OpenRos1Bag(kRealDir + "/scan_tools-demo.bag");
  try {
    bag->ForEach({"/fix"}, [](const RecordedMessage&) {});
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/fix"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("topics: /scan"), std::string::npos) << e.what();
  }
}

// A bag from the writer: scans, fixes and IMU at their usual rates for `seconds`, with receive
// times slightly out of order (as a recorder's threads deliver them).
struct Written {
  std::vector<Seen> messages;  // in the order they should come back
  std::string path;
};

Written WriteSample(const std::string& name, ChunkCompression compression, double seconds,
                    size_t chunk_bytes) {
  Written w;
  w.path = ScratchPath(name);
  Ros1BagWriter writer(w.path, compression, chunk_bytes);
  const int scan = writer.AddConnection("/scan", RosType::kLaserScan);
  const int fix = writer.AddConnection("/fix", RosType::kNavSatFix);
  const int imu = writer.AddConnection("/imu", RosType::kImu);
  const double t0 = 1700000000.0;
  struct Item {
    double t;
    int conn;
    std::vector<uint8_t> payload;
  };
  std::vector<Item> items;
  for (int i = 0; i < static_cast<int>(seconds * 40); ++i) {
    LaserScanMsg m;
    m.header.seq = static_cast<uint32_t>(i);
    m.header.stamp_s = t0 + i / 40.0;
    m.header.frame_id = "laser";
    m.angle_min_rad = -2.0f;
    m.angle_increment_rad = 0.01f;
    for (int b = 0; b < 271; ++b) m.ranges_m.push_back(1.0f + 0.001f * ((b * 7 + i) % 1000));
    items.push_back({m.header.stamp_s + 0.003, scan, EncodeLaserScan(m, WireFormat::kRos1)});
  }
  for (int i = 0; i < static_cast<int>(seconds * 10); ++i) {
    NavSatFixMsg m;
    m.header.stamp_s = t0 + i / 10.0;
    m.latitude_deg = 42.0 + i * 1e-6;
    items.push_back({m.header.stamp_s + 0.02, fix, EncodeNavSatFix(m, WireFormat::kRos1)});
  }
  for (int i = 0; i < static_cast<int>(seconds * 100); ++i) {
    QuaternionMsg m;
    m.header.stamp_s = t0 + i / 100.0;
    m.z = std::sin(i * 0.01);
    m.w = std::cos(i * 0.01);
    // Every 7th delivered 15 ms late, after later ones: written out of time order.
    items.push_back(
        {m.header.stamp_s + (i % 7 == 0 ? 0.015 : 0.001), imu, EncodeImu(m, WireFormat::kRos1)});
  }
  // Written in a scrambled but mostly forward order: by time rounded to 50 ms, then topic.
  std::stable_sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    return std::floor(a.t * 20) < std::floor(b.t * 20);
  });
  const char* names[] = {"/scan", "/fix", "/imu"};
  for (const Item& item : items) writer.Write(item.conn, item.t, item.payload);
  writer.Close();
  // Expected order: receive time rounded to the nanosecond as stored, ties in write order.
  std::vector<size_t> order(items.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  auto ns = [](double t) { return std::llround((t - 1700000000.0) * 1e9); };
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return ns(items[a].t) < ns(items[b].t); });
  for (size_t i : order) {
    w.messages.push_back({names[items[i].conn], items[i].t, items[i].payload, 0});
  }
  return w;
}

std::string CompressionLabel(ChunkCompression compression) {
  static const EnumText<ChunkCompression> kTexts[] = {{ChunkCompression::kBz2, "Bz2"},
                                                      {ChunkCompression::kLz4, "Lz4"}};
  return TextOf(kTexts, compression, "None");
}

class WriterRoundTripTest : public ::testing::TestWithParam<ChunkCompression> {};

TEST_P(WriterRoundTripTest, ReadsBackWhatWasWritten) {
  const Written w = WriteSample("roundtrip.bag", GetParam(), 6.0, 64 * 1024);
  const auto bag = OpenRos1Bag(w.path);
  EXPECT_TRUE(static_cast<Ros1Bag&>(*bag).index_used());
  EXPECT_TRUE(bag->warnings().empty());
  EXPECT_EQ(bag->compressions(), std::set<ChunkCompression>{GetParam()});
  ASSERT_EQ(bag->topics().size(), 3u);
  EXPECT_EQ(bag->topics()[0].name, "/fix");  // sorted by name
  EXPECT_EQ(Find(*bag, "/scan")->count, 240);
  EXPECT_EQ(Find(*bag, "/fix")->count, 60);
  EXPECT_EQ(Find(*bag, "/imu")->count, 600);
  EXPECT_EQ(Find(*bag, "/imu")->type, "sensor_msgs/Imu");
  EXPECT_EQ(Find(*bag, "/imu")->md5sum, RosTypeMd5(RosType::kImu));
  const std::vector<Seen> back = ReadAll(*bag);
  ASSERT_EQ(back.size(), w.messages.size());
  std::map<std::string, int64_t> per_topic;
  for (size_t i = 0; i < back.size(); ++i) {
    EXPECT_EQ(back[i].topic, w.messages[i].topic) << i;
    EXPECT_EQ(back[i].payload, w.messages[i].payload) << i;
    EXPECT_NEAR(back[i].receive_s, w.messages[i].receive_s, 1e-6) << i;
    EXPECT_EQ(back[i].index, per_topic[back[i].topic]++);
  }
  // Only the requested topic, and the same bytes when walked without the index.
  EXPECT_EQ(ReadAll(*bag, {"/fix"}).size(), 60u);
  std::vector<uint8_t> bytes = Slurp(w.path);
  ZeroIndexPos(&bytes);
  const auto walked = OpenRos1BagFromMemory(bytes, "walked");
  EXPECT_FALSE(static_cast<Ros1Bag&>(*walked).index_used());
  const std::vector<Seen> walked_back = ReadAll(*walked);
  ASSERT_EQ(walked_back.size(), back.size());
  for (size_t i = 0; i < back.size(); ++i) EXPECT_EQ(walked_back[i].payload, back[i].payload);
  std::remove(w.path.c_str());
}

INSTANTIATE_TEST_SUITE_P(EveryCompression, WriterRoundTripTest,
                         ::testing::Values(ChunkCompression::kNone, ChunkCompression::kBz2,
                                           ChunkCompression::kLz4),
                         [](const auto& param_info) { return CompressionLabel(param_info.param); });

TEST(Ros1BagWriterTest, NoBagLeftWithoutClose) {
  const std::string path = ScratchPath("unclosed.bag");
  {
    Ros1BagWriter writer(path, ChunkCompression::kNone);
    const int c = writer.AddConnection("/fix", RosType::kNavSatFix);
    writer.Write(c, 10.0, EncodeNavSatFix(NavSatFixMsg(), WireFormat::kRos1));
  }
  EXPECT_FALSE(std::filesystem::exists(path));
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
  EXPECT_THROW(Ros1BagWriter(path, ChunkCompression::kZstd), io::InputError);
}

TEST(Ros1BagWriterTest, BagWithoutMessagesOpensClean) {
  const std::string path = ScratchPath("empty.bag");
  {
    Ros1BagWriter writer(path, ChunkCompression::kBz2);
    writer.AddConnection("/scan", RosType::kLaserScan);
    writer.Close();
  }
  const auto bag = OpenRos1Bag(path);
  std::remove(path.c_str());
  EXPECT_TRUE(static_cast<Ros1Bag&>(*bag).index_used());
  EXPECT_TRUE(bag->warnings().empty());
  ASSERT_EQ(bag->topics().size(), 1u);
  EXPECT_EQ(bag->topics()[0].count, 0);
  EXPECT_TRUE(ReadAll(*bag).empty());
}

// Reads a damaged bag: an io::InputError, or messages that are each one of the originals (once),
// in time order, with a warning saying what was lost. Returns how many messages came back
// (-1: error). (A cut keeps the messages written before it: with out-of-order writes that is
// not a prefix in time.)
int64_t ReadDamaged(const std::vector<uint8_t>& bytes, const std::vector<Seen>& original) {
  try {
    const auto bag = OpenRos1BagFromMemory(bytes, "cut");
    std::map<std::pair<std::string, std::vector<uint8_t>>, int> left;
    for (const Seen& s : original) ++left[{s.topic, s.payload}];
    int64_t n = 0;
    double last = 0;
    for (const Seen& s : ReadAll(*bag)) {
      int& copies = left[std::make_pair(s.topic, s.payload)];
      EXPECT_GT(copies--, 0) << s.topic << " message not written";
      EXPECT_GE(s.receive_s, last);
      last = s.receive_s;
      ++n;
    }
    if (n < static_cast<int64_t>(original.size())) {
      EXPECT_FALSE(bag->warnings().empty());
    }
    return n;
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cut"), std::string::npos);
    return -1;
  }
}

TEST(Ros1BagDamageTest, CutAtEvery97thByte) {
  for (ChunkCompression compression :
       {ChunkCompression::kNone, ChunkCompression::kBz2, ChunkCompression::kLz4}) {
    const Written w = WriteSample("cut.bag", compression, 1.0, 8 * 1024);
    const std::vector<uint8_t> bytes = Slurp(w.path);
    std::remove(w.path.c_str());
    int64_t errors = 0, partial = 0, most = 0;
    for (size_t cut = 0; cut < bytes.size(); cut += 97) {
      const int64_t n =
          ReadDamaged(std::vector<uint8_t>(bytes.begin(), bytes.begin() + cut), w.messages);
      errors += n < 0;
      partial += n >= 0 && n < static_cast<int64_t>(w.messages.size());
      most = std::max(most, n);
    }
    // Cuts inside the bag header fail; later cuts read what comes before them.
    EXPECT_GT(errors, 0);
    EXPECT_GT(partial, 0);
    EXPECT_EQ(most, static_cast<int64_t>(w.messages.size()));  // cut inside the index
  }
}

TEST(Ros1BagDamageTest, RealBagsCutAnywhere) {
  REQUIRE_REAL("robot_localization-test1.bag");
  // (file, step): bz2 chunks are slow to decompress, so fewer cuts there.
  for (const auto& [file, step] : {std::make_pair("scan_tools-demo.bag", 9973),
                                   std::make_pair("robot_localization-test1.bag", 299993)}) {
    const std::vector<uint8_t> bytes = Slurp(kRealDir + "/" + file);
    int64_t read = 0;
    for (size_t cut = 50; cut < bytes.size(); cut += static_cast<size_t>(step)) {
      std::vector<uint8_t> head(bytes.begin(), bytes.begin() + static_cast<long>(cut));
      try {
        const auto bag = OpenRos1BagFromMemory(std::move(head), "cut");
        EXPECT_FALSE(bag->warnings().empty());
        read += static_cast<int64_t>(ReadAll(*bag).size());
      } catch (const io::InputError&) {
      }
    }
    EXPECT_GT(read, 0) << file;
  }
}

TEST(Ros1BagDamageTest, NeverClosedChunkIsReadToTheEnd) {
  // What a killed rosbag leaves: bag header with index_pos 0, the open chunk's header with zero
  // lengths, its records up to where the process died.
  const Written w = WriteSample("killed.bag", ChunkCompression::kNone, 1.0, 1 << 20);
  std::vector<uint8_t> bytes = Slurp(w.path);
  std::remove(w.path.c_str());
  ZeroIndexPos(&bytes);
  const size_t chunk_pos = 13 + 4096;
  const uint32_t header_len = bytes[chunk_pos] | bytes[chunk_pos + 1] << 8;
  const size_t size_field = chunk_pos + 4 + header_len - 4;  // "size=" is the last field
  ASSERT_EQ(std::string(bytes.begin() + size_field - 5, bytes.begin() + size_field), "size=");
  const size_t data_len =
      bytes[size_field + 4] | bytes[size_field + 5] << 8 | bytes[size_field + 6] << 16;
  const size_t chunk_end = size_field + 8 + data_len;
  std::fill(bytes.begin() + size_field, bytes.begin() + size_field + 8, 0);  // size, data_len
  bytes.resize(chunk_end - 1500);  // died mid-chunk: no index data, no index
  const auto bag = OpenRos1BagFromMemory(bytes, "killed");
  ASSERT_GE(bag->warnings().size(), 2u);
  EXPECT_NE(bag->warnings()[0].find("index_pos 0"), std::string::npos);
  EXPECT_NE(bag->warnings()[1].find("messages read from it"), std::string::npos);
  const int64_t n = ReadDamaged(bytes, w.messages);
  EXPECT_GT(n, 100);
  EXPECT_LT(n, static_cast<int64_t>(w.messages.size()));
}

LaserScanMsg TinyScanForBag() {
  LaserScanMsg m;
  m.header.frame_id = "laser";
  m.ranges_m = {1.0f, 2.0f, 3.0f};
  return m;
}

std::vector<uint8_t> FlipInFirstChunk(ChunkCompression compression, const Written& w) {
  std::vector<uint8_t> bytes = Slurp(w.path);
  std::remove(w.path.c_str());
  (void)compression;
  const size_t chunk_pos = 13 + 4096;
  for (size_t i = chunk_pos + 300; i < chunk_pos + 340; ++i) bytes[i] ^= 0x5a;
  return bytes;
}

TEST(Ros1BagDamageTest, CorruptCompressedChunkNamesItsOffset) {
  for (ChunkCompression compression : {ChunkCompression::kBz2, ChunkCompression::kLz4}) {
    const Written w = WriteSample("corrupt.bag", compression, 1.0, 1 << 20);
    const auto bag = OpenRos1BagFromMemory(FlipInFirstChunk(compression, w), "corrupt.bag");
    testing_support::ExpectContains(
        testing_support::MessageOf<io::InputError>([&] { ReadAll(*bag); }),
        {"corrupt.bag:byte 4109: chunk does not decompress"});
  }
}

TEST(Ros1BagDamageTest, OnlyChunksOfRequestedTopicsAreDecompressed) {
  const std::string path = ScratchPath("two-chunks.bag");
  {
    Ros1BagWriter writer(path, ChunkCompression::kLz4, /*chunk_bytes=*/1);  // a chunk each
    const int fix = writer.AddConnection("/fix", RosType::kNavSatFix);
    const int scan = writer.AddConnection("/scan", RosType::kLaserScan);
    writer.Write(fix, 1.0, EncodeNavSatFix(NavSatFixMsg(), WireFormat::kRos1));
    writer.Write(scan, 2.0, EncodeLaserScan(TinyScanForBag(), WireFormat::kRos1));
    writer.Close();
  }
  std::vector<uint8_t> bytes = Slurp(path);
  std::remove(path.c_str());
  const std::string field = "compression=lz4";
  auto second = std::search(bytes.begin(), bytes.end(), field.begin(), field.end());
  ASSERT_NE(second, bytes.end());
  second = std::search(second + 1, bytes.end(), field.begin(), field.end());
  ASSERT_NE(second, bytes.end());
  for (auto it = second + 300; it != second + 320; ++it) *it ^= 0x5a;  // inside /scan's chunk
  const auto bag = OpenRos1BagFromMemory(bytes, "two-chunks.bag");
  EXPECT_EQ(ReadAll(*bag, {"/fix"}).size(), 1u);
  EXPECT_THROW(ReadAll(*bag, {"/scan"}), io::InputError);
}

TEST(Ros1BagDamageTest, UnknownCompressionIsNamed) {
  const Written w = WriteSample("xz.bag", ChunkCompression::kLz4, 0.5, 1 << 20);
  std::vector<uint8_t> bytes = Slurp(w.path);
  std::remove(w.path.c_str());
  const std::string field = "compression=lz4";
  auto it = std::search(bytes.begin(), bytes.end(), field.begin(), field.end());
  ASSERT_NE(it, bytes.end());
  std::copy_n("compression=xz9", field.size(), it);
  try {
    OpenRos1BagFromMemory(bytes, "xz.bag");
    FAIL() << "no error";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("'xz9'"), std::string::npos) << e.what();
  }
}

TEST(Ros1BagDamageTest, NotABag) {
  const std::string text = "#ROSBAG V1.2\nold";
  EXPECT_THROW(OpenRos1BagFromMemory(std::vector<uint8_t>(text.begin(), text.end()), "old.bag"),
               io::InputError);
  EXPECT_THROW(OpenRos1BagFromMemory({}, "empty.bag"), io::InputError);
  EXPECT_THROW(OpenRos1Bag("/nonexistent/x.bag"), io::InputError);
}

}  // namespace
}  // namespace wallcal::recording
