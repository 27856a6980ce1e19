// SPDX-License-Identifier: Apache-2.0
// MCAP reader and writer: the real rosbag2 MCAP files (expected values from an independent
// decode of the files, not from this reader), writer round trips for every chunk compression,
// records walked without a summary, and damaged input (cuts, flipped bytes, CRCs, codecs).

#include <gtest/gtest.h>
#include <zlib.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "io/types.h"
#include "recording/mcap/internal/mcap_reader.h"
#include "recording/mcap/internal/mcap_records.h"
#include "recording/writers/mcap_writer.h"
#include "test/support/expect_text.h"
#include "test/support/recorded_messages.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;
using namespace testing_support;  // NOLINT: the test helpers of test/support

std::vector<uint8_t> ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

uint32_t Crc(const std::vector<uint8_t>& v) {
  return static_cast<uint32_t>(crc32(0, v.data(), static_cast<uInt>(v.size())));
}

const TopicInfo* Find(const Recording& rec, const std::string& name) {
  for (const TopicInfo& t : rec.topics()) {
    if (t.name == name) return &t;
  }
  return nullptr;
}

#define SKIP_WITHOUT_REAL()                                   \
  do {                                                        \
    if (!fs::exists(kRealRos2)) {                             \
      GTEST_SKIP() << "no shared test data at " << kRealRos2; \
    }                                                         \
  } while (0)

TEST(McapReaderTest, ReadsRosbag2CdrTestFile) {
  SKIP_WITHOUT_REAL();
  auto rec = OpenMcap(kRealRos2 + "/rosbag2-cdr_test_0.mcap");
  EXPECT_EQ(rec->format(), RecordingFormat::kMcap);
  EXPECT_TRUE(rec->warnings().empty());
  EXPECT_EQ(rec->compressions(), std::set<ChunkCompression>{ChunkCompression::kNone});
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[0].name, "/array_topic");  // sorted by name
  EXPECT_EQ(rec->topics()[0].type, "test_msgs/msg/Arrays");
  EXPECT_EQ(rec->topics()[0].encoding, "cdr");
  EXPECT_EQ(rec->topics()[0].count, 4);
  EXPECT_NEAR(rec->topics()[0].first_s, 1586406456.782683500, 1e-6);
  EXPECT_NEAR(rec->topics()[0].last_s, 1586406456.914169506, 1e-6);
  EXPECT_EQ(rec->topics()[1].name, "/test_topic");
  EXPECT_EQ(rec->topics()[1].type, "test_msgs/msg/BasicTypes");
  EXPECT_EQ(rec->topics()[1].count, 3);

  // Independent decode: log times, sizes and CRC-32 of each payload, in log-time order.
  struct Want {
    const char* topic;
    double t_s;
    size_t size;
    uint32_t crc;
  };
  const Want want[] = {
      {"/test_topic", 1586406456.763032325, 52, 0x2b671247},
      {"/array_topic", 1586406456.782683500, 696, 0xab8a469a},
      {"/test_topic", 1586406456.812989925, 52, 0x2b671247},
      {"/array_topic", 1586406456.814049600, 696, 0xab8a469a},
      {"/test_topic", 1586406456.863382628, 52, 0x2b671247},
      {"/array_topic", 1586406456.866330524, 696, 0xab8a469a},
      {"/array_topic", 1586406456.914169506, 696, 0xab8a469a},
  };
  const std::vector<GotMessage> got = CollectMessages(*rec, {"/test_topic", "/array_topic"});
  ASSERT_EQ(got.size(), 7u);
  int64_t tests = 0, arrays = 0;
  for (size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].topic, want[i].topic) << i;
    EXPECT_NEAR(got[i].receive_s, want[i].t_s, 1e-6) << i;
    EXPECT_EQ(got[i].data.size(), want[i].size) << i;
    EXPECT_EQ(Crc(got[i].data), want[i].crc) << i;
    EXPECT_EQ(got[i].index, got[i].topic == "/test_topic" ? tests++ : arrays++);
    EXPECT_EQ(got[i].file_offset, 42u);  // the one chunk starts at byte 42
  }
  // One topic alone.
  EXPECT_EQ(CollectMessages(*rec, {"/test_topic"}).size(), 3u);
}

TEST(McapReaderTest, ReadsZstdTalkerStrings) {
  SKIP_WITHOUT_REAL();
  auto rec = OpenMcap(kRealRos2 + "/rosbag2-talker.mcap");
  EXPECT_TRUE(rec->warnings().empty());
  EXPECT_EQ(rec->compressions(), std::set<ChunkCompression>{ChunkCompression::kZstd});
  ASSERT_EQ(rec->topics().size(), 3u);
  ASSERT_NE(Find(*rec, "/parameter_events"), nullptr);
  EXPECT_EQ(Find(*rec, "/parameter_events")->count, 0);
  EXPECT_EQ(Find(*rec, "/rosout")->count, 10);
  EXPECT_EQ(Find(*rec, "/rosout")->type, "rcl_interfaces/msg/Log");
  EXPECT_EQ(Find(*rec, "/topic")->type, "std_msgs/msg/String");
  EXPECT_EQ(Find(*rec, "/topic")->count, 10);
  EXPECT_NEAR(Find(*rec, "/topic")->first_s, 1585866235.112609068, 1e-6);
  EXPECT_NEAR(Find(*rec, "/topic")->last_s, 1585866239.643508139, 1e-6);

  const std::vector<GotMessage> got = CollectMessages(*rec, {"/topic"});
  ASSERT_EQ(got.size(), 10u);
  for (size_t i = 0; i < got.size(); ++i) {
    // CDR: 4-byte encapsulation header, uint32 length including the NUL, the characters.
    const std::vector<uint8_t>& d = got[i].data;
    ASSERT_EQ(d.size(), 24u);
    EXPECT_EQ(d[1], 0x01);  // CDR little endian
    uint32_t n = 0;
    std::memcpy(&n, &d[4], 4);
    ASSERT_EQ(n, 16u);
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(&d[8]), n - 1),
              "Hello, world! " + std::to_string(i));
    EXPECT_EQ(got[i].index, static_cast<int64_t>(i));
  }
  EXPECT_NEAR(got[0].receive_s, 1585866235.112609068, 1e-6);
  EXPECT_NEAR(got[9].receive_s, 1585866239.643508139, 1e-6);
  const std::vector<GotMessage> all = CollectMessages(*rec, {"/topic", "/rosout"});
  ASSERT_EQ(all.size(), 20u);
  for (size_t i = 0; i < all.size(); ++i) {
    EXPECT_EQ(all[i].topic, i % 2 == 0 ? "/rosout" : "/topic") << i;  // interleaved by time
    EXPECT_EQ(all[i].data.size(), i % 2 == 0 ? 176u : 24u);
  }
}

TEST(McapReaderTest, BufferEntryReadsTheSameAsTheFile) {
  SKIP_WITHOUT_REAL();
  const std::string path = kRealRos2 + "/rosbag2-talker.mcap";
  auto from_file = OpenMcap(path);
  auto from_buffer = OpenMcapBuffer("talker", ReadBytes(path));
  const auto a = CollectMessages(*from_file, {"/topic", "/rosout"});
  const auto b = CollectMessages(*from_buffer, {"/topic", "/rosout"});
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i].data, b[i].data);
}

// Two channels written in separate runs so chunks overlap in time: /b's messages are written
// after all of /a's. Payload: 4 bytes channel tag + the message's number.
std::string WriteTwoTopics(const std::string& path, ChunkCompression c, int n = 60,
                           size_t chunk_bytes = 300) {
  McapWriter w(path, c, chunk_bytes);
  const uint16_t a = w.AddChannel("/a", "std_msgs/msg/String", "string data\n");
  const uint16_t b = w.AddChannel("/b", "sensor_msgs/msg/LaserScan", "float32 angle_min\n");
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> p = {0, 1, 0, 0, 'a', static_cast<uint8_t>(i)};
    w.Write(a, 100.0 + 0.1 * i, 100.0 + 0.1 * i, p);
  }
  for (int i = 0; i < n; ++i) {
    std::vector<uint8_t> p = {0, 1, 0, 0, 'b', static_cast<uint8_t>(i), 7, 7, 7, 7};
    w.Write(b, 100.0 + 0.1 * i + (i % 2 == 0 ? 0.0 : 0.05), 100.0, p);  // even i: ties with /a
  }
  w.Close();
  return path;
}

void ExpectTwoTopicsInOrder(const std::vector<GotMessage>& got, int n) {
  ASSERT_EQ(got.size(), static_cast<size_t>(2 * n));
  for (size_t i = 1; i < got.size(); ++i) {
    ASSERT_LE(got[i - 1].receive_s, got[i].receive_s) << i;
    if (got[i - 1].receive_s == got[i].receive_s) {
      EXPECT_EQ(got[i - 1].topic, "/a");  // tie: /a was earlier in the file
      EXPECT_EQ(got[i].topic, "/b");
    }
  }
  int64_t next_a = 0, next_b = 0;
  for (const GotMessage& g : got) {
    const bool is_a = g.topic == "/a";
    const int64_t want = is_a ? next_a++ : next_b++;
    EXPECT_EQ(g.index, want);
    ASSERT_GE(g.data.size(), 6u);
    EXPECT_EQ(g.data[4], is_a ? 'a' : 'b');
    EXPECT_EQ(g.data[5], static_cast<uint8_t>(want));
    const double t = 100.0 + 0.1 * static_cast<double>(want) + (!is_a && want % 2 ? 0.05 : 0.0);
    EXPECT_NEAR(g.receive_s, t, 1e-9);
  }
}

class McapRoundTrip : public ::testing::TestWithParam<ChunkCompression> {};

TEST_P(McapRoundTrip, WrittenFileReadsBackThroughTheSummary) {
  const std::string path =
      WriteTwoTopics(FreshScratchFolder("round_trip") + "/two.mcap", GetParam());
  auto rec = OpenMcap(path);
  EXPECT_TRUE(rec->warnings().empty()) << rec->warnings().front();
  EXPECT_EQ(rec->compressions(), std::set<ChunkCompression>{GetParam()});
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[1].type, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(rec->topics()[1].count, 60);
  EXPECT_NEAR(rec->topics()[1].last_s, 100.0 + 5.9 + 0.05, 1e-9);
  ExpectTwoTopicsInOrder(CollectMessages(*rec, {"/a", "/b"}), 60);
  const fs::directory_iterator files(fs::path(path).parent_path());
  EXPECT_EQ(std::distance(fs::begin(files), fs::end(files)), 1);  // no temporary file left
}

TEST_P(McapRoundTrip, FileWithoutFooterIsWalkedWithAWarning) {
  const std::string path =
      WriteTwoTopics(FreshScratchFolder("no_footer") + "/two.mcap", GetParam());
  std::vector<uint8_t> bytes = ReadBytes(path);
  const uint64_t summary_start = mcap::GetU64(&bytes[bytes.size() - 8 - 20]);
  bytes.resize(summary_start - 13);  // cut before Data End: as a crashed recorder leaves it
  auto rec = OpenMcapBuffer("cut.mcap", bytes);
  ASSERT_FALSE(rec->warnings().empty());
  EXPECT_NE(rec->warnings()[0].find("no footer"), std::string::npos) << rec->warnings()[0];
  ExpectTwoTopicsInOrder(CollectMessages(*rec, {"/a", "/b"}), 60);
}

TEST_P(McapRoundTrip, CutAtEvery61stByteNeverCrashes) {
  const std::vector<uint8_t> bytes =
      ReadBytes(WriteTwoTopics(FreshScratchFolder("cuts") + "/two.mcap", GetParam(), 40, 200));
  int opened = 0, thrown = 0;
  size_t best = 0;
  for (size_t cut = 0; cut < bytes.size(); cut += 61) {
    try {
      auto rec = OpenMcapBuffer("cut", std::vector<uint8_t>(bytes.begin(), bytes.begin() + cut));
      ++opened;
      EXPECT_FALSE(rec->warnings().empty()) << cut;  // a cut file is never silently whole
      const std::vector<GotMessage> got = CollectMessages(*rec, {"/a", "/b"});
      for (size_t i = 1; i < got.size(); ++i) ASSERT_LE(got[i - 1].receive_s, got[i].receive_s);
      best = std::max(best, got.size());
    } catch (const io::InputError&) {
      ++thrown;  // too short to be MCAP (no header) or a topic not yet defined
    }
  }
  EXPECT_GT(opened, 10);
  EXPECT_GT(thrown, 0);
  EXPECT_LE(best, 80u);
  EXPECT_GT(best, 60u);  // late cuts keep most messages
}

INSTANTIATE_TEST_SUITE_P(Compressions, McapRoundTrip,
                         ::testing::Values(ChunkCompression::kNone, ChunkCompression::kZstd,
                                           ChunkCompression::kLz4));

// Sets the Data End and footer CRCs to 0 ("not available") so a chunk's own check is reached.
void ZeroFileCrcs(std::vector<uint8_t>* bytes) {
  const size_t footer = bytes->size() - 8 - 20;
  const uint64_t summary_start = mcap::GetU64(&(*bytes)[footer]);
  std::memset(&(*bytes)[summary_start - 4], 0, 4);
  std::memset(&(*bytes)[footer + 16], 0, 4);
}

constexpr uint64_t kFirstChunk = 36;  // magic 8 + Header record 9 + "ros2" 8 + "wallcal" 11

TEST(McapReaderTest, FlippedByteFailsTheDataCrcThenTheChunkCrc) {
  std::vector<uint8_t> bytes =
      ReadBytes(WriteTwoTopics(FreshScratchFolder("flip") + "/two.mcap", ChunkCompression::kNone));
  ASSERT_EQ(bytes[kFirstChunk], mcap::kChunk);
  bytes[kFirstChunk + 200] ^= 0x40;  // inside the first chunk's records
  std::string error = ThrownMessage<io::InputError>([&] { OpenMcapBuffer("flip.mcap", bytes); });
  EXPECT_NE(error.find("data section CRC mismatch"), std::string::npos) << error;
  ZeroFileCrcs(&bytes);
  error = ThrownMessage<io::InputError>([&] {
    auto rec = OpenMcapBuffer("flip.mcap", bytes);
    CollectMessages(*rec, {"/a"});
  });
  EXPECT_NE(error.find("flip.mcap:36: chunk CRC mismatch"), std::string::npos) << error;
}

TEST(McapReaderTest, FlippedSummaryByteFailsTheSummaryCrc) {
  std::vector<uint8_t> bytes = ReadBytes(
      WriteTwoTopics(FreshScratchFolder("flip_summary") + "/two.mcap", ChunkCompression::kZstd));
  const uint64_t summary_start = mcap::GetU64(&bytes[bytes.size() - 28]);
  bytes[summary_start + 20] ^= 1;
  const std::string error = ThrownMessage<io::InputError>([&] { OpenMcapBuffer("s.mcap", bytes); });
  EXPECT_NE(error.find("s.mcap:" + std::to_string(summary_start) + ": summary CRC mismatch"),
            std::string::npos)
      << error;
}

TEST(McapReaderTest, DamagedZstdChunkThrows) {
  std::vector<uint8_t> bytes =
      ReadBytes(WriteTwoTopics(FreshScratchFolder("zstd") + "/two.mcap", ChunkCompression::kZstd));
  ZeroFileCrcs(&bytes);
  // The chunk's records start after 8+8+8+4 + (4+4 "zstd") + 8 bytes of fields.
  const size_t records = kFirstChunk + 9 + 44;
  for (size_t i = records; i < records + 12; ++i) bytes[i] ^= 0xA5;
  const std::string error = ThrownMessage<io::InputError>([&] {
    auto rec = OpenMcapBuffer("z.mcap", bytes);
    CollectMessages(*rec, {"/a", "/b"});
  });
  EXPECT_NE(error.find("z.mcap:36: zstd chunk does not decompress"), std::string::npos) << error;
}

TEST(McapReaderTest, UnknownCompressionIsNamed) {
  std::vector<uint8_t> bytes = ReadBytes(
      WriteTwoTopics(FreshScratchFolder("brotli") + "/two.mcap", ChunkCompression::kZstd));
  ZeroFileCrcs(&bytes);
  const uint8_t zstd[] = {4, 0, 0, 0, 'z', 's', 't', 'd'};
  int patched = 0;
  for (size_t i = 0; i + sizeof zstd <= bytes.size(); ++i) {
    if (std::memcmp(&bytes[i], zstd, sizeof zstd) == 0) {
      std::memcpy(&bytes[i + 4], "brot", 4);
      ++patched;
    }
  }
  ASSERT_GT(patched, 1);  // chunks and chunk indexes
  const std::string error = ThrownMessage<io::InputError>([&] { OpenMcapBuffer("b.mcap", bytes); });
  EXPECT_NE(error.find("unknown chunk compression 'brot'"), std::string::npos) << error;
}

// A chunk index whose chunk starts past the summary's start (found by fuzzing: the unsigned
// difference summary_start - start wrapped, and a 17 TB read was asked for). The index is
// distrusted and the data section walked instead.
TEST(McapReaderTest, ChunkIndexPointingPastTheSummaryIsNotFollowed) {
  std::vector<uint8_t> bytes = ReadBytes(
      WriteTwoTopics(FreshScratchFolder("index_past") + "/two.mcap", ChunkCompression::kNone));
  ZeroFileCrcs(&bytes);
  const uint64_t summary_start = mcap::GetU64(&bytes[bytes.size() - 28]);
  size_t pos = summary_start, patched = 0;
  while (pos + mcap::kRecordHeaderSize <= bytes.size() - 28 - mcap::kRecordHeaderSize) {
    const uint64_t len = mcap::GetU64(&bytes[pos + 1]);
    if (bytes[pos] == mcap::kChunkIndex && patched == 0) {
      const size_t content = pos + mcap::kRecordHeaderSize;
      const uint64_t start = summary_start + 10, length = (uint64_t{1} << 44) + 110;
      for (int i = 0; i < 8; ++i) bytes[content + 16 + i] = static_cast<uint8_t>(start >> (8 * i));
      for (int i = 0; i < 8; ++i) bytes[content + 24 + i] = static_cast<uint8_t>(length >> (8 * i));
      ++patched;
    }
    pos += mcap::kRecordHeaderSize + len;
  }
  ASSERT_EQ(patched, 1u);
  auto rec = OpenMcapBuffer("past.mcap", bytes);
  ASSERT_FALSE(rec->warnings().empty());
  EXPECT_NE(rec->warnings()[0].find("points outside the data section"), std::string::npos)
      << rec->warnings()[0];
  ExpectTwoTopicsInOrder(CollectMessages(*rec, {"/a", "/b"}), 60);
}

TEST(McapReaderTest, UnknownTopicListsTheTopicsPresent) {
  auto rec =
      OpenMcap(WriteTwoTopics(FreshScratchFolder("unknown") + "/two.mcap", ChunkCompression::kLz4));
  const std::string error =
      ThrownMessage<io::InputError>([&] { CollectMessages(*rec, {"/scan"}); });
  testing_support::ExpectContains(error, {"no topic /scan", "topics: /a, /b"});
}

// A hand-built file without chunks or summary: loose messages, one channel in JSON.
std::vector<uint8_t> LooseFile() {
  mcap::Out out;
  out.Raw(mcap::kMagic, 8);
  size_t at = out.Begin(mcap::kHeader);
  out.Str("ros2");
  out.Str("hand");
  out.End(at);
  at = out.Begin(mcap::kSchema);
  out.U16(1);
  out.Str("std_msgs/msg/String");
  out.Str("ros2msg");
  out.Str("string data");
  out.End(at);
  for (uint16_t id : {1, 2}) {
    at = out.Begin(mcap::kChannel);
    out.U16(id);
    out.U16(1);
    out.Str(id == 1 ? "/cdr" : "/json");
    out.Str(id == 1 ? "cdr" : "json");
    out.U32(0);
    out.End(at);
  }
  const uint64_t times[] = {30, 10, 20};  // not in order in the file
  for (int i = 0; i < 3; ++i) {
    for (uint16_t id : {1, 2}) {
      at = out.Begin(mcap::kMessage);
      out.U16(id);
      out.U32(0);
      out.U64(times[i] * 1000000000ull);
      out.U64(0);
      out.U8(static_cast<uint8_t>(i));
      out.End(at);
    }
  }
  at = out.Begin(mcap::kDataEnd);
  out.U32(0);
  out.End(at);
  out.U8(mcap::kFooter);
  out.U64(20);
  out.U64(0);
  out.U64(0);
  out.U32(0);
  out.Raw(mcap::kMagic, 8);
  return out.bytes;
}

TEST(McapReaderTest, LooseMessagesWithoutSummaryComeOutInTimeOrder) {
  auto rec = OpenMcapBuffer("loose.mcap", LooseFile());
  ASSERT_EQ(rec->warnings().size(), 1u);
  EXPECT_NE(rec->warnings()[0].find("no summary section"), std::string::npos);
  ASSERT_EQ(rec->topics().size(), 2u);
  EXPECT_EQ(rec->topics()[1].encoding, "json");
  const std::vector<GotMessage> got = CollectMessages(*rec, {"/cdr"});
  ASSERT_EQ(got.size(), 3u);
  EXPECT_DOUBLE_EQ(got[0].receive_s, 10.0);
  EXPECT_EQ(got[0].data, std::vector<uint8_t>{1});
  EXPECT_DOUBLE_EQ(got[2].receive_s, 30.0);
  EXPECT_EQ(got[2].data, std::vector<uint8_t>{0});
}

TEST(McapReaderTest, NonCdrTopicIsListedButNotRead) {
  auto rec = OpenMcapBuffer("loose.mcap", LooseFile());
  const std::string error =
      ThrownMessage<io::InputError>([&] { CollectMessages(*rec, {"/json"}); });
  EXPECT_NE(error.find("topic /json is encoded as 'json'"), std::string::npos) << error;
}

TEST(McapReaderTest, NotMcapThrows) {
  const std::string error = ThrownMessage<io::InputError>(
      [] { OpenMcapBuffer("x.bag", std::vector<uint8_t>(100, 'x')); });
  EXPECT_NE(error.find("x.bag:0: not an MCAP file"), std::string::npos) << error;
  EXPECT_NE(ThrownMessage<io::InputError>([] { OpenMcap("/nonexistent/file.mcap"); }), "");
}

TEST(McapWriterTest, WithoutCloseLeavesNoFile) {
  const std::string dir = FreshScratchFolder("abandon");
  {
    McapWriter w(dir + "/x.mcap", ChunkCompression::kZstd);
    const uint16_t c = w.AddChannel("/a", "std_msgs/msg/String", "");
    w.Write(c, 1.0, 1.0, std::vector<uint8_t>{0, 1, 0, 0});
  }
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace wallcal::recording
