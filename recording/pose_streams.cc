// SPDX-License-Identifier: Apache-2.0
// The GNSS, heading and attitude streams of a recording, decoded message by message
// (PoseDecoder): for a whole read (ReadPoseLogs) and for a recording read on as it grows
// (PoseTail, GNSS and heading only), with the same state carried from one message to the next
// either way.

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include "recording/internal/stream_decoding.h"
#include "recording/recording_streams.h"

namespace wallcal::recording {
namespace {

// An nmea_msgs/Sentence as a logger-stamped line for the NMEA reader (line ends in it made
// blanks, so that one message stays one line).
std::string SentenceLine(const NmeaSentenceMsg& msg, double stamp_s) {
  std::string sentence = msg.sentence;
  for (char& c : sentence) {
    if (c == '\n' || c == '\r') c = ' ';
  }
  // A negative or non-finite stamp cannot be a logger prefix: the line is then counted by the
  // NMEA reader as it would count it in a text log.
  if (!std::isfinite(stamp_s) || stamp_s < 0) return sentence;
  char prefix[48];
  std::snprintf(prefix, sizeof(prefix), "%.9f ", stamp_s);
  return prefix + sentence;
}

}  // namespace

PoseDecoder::PoseDecoder(std::string path, const TopicStream* gnss, const TopicStream* heading,
                         double max_sigma_m, const TopicStream* attitude)
    : path_(std::move(path)), max_sigma_m_(max_sigma_m) {
  if (gnss != nullptr) {
    gnss_.read = true;
    gnss_.spec = *gnss;
  }
  if (heading != nullptr) {
    heading_.read = true;
    heading_.spec = *heading;
  }
  if (attitude != nullptr) {
    attitude_.read = true;
    attitude_.spec = *attitude;
  }
}

std::set<std::string> PoseDecoder::topics() const {
  std::set<std::string> names;
  if (gnss_.read) names.insert(gnss_.spec.topic);
  if (heading_.read) names.insert(heading_.spec.topic);
  if (attitude_.read) names.insert(attitude_.spec.topic);
  return names;
}

void PoseDecoder::Check(Stream* stream, const Recording& recording, const char* key) {
  if (stream->spec.type != RosType::kOther) return;
  stream->spec.type = CheckTopic(recording, stream->spec.topic,
                                 stream == &gnss_       ? AcceptedGnssTypes()
                                 : stream == &heading_ ? AcceptedHeadingTypes()
                                                       : AcceptedAttitudeTypes(),
                                 key);
  if (stream->spec.type == RosType::kNmeaSentence) {
    stream->sentences.emplace(path_ + " " + stream->spec.topic);
  }
}

void PoseDecoder::CheckTopics(const Recording& recording) {
  if (gnss_.read) Check(&gnss_, recording, "gnss.topic");
  if (heading_.read) Check(&heading_, recording, "heading.topic");
  if (attitude_.read) Check(&attitude_, recording, "attitude.topic");
}

void PoseDecoder::Take(const RecordedMessage& m, const Recording& recording) {
  const bool for_gnss = gnss_.read && m.topic->name == gnss_.spec.topic;
  const bool for_heading = heading_.read && m.topic->name == heading_.spec.topic;
  const bool for_attitude = attitude_.read && m.topic->name == attitude_.spec.topic;
  if (for_gnss) Check(&gnss_, recording, "gnss.topic");
  if (for_heading) Check(&heading_, recording, "heading.topic");
  if (for_attitude) Check(&attitude_, recording, "attitude.topic");
  // One topic may serve several streams (GGA and HDT sentences, an Imu for heading and
  // attitude): each stream reads every message of it.
  bool sentence_decoded = false;
  for (Stream* stream : {for_gnss ? &gnss_ : nullptr, for_heading ? &heading_ : nullptr,
                         for_attitude ? &attitude_ : nullptr}) {
    if (stream == nullptr || stream->spec.type != RosType::kNmeaSentence) continue;
    if (!sentence_decoded) {
      Require(DecodeNmeaSentence(m.data, m.size, m.wire, &sentence_msg_), recording, m,
              RosType::kNmeaSentence);
      sentence_decoded = true;
    }
    stream->sentences->Add(
        SentenceLine(sentence_msg_, StampOf(sentence_msg_.header, m, stream->spec.stamp)));
  }
  if (for_gnss && gnss_.spec.type != RosType::kNmeaSentence) TakeFix(m, recording);
  if (for_heading && heading_.spec.type != RosType::kNmeaSentence) TakeHeading(m, recording);
  if (for_attitude && attitude_.spec.type != RosType::kNmeaSentence) TakeAttitude(m, recording);
}

void PoseDecoder::TakeFix(const RecordedMessage& m, const Recording& recording) {
  Require(DecodeNavSatFix(m.data, m.size, m.wire, &fix_msg_), recording, m, gnss_.spec.type);
  io::NmeaLog& log = gnss_.log;
  ++log.lines_read;
  const double stamp_s = StampOf(fix_msg_.header, m, gnss_.spec.stamp);
  const io::GnssFix fix = FixFromNavSatFix(fix_msg_, stamp_s, max_sigma_m_, LineOf(m.index));
  if (fix.quality == 0) {
    log.skipped.Add("NavSatFix without a fix (status -1)", fix.line);
    return;
  }
  if (fix_msg_.position_covariance_type == 0) gnss_without_covariance_ = true;
  ++log.fixes_by_quality[fix.quality];
  if (!(stamp_s > gnss_.last_s)) {
    log.skipped.Add("time not increasing", fix.line);
    return;
  }
  gnss_.last_s = stamp_s;
  log.fixes.push_back(fix);
}

void PoseDecoder::TakeHeading(const RecordedMessage& m, const Recording& recording) {
  const RosType type = heading_.spec.type;
  QuaternionMsg& q = quaternion_msg_;
  Require(type == RosType::kImu ? DecodeImu(m.data, m.size, m.wire, &q)
                                : DecodeQuaternionStamped(m.data, m.size, m.wire, &q),
          recording, m, type);
  io::NmeaLog& log = heading_.log;
  ++log.lines_read;
  const int line = LineOf(m.index);
  if (type == RosType::kImu && q.orientation_covariance[0] == -1.0) {
    log.skipped.Add("Imu without orientation (covariance[0] = -1)", line);
    return;
  }
  const double norm = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w);
  if (!std::isfinite(norm) || norm < 1e-6) {
    log.skipped.Add("quaternion not finite or zero", line);
    return;
  }
  const double stamp_s = StampOf(q.header, m, heading_.spec.stamp);
  if (!(stamp_s > heading_.last_s)) {
    log.skipped.Add("time not increasing", line);
    return;
  }
  heading_.last_s = stamp_s;
  io::HeadingSample sample;
  sample.stamp_s = stamp_s;
  sample.heading_rad = HeadingFromEnuQuaternion(q.x, q.y, q.z, q.w);
  sample.line = line;
  log.headings.push_back(sample);
}

void PoseDecoder::TakeAttitude(const RecordedMessage& m, const Recording& recording) {
  QuaternionMsg& q = quaternion_msg_;
  Require(DecodeImu(m.data, m.size, m.wire, &q), recording, m, attitude_.spec.type);
  attitude_.imu.Add(q, StampOf(q.header, m, attitude_.spec.stamp), LineOf(m.index));
}

void PoseDecoder::AddTo(PoseLogs* out) const {
  if (gnss_.read) out->gnss = gnss_.sentences ? gnss_.sentences->Log() : gnss_.log;
  if (heading_.read) out->headings = heading_.sentences ? heading_.sentences->Log() : heading_.log;
  if (attitude_.read) {
    out->attitudes = AttitudeStreamOf(attitude_.sentences
                                          ? attitude_.sentences->Log()
                                          : attitude_.imu.Finish(path_, attitude_.spec.topic),
                                      attitude_.spec.time_offset_s);
  }
  if (gnss_without_covariance_) {
    out->warnings.push_back(path_ + ": " + gnss_.spec.topic +
                            ": NavSatFix without position covariance: RTK float fixes cannot be "
                            "told apart from fixed ones (all fixes with status >= 0 are used)");
  }
}

// One recording of the pose streams, read on.
struct PoseTail::Source {
  std::string path;
  std::optional<TopicStream> gnss, heading;
  double max_sigma_m = 0.0;
  std::unique_ptr<RecordingTail> tail;
  std::unique_ptr<PoseDecoder> decoder;
  TailRead last;

  void NewDecoder() {
    decoder = std::make_unique<PoseDecoder>(path, gnss ? &*gnss : nullptr,
                                            heading ? &*heading : nullptr, max_sigma_m);
  }
};

PoseTail::PoseTail(const io::SessionSpec& spec, bool gnss, bool heading) {
  const TopicStream gnss_stream{spec.gnss_topic, spec.gnss_stamp, RosType::kOther, 0.0};
  const TopicStream heading_stream{spec.heading_topic, spec.heading_stamp, RosType::kOther,
                                   0.0};
  const auto add = [&](const std::string& path) {
    sources_.push_back(std::make_unique<Source>());
    Source& source = *sources_.back();
    source.path = path;
    source.max_sigma_m = spec.gnss_max_sigma_m;
    source.tail = OpenRecordingTail(path);
    if (!source.tail) {
      throw io::InputError(io::Where(path, 0,
                                     "not a recording; expected a ROS 1 bag, an MCAP file, a "
                                     ".db3 file or a rosbag2 folder"));
    }
    return &source;
  };
  if (gnss) add(spec.gnss_log)->gnss = gnss_stream;
  if (heading) {
    if (gnss && spec.heading_log == spec.gnss_log) {
      sources_.front()->heading = heading_stream;  // both topics in one pass
      heading_source_ = 0;
    } else {
      add(spec.heading_log)->heading = heading_stream;
      heading_source_ = sources_.size() - 1;
    }
  }
  for (const std::unique_ptr<Source>& source : sources_) source->NewDecoder();
}

PoseTail::~PoseTail() = default;

const TailRead& PoseTail::gnss_read() const {
  static const TailRead kNone;
  return !sources_.empty() && sources_.front()->gnss ? sources_.front()->last : kNone;
}

const TailRead& PoseTail::heading_read() const {
  static const TailRead kNone;
  return heading_source_ < sources_.size() ? sources_[heading_source_]->last : kNone;
}

PoseLogs PoseTail::ReadOn() {
  // The messages of one read, held until the read says whether it restarted (then the decoder
  // starts afresh before it takes them).
  struct Held {
    RecordedMessage message;
    std::vector<uint8_t> data;
  };
  PoseLogs logs;
  for (const std::unique_ptr<Source>& source : sources_) {
    std::vector<Held> held;
    source->last = source->tail->ReadOn(source->decoder->topics(), [&](const RecordedMessage& m) {
      held.push_back({m, std::vector<uint8_t>(m.data, m.data + m.size)});
    });
    if (source->last.restarted) source->NewDecoder();
    const TailTopics topics(*source->tail);
    try {
      for (Held& h : held) {
        h.message.data = h.data.data();
        source->decoder->Take(h.message, topics);
      }
    } catch (const io::InputError&) {
      // A message that does not decode: the recording is read from its start next time, so
      // that every read names it, as a whole read does.
      source->tail = OpenRecordingTail(source->path);
      source->NewDecoder();
      throw;
    }
    source->decoder->CheckTopics(topics);  // as a whole read: a topic not met yet is named
    source->decoder->AddTo(&logs);
  }
  return logs;
}

}  // namespace wallcal::recording
