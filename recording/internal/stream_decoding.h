// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the whole reads of a session's streams (recording_streams.cc) and their reads on as a
// recording grows (ScanTail, PoseTail) share: the checks that name a message that does not
// decode, the stamp a stream takes, the topics a tail has met seen as a Recording, and the
// decoding of GNSS, heading and attitude messages into the records of io/types.h. Private to
// recording/.

#include <cstdint>
#include <optional>
#include <set>
#include <string>

#include "io/text/nmea_reader.h"
#include "io/types.h"
#include "recording/attitude_stream.h"
#include "recording/recording.h"
#include "recording/recording_streams.h"
#include "recording/recording_tail.h"
#include "recording/ros/ros_messages.h"

namespace wallcal::recording {

// A message's line in the records: its 1-based index on its topic.
int LineOf(int64_t index);
// "topic /fix message 12", for messages.
std::string Describe(const RecordedMessage& m);
// Throws a decoder's failure as an io::InputError naming the file, topic, message and byte.
void Require(const DecodeResult& result, const Recording& recording, const RecordedMessage& m,
             RosType type);
// header.stamp, or the receive time with `stamp: receive`.
double StampOf(const RosHeader& header, const RecordedMessage& m, io::StampSource stamp);

// The topics a RecordingTail has met, seen as a Recording (for CheckTopic and messages).
class TailTopics : public Recording {
 public:
  explicit TailTopics(const RecordingTail& tail);
  RecordingFormat format() const override { return format_; }
  void ForEach(const std::set<std::string>&, const MessageFn&) override {}

 private:
  RecordingFormat format_;
};

// One session stream on a recording topic.
struct TopicStream {
  std::string topic;
  io::StampSource stamp = io::StampSource::kHeader;
  RosType type = RosType::kOther;  // kOther until checked against the recording's topics
  double time_offset_s = 0.0;       // added to every stamp (the attitude stream's)
};

// A recording's GNSS, heading and/or attitude messages decoded one at a time into the logs ReadPoseLogs
// returns, keeping what it decoded: handed every message of a whole read, or those of each
// read on in turn, it gives the same logs.
class PoseDecoder {
 public:
  // The streams to decode (null: that stream is not read). `path` names the recording in the
  // logs of nmea_msgs/Sentence topics and in warnings.
  PoseDecoder(std::string path, const TopicStream* gnss, const TopicStream* heading,
              double max_sigma_m, const TopicStream* attitude = nullptr);

  // The topics of the streams read.
  std::set<std::string> topics() const;
  // Checks every stream's topic against `recording` (CheckTopic: throws io::InputError for a
  // topic it lacks or of another type) and takes its type.
  void CheckTopics(const Recording& recording);
  // Decodes one message on a stream's topic; a stream not checked yet is checked against
  // `recording` first. Throws io::InputError naming the message when it does not decode.
  void Take(const RecordedMessage& m, const Recording& recording);
  // The logs of the streams read so far into *out (the others left as they are; the attitude
  // stream as recording/attitude_stream.h gives it, its time offset added), and the warning for
  // a NavSatFix topic without position covariance. Throws io::InputError for an Imu attitude
  // topic whose every message is without orientation (ImuAttitudeStream::Finish).
  void AddTo(PoseLogs* out) const;

 private:
  struct Stream {
    bool read = false;
    TopicStream spec;
    io::NmeaLog log;  // NavSatFix, QuaternionStamped, Imu
    std::optional<io::NmeaLineFeed> sentences;  // nmea_msgs/Sentence
    ImuAttitudeStream imu;                      // the attitude stream's sensor_msgs/Imu
    double last_s = 0.0;  // the last stamp taken ("time not increasing")
    bool any = false;     // a sample taken
  };
  void Check(Stream* stream, const Recording& recording, const char* key);
  void TakeFix(const RecordedMessage& m, const Recording& recording);
  void TakeHeading(const RecordedMessage& m, const Recording& recording);
  void TakeAttitude(const RecordedMessage& m, const Recording& recording);

  std::string path_;
  double max_sigma_m_;
  Stream gnss_, heading_, attitude_;
  bool gnss_without_covariance_ = false;
  NavSatFixMsg fix_msg_;
  NmeaSentenceMsg sentence_msg_;
  QuaternionMsg quaternion_msg_;
};

}  // namespace wallcal::recording
