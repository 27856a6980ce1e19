// SPDX-License-Identifier: Apache-2.0
// inspect on a robot recording: every topic's type, count, rate, span and gaps, the statistics
// of the supported types, the suggested session.yaml, and the dumps of one topic.
#include <algorithm>
#include <cctype>
#include <climits>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include "common/angles.h"
#include "io/config/session_reader.h"
#include "io/scanner_geometry.h"
#include "io/version.h"
#include "pipeline/config_dirs.h"
#include "preflight/internal/inspect_internal.h"
#include "recording/attitude_stream.h"
#include "recording/recording.h"
#include "recording/recording_streams.h"

namespace wallcal::preflight {

using namespace internal;  // the helpers shared by the inspect files

namespace {

namespace fs = std::filesystem;

// What one pass over a recording learns about each topic.
struct TopicSummary {
  const recording::TopicInfo* info = nullptr;
  recording::RosType type = recording::RosType::kOther;
  std::vector<double> receive_s;
  std::vector<int> lines;
  // LaserScan
  std::map<size_t, int64_t> beams;
  int64_t readings = 0, in_range = 0;
  float first_increment_rad = 0, first_range_max_m = 0, first_angle_min_rad = 0;
  // NavSatFix
  std::map<int, int64_t> status;
  int64_t fixes_sigma_ok = 0, fixes_no_covariance = 0;
  // headings (QuaternionStamped, Imu)
  std::vector<double> headings_rad;
  // Imu: the attitude its orientation gives (messages without orientation are not in it)
  io::NmeaLog attitudes;
  int64_t imu_with_orientation = 0;
  // nmea_msgs/Sentence: sentence types ("GGA") -> count
  std::map<std::string, int64_t> sentences;
  int64_t undecodable = 0;
};

std::map<std::string, TopicSummary> Summarise(recording::Recording& recording) {
  std::map<std::string, TopicSummary> topics;
  std::set<std::string> names;
  for (const recording::TopicInfo& info : recording.topics()) {
    TopicSummary& t = topics[info.name];
    t.info = &info;
    t.type = recording::RosTypeFromName(info.type);
    names.insert(info.name);
  }
  recording::LaserScanMsg scan;
  recording::NavSatFixMsg fix;
  recording::QuaternionMsg quaternion;
  recording::NmeaSentenceMsg sentence;
  recording.ForEach(names, [&](const recording::RecordedMessage& m) {
    TopicSummary& t = topics[m.topic->name];
    t.receive_s.push_back(m.receive_s);
    t.lines.push_back(static_cast<int>(std::min<int64_t>(m.index + 1, INT_MAX)));
    switch (t.type) {
      case recording::RosType::kLaserScan:
        if (!recording::DecodeLaserScan(m.data, m.size, m.wire, &scan).ok()) {
          ++t.undecodable;
          break;
        }
        if (t.beams.empty()) {
          t.first_increment_rad = scan.angle_increment_rad;
          t.first_range_max_m = scan.range_max_m;
          t.first_angle_min_rad = scan.angle_min_rad;
        }
        ++t.beams[scan.ranges_m.size()];
        for (float r : scan.ranges_m) {
          ++t.readings;
          t.in_range += std::isfinite(r) && r >= scan.range_min_m && r < scan.range_max_m;
        }
        break;
      case recording::RosType::kNavSatFix:
        if (!recording::DecodeNavSatFix(m.data, m.size, m.wire, &fix).ok()) {
          ++t.undecodable;
          break;
        }
        ++t.status[fix.status];
        t.fixes_no_covariance += fix.position_covariance_type == 0;
        t.fixes_sigma_ok +=
            recording::FixFromNavSatFix(fix, 0.0, io::kDefaultGnssMaxSigmaM, 1).quality == 4 &&
            fix.position_covariance_type != 0;
        break;
      case recording::RosType::kQuaternionStamped:
      case recording::RosType::kImu: {
        const bool ok =
            t.type == recording::RosType::kImu
                ? recording::DecodeImu(m.data, m.size, m.wire, &quaternion).ok()
                : recording::DecodeQuaternionStamped(m.data, m.size, m.wire, &quaternion).ok();
        if (!ok) {
          ++t.undecodable;
        } else if (quaternion.orientation_covariance[0] != -1.0) {
          t.headings_rad.push_back(recording::HeadingFromEnuQuaternion(quaternion.x, quaternion.y,
                                                                       quaternion.z, quaternion.w));
        }
        if (ok && t.type == recording::RosType::kImu) {
          io::AttitudeSample sample;
          const recording::ImuAttitude outcome = recording::AttitudeFromImu(quaternion, &sample);
          t.imu_with_orientation += outcome != recording::ImuAttitude::kNoOrientation;
          if (outcome == recording::ImuAttitude::kSample) {
            sample.stamp_s = quaternion.header.stamp_s;
            sample.line = t.lines.back();
            t.attitudes.attitudes.push_back(sample);
          } else {
            t.attitudes.skipped.Add(recording::ImuAttitudeSkipReason(outcome), t.lines.back());
          }
        }
        break;
      }
      case recording::RosType::kNmeaSentence:
        if (!recording::DecodeNmeaSentence(m.data, m.size, m.wire, &sentence).ok()) {
          ++t.undecodable;
        } else if (sentence.sentence.size() > 6 && sentence.sentence[0] == '$') {
          ++t.sentences[sentence.sentence.substr(3, 3)];
        }
        break;
      case recording::RosType::kOther:
        break;
    }
  });
  return topics;
}

bool HasSentence(const TopicSummary& t, const char* type) {
  const auto it = t.sentences.find(type);
  return it != t.sentences.end() && it->second > 0;
}

// Topics that fit a role, best first: by type preference, then message count, then name.
std::vector<const TopicSummary*> Candidates(const std::map<std::string, TopicSummary>& topics,
                                            const std::vector<recording::RosType>& preference,
                                            const char* sentence_type) {
  std::vector<const TopicSummary*> out;
  for (const auto& [name, t] : topics) {
    const auto rank = std::find(preference.begin(), preference.end(), t.type);
    if (rank == preference.end() || t.info->count == 0) continue;
    if (t.type == recording::RosType::kNmeaSentence && !HasSentence(t, sentence_type)) continue;
    out.push_back(&t);
  }
  auto rank_of = [&](const TopicSummary* t) {
    return std::find(preference.begin(), preference.end(), t->type) - preference.begin();
  };
  std::stable_sort(out.begin(), out.end(), [&](const TopicSummary* a, const TopicSummary* b) {
    if (rank_of(a) != rank_of(b)) return rank_of(a) < rank_of(b);
    return a->info->count > b->info->count;
  });
  return out;
}

std::string Why(const std::vector<const TopicSummary*>& candidates, const char* role) {
  if (candidates.size() < 2) return "";
  std::ostringstream out;
  out << "  # " << candidates.size() << " topics fit the " << role << ": ";
  for (size_t i = 0; i < candidates.size(); ++i) {
    out << (i ? ", " : "") << candidates[i]->info->name << " (" << candidates[i]->info->type << ", "
        << candidates[i]->info->count << " messages)";
  }
  out << "; chosen: the preferred type, then the most messages\n";
  return out.str();
}

// The preset of the scanner family that recorded the scans (io/scanner_geometry.h): one whose
// geometry is the scans' if there is one, else the first whose family limits hold them (then
// `from_data` says what the scans carry themselves); "" when none fits.
std::string MatchingPreset(const TopicSummary& scans, std::string* from_data) {
  if (scans.beams.empty()) return "";
  std::string family;
  for (const std::string& dir : pipeline::PresetDirs()) {
    std::error_code error;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, error)) {
      if (entry.path().extension() == ".yaml") files.push_back(entry.path());
    }
    std::sort(files.begin(), files.end());  // the same answer whatever the folder's order
    for (const fs::path& file : files) {
      try {
        const io::ScannerPreset preset = io::ReadScannerPreset(file.string());
        const io::GeometryCheck check = io::CheckScanGeometry(
            static_cast<int64_t>(scans.beams.begin()->first), scans.first_increment_rad,
            scans.first_range_max_m, preset);
        if (check.fit == io::GeometryFit::kAsPreset) {
          from_data->clear();
          return preset.name;
        }
        if (check.fit == io::GeometryFit::kFromData && family.empty()) {
          family = preset.name;
          *from_data = check.what;
        }
      } catch (const io::InputError&) {
        continue;  // a broken preset file is calibrate's business, not the suggestion's
      }
    }
  }
  return family;
}

// A scanner id (and frame name) from a scan topic: "/front_left/scan" -> "front_left",
// "/scan_rear" -> "scan_rear"; letters, digits and '_' only, unique among *taken.
std::string SuggestedScannerId(const std::string& topic, std::set<std::string>* taken) {
  std::string name = topic;
  const std::string tail = "/scan";
  if (name.size() > tail.size() && name.compare(name.size() - tail.size(), tail.size(), tail) == 0) {
    name.resize(name.size() - tail.size());
  }
  std::string id;
  for (const char c : name) {
    const bool plain = std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_';
    if (plain) {
      id += c;
    } else if (!id.empty() && id.back() != '_') {
      id += '_';
    }
  }
  while (!id.empty() && id.back() == '_') id.pop_back();
  if (id.empty()) id = "scanner";
  std::string unique = id;
  for (int k = 2; !taken->insert(unique).second; ++k) unique = id + "_" + std::to_string(k);
  return unique;
}

std::string FormatTopic(const TopicSummary& t, const std::string& path) {
  std::ostringstream out;
  StreamStats stats = ComputeStreamStats(t.info->name + " [" + t.info->type + "]", path,
                                         t.receive_s, t.lines);
  out << FormatStream(stats);
  if (t.undecodable > 0) out << "    damaged   " << t.undecodable << " messages do not decode\n";
  if (!t.beams.empty()) {
    out << "    beams    ";
    for (const auto& [beams, count] : t.beams) out << " " << beams << " beams: " << count << " scans;";
    out << "\n    geometry  first scan: angle_min " << Fmt("%.3f", t.first_angle_min_rad * kRadToDeg)
        << "°, increment " << Fmt("%.4f", t.first_increment_rad * kRadToDeg) << "°, range_max "
        << Fmt("%.2f", t.first_range_max_m) << " m\n";
    out << "    readings  " << t.in_range << " of " << t.readings
        << " in [range_min, range_max) (the rest: no return)\n";
  }
  if (!t.status.empty()) {
    out << "    status   ";
    for (const auto& [status, count] : t.status) out << " " << status << ": " << count << ";";
    out << "\n    accepted  " << t.fixes_sigma_ok << " fixes with horizontal σ <= "
        << Fmt("%.3f", io::kDefaultGnssMaxSigmaM) << " m (gnss.max_sigma_m default)";
    if (t.fixes_no_covariance > 0) {
      out << "; " << t.fixes_no_covariance << " without covariance (float cannot be told apart)";
    }
    out << "\n";
  }
  if (!t.headings_rad.empty()) {
    out << "    headings   " << HistogramAxis() << "\n";
    out << "    (10° bins) " << Histogram(t.headings_rad) << "\n";
  }
  if (t.type == recording::RosType::kImu) {
    // The attitude the orientation gives (the messages' time statistics are above).
    const AttitudeSummary attitude = SummariseAttitude(path, t.info->name, t.attitudes);
    if (attitude.stats.records > 0) {
      out << "    attitude  " << attitude.stats.records << " of " << t.receive_s.size()
          << " messages give roll and pitch\n";
      out << FormatAttitudeValues(attitude);
    }
    if (!t.attitudes.skipped.by_reason.empty()) {
      out << "    skipped   " << DescribeSkips(t.attitudes.skipped) << " (as attitude)\n";
    }
  }
  if (!t.sentences.empty()) {
    out << "    sentences";
    for (const auto& [type, count] : t.sentences) out << " " << type << ": " << count << ";";
    out << "\n";
  }
  return out.str();
}

// The recording does not say where a scanner sits: the lines are comments to fill in.
std::string MountGuessLines(const std::string& indent) {
  return indent +
         "# mount_guess: {x: 0.0, y: 0.0, yaw_deg: 0}  # CHECK: where it sits and points\n" +
         indent + "#   on the vehicle, to a tape measure's 0.1 m and 10 deg: a scanner turned\n" +
         indent + "#   from straight ahead finds the wall in no scan without it\n" + indent +
         "# z_m: 0.0  # CHECK: the scanner's height relative to the antenna (m): tape from\n" +
         indent + "#   the antenna's reference point to the scanner's optical centre, negative\n" +
         indent + "#   when the scanner is below the antenna\n";
}

}  // namespace

std::string InspectRecording(const std::string& path) {
  std::unique_ptr<recording::Recording> recording = recording::OpenRecording(path);
  const std::map<std::string, TopicSummary> topics = Summarise(*recording);
  std::ostringstream out;
  out << "wallcal inspect " << io::kToolVersion << ": " << path << " ("
      << recording::RecordingFormatName(recording->format()) << ", " << topics.size()
      << " topics)\n";
  for (const auto& [name, t] : topics) out << FormatTopic(t, path);
  for (const std::string& w : recording->warnings()) out << "  warning: " << w << "\n";
  out << "  (run with --suggest-session for a session.yaml naming the topics)\n";
  return out.str();
}

std::string SuggestSession(const std::string& path) {
  std::unique_ptr<recording::Recording> recording = recording::OpenRecording(path);
  const std::map<std::string, TopicSummary> topics = Summarise(*recording);
  const auto scans = Candidates(topics, recording::AcceptedScanTypes(), "");
  const auto gnss = Candidates(
      topics, {recording::RosType::kNavSatFix, recording::RosType::kNmeaSentence}, "GGA");
  auto heading = Candidates(topics,
                            {recording::RosType::kQuaternionStamped, recording::RosType::kImu,
                             recording::RosType::kNmeaSentence},
                            "HDT");
  if (heading.empty()) heading = Candidates(topics, {recording::RosType::kNmeaSentence}, "THS");
  const std::string log = fs::path(path).filename().string();
  auto topic_line = [](const std::vector<const TopicSummary*>& c, const char* type) {
    return c.empty() ? std::string("  topic: NONE  # no ") + type + " topic in the recording\n"
                     : "  topic: " + c.front()->info->name + "  # " + c.front()->info->type + ", " +
                           std::to_string(c.front()->info->count) + " messages\n";
  };
  std::ostringstream out;
  out << "# session.yaml suggested by wallcal inspect " << io::kToolVersion << " from " << log
      << "\n# Put it next to the recording, check every line marked CHECK, add the survey.\n";
  out << "name: " << fs::path(path).stem().string() << "\n";
  const auto model_line = [](const TopicSummary& topic) {
    std::string from_data;
    const std::string preset = MatchingPreset(topic, &from_data);
    return preset.empty()      ? std::string("sick_lms291  # CHECK: no preset matches the scans")
           : from_data.empty() ? preset + "  # matches the beam count and increment"
                               : preset + "  # its family; from the data: " + from_data;
  };
  if (scans.size() >= 2) {
    // Several scan topics: every one is proposed as a scanner of its own (scanners:), its id
    // (and frame) made from the topic name.
    out << "scanners:  # CHECK: one entry per scanner on the vehicle; remove the others\n";
    std::set<std::string> ids;
    for (const TopicSummary* topic : scans) {
      out << "  - id: " << SuggestedScannerId(topic->info->name, &ids) << "\n";
      out << "    model: " << model_line(*topic) << "\n";
      out << "    log: " << log << "\n";
      out << "    topic: " << topic->info->name << "  # " << topic->info->type << ", "
          << topic->info->count << " messages\n";
      out << "    stamp: header\n    time_offset_s: 0\n" << MountGuessLines("    ");
    }
  } else {
    out << "scanner:\n";
    out << "  model: "
        << (scans.empty() ? std::string("sick_lms291  # CHECK: no preset matches the scans")
                          : model_line(*scans.front()))
        << "\n";
    out << "  log: " << log << "\n"
        << topic_line(scans, "sensor_msgs/LaserScan") << Why(scans, "scanner");
    out << "  stamp: header  # or receive: the recorder's time\n  time_offset_s: 0\n"
        << MountGuessLines("  ");
  }
  out << "gnss:\n  log: " << log << "\n" << topic_line(gnss, "sensor_msgs/NavSatFix or GGA sentence")
      << Why(gnss, "GNSS");
  if (!gnss.empty() && gnss.front()->type == recording::RosType::kNavSatFix) {
    out << "  max_sigma_m: " << Fmt("%.2f", io::kDefaultGnssMaxSigmaM)
        << "  # fixes with a larger horizontal σ (RTK float) are not used\n";
  } else {
    out << "  min_fix_quality: 4  # 4 RTK fixed; 5 also float\n";
  }
  out << "heading:\n  log: " << log << "\n"
      << topic_line(heading, "QuaternionStamped, Imu or HDT/THS sentence") << Why(heading, "heading");
  out << "  reference: true_north  # CHECK: an INS's ENU yaw is referenced to true north\n";
  // The attitude stream: an Imu topic whose driver fills the orientation with the vehicle's
  // (roll and pitch a vehicle stands at). One whose orientation is another frame's (an IMU
  // turned on the vehicle) is named in a comment, not proposed.
  std::vector<const TopicSummary*> attitude;
  for (const TopicSummary* t : Candidates(topics, {recording::RosType::kImu}, "")) {
    if (!t->attitudes.attitudes.empty()) {
      attitude.push_back(t);
    } else if (t->imu_with_orientation > 0) {
      out << "# attitude: not " << t->info->name << ": its orientation is not the vehicle's (no "
          << "message with roll and pitch within ±30°: an IMU turned on the vehicle?)\n";
    }
  }
  if (!attitude.empty()) {
    const TopicSummary& chosen = *attitude.front();
    out << "attitude:  # the vehicle's roll and pitch (docs/session-format.md)\n  log: " << log
        << "\n  topic: " << chosen.info->name << "  # " << chosen.info->type << ", "
        << chosen.info->count << " messages, " << chosen.attitudes.attitudes.size()
        << " with the vehicle's roll and pitch\n"
        << Why(attitude, "attitude") << "  stamp: header  # or receive: the recorder's time\n"
        << "  # sigma_deg: " << Fmt("%.1f", io::kDefaultAttitudeSigmaRad * kRadToDeg)
        << "  # a sample's 1σ of roll and pitch where the Imu's covariance gives none\n";
  }
  out << "survey:\n  points: survey.csv  # CHECK: the surveyor's file (CSV or Leica GSI)\n"
      << "  control:\n    - {id: C1, lat: 0.0, lon: 0.0, h: 0.0}  # CHECK: RTK-measured control points\n"
      << "    - {id: C2, lat: 0.0, lon: 0.0, h: 0.0}\n"
      << "walls:\n  - {id: wall, code: WALL1}  # CHECK: the survey code of the wall's points\n";
  return out.str();
}

void DumpRecording(const std::string& path, DumpKind kind, const std::string& topic,
                   std::ostream& out) {
  std::unique_ptr<recording::Recording> recording = recording::OpenRecording(path);
  const std::vector<recording::RosType> accepted =
      kind == DumpKind::kScans      ? recording::AcceptedScanTypes()
      : kind == DumpKind::kGnss     ? recording::AcceptedGnssTypes()
      : kind == DumpKind::kAttitude ? recording::AcceptedAttitudeTypes()
                                    : recording::AcceptedHeadingTypes();
  std::string chosen = topic;
  if (chosen.empty()) {
    std::vector<std::string> fit;
    for (const recording::TopicInfo& info : recording->topics()) {
      if (std::find(accepted.begin(), accepted.end(), recording::RosTypeFromName(info.type)) !=
          accepted.end()) {
        fit.push_back(info.name + " (" + info.type + ")");
        chosen = info.name;
      }
    }
    if (fit.size() != 1) {
      std::string list;
      for (const std::string& f : fit) list += (list.empty() ? "" : ", ") + f;
      throw io::InputError(io::Where(
          path, 0,
          fit.empty() ? "no topic of a type this dump reads"
                      : "several topics fit: " + list + "; expected --topic NAME to pick one"));
    }
  }
  recording.reset();
  io::SessionSpec spec;
  spec.scanner_log = spec.gnss_log = spec.heading_log = path;
  spec.scanner_topic = spec.gnss_topic = spec.heading_topic = chosen;
  spec.attitude_log = path;
  spec.attitude_topic = chosen;
  WriteDumpCsv(spec, kind, nullptr, out);
}

}  // namespace wallcal::preflight
