// SPDX-License-Identifier: Apache-2.0
#include "io/config/rosbag2_metadata.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "io/types.h"

namespace wallcal::io {
namespace {

int LineOf(const YAML::Node& node) {
  return node.IsDefined() && node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
}
// A missing key of a const node is an invalid node, whose type queries throw: ask first.
bool IsMap(const YAML::Node& node) { return node.IsDefined() && node.IsMap(); }
bool IsSequence(const YAML::Node& node) { return node.IsDefined() && node.IsSequence(); }

// A scalar of type T at node[key]; `required` keys throw when missing.
template <typename T>
T Get(const YAML::Node& map, const char* key, const std::string& name, const char* expected,
      bool required, T fallback) {
  const YAML::Node node = map[key];
  if (!node.IsDefined() || node.IsNull()) {
    if (required) {
      throw InputError(
          Where(name, LineOf(map), std::string("missing '") + key + "'; expected " + expected));
    }
    return fallback;
  }
  try {
    if (!node.IsScalar()) throw YAML::BadConversion(node.Mark());
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(Where(name, LineOf(node), std::string("'") + key + "' is not " + expected));
  }
}

}  // namespace

Rosbag2Metadata ParseRosbag2Metadata(const std::string& text, const std::string& name) {
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError(Where(name, e.mark.line + 1, "YAML syntax error: " + e.msg));
  } catch (const YAML::Exception& e) {
    throw InputError(Where(name, 0, std::string("cannot read YAML: ") + e.what()));
  }
  const YAML::Node info = IsMap(root) ? root["rosbag2_bagfile_information"] : YAML::Node();
  if (!IsMap(info)) {
    throw InputError(Where(name, LineOf(root),
                           "expected a 'rosbag2_bagfile_information' map "
                           "(a rosbag2 metadata.yaml)"));
  }
  Rosbag2Metadata meta;
  meta.version = Get<int>(info, "version", name, "an integer", false, 0);
  meta.storage_identifier =
      Get<std::string>(info, "storage_identifier", name, "a name (sqlite3, mcap)", true, "");
  meta.message_count = Get<int64_t>(info, "message_count", name, "an integer", false, 0);
  meta.compression_format = Get<std::string>(info, "compression_format", name, "text", false, "");
  meta.compression_mode = Get<std::string>(info, "compression_mode", name, "text", false, "");
  const YAML::Node duration = info["duration"];
  if (IsMap(duration)) {
    meta.duration_ns = Get<int64_t>(duration, "nanoseconds", name, "an integer", false, 0);
  }
  const YAML::Node start = info["starting_time"];
  if (IsMap(start)) {
    meta.starting_time_ns =
        Get<int64_t>(start, "nanoseconds_since_epoch", name, "an integer", false, 0);
  }
  const YAML::Node files = info["relative_file_paths"];
  if (!IsSequence(files) || files.size() == 0) {
    throw InputError(Where(name, LineOf(files.IsDefined() ? files : info),
                           "expected 'relative_file_paths': a list of storage files"));
  }
  for (const YAML::Node& file : files) {
    if (!file.IsDefined() || !file.IsScalar() || file.Scalar().empty()) {
      throw InputError(Where(name, LineOf(file), "a relative_file_paths entry is not a file name"));
    }
    meta.relative_file_paths.push_back(file.Scalar());
  }
  const YAML::Node topics = info["topics_with_message_count"];
  if (topics.IsDefined() && !topics.IsNull()) {
    if (!IsSequence(topics)) {
      throw InputError(Where(name, LineOf(topics), "'topics_with_message_count' is not a list"));
    }
    for (const YAML::Node& entry : topics) {
      const YAML::Node topic = IsMap(entry) ? entry["topic_metadata"] : YAML::Node();
      if (!IsMap(topic)) {
        throw InputError(Where(name, LineOf(entry), "expected 'topic_metadata' with the topic"));
      }
      Rosbag2TopicCount count;
      count.name = Get<std::string>(topic, "name", name, "a topic name", true, "");
      if (count.name.empty()) {
        throw InputError(Where(name, LineOf(topic), "a topic_metadata has an empty name"));
      }
      count.type = Get<std::string>(topic, "type", name, "a type name", false, "");
      count.serialization_format =
          Get<std::string>(topic, "serialization_format", name, "text", false, "");
      count.message_count = Get<int64_t>(entry, "message_count", name, "an integer", false, 0);
      meta.topics.push_back(count);
    }
  }
  return meta;
}

Rosbag2Metadata ReadRosbag2Metadata(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(Where(path, 0, "cannot open; expected a rosbag2 metadata.yaml"));
  std::ostringstream text;
  text << in.rdbuf();
  return ParseRosbag2Metadata(text.str(), path);
}

std::string FormatRosbag2Metadata(const Rosbag2Metadata& meta) {
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value
      << YAML::BeginMap;
  out << YAML::Key << "version" << YAML::Value << 5;
  out << YAML::Key << "storage_identifier" << YAML::Value << meta.storage_identifier;
  out << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
      << YAML::Value << meta.duration_ns << YAML::EndMap;
  out << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key
      << "nanoseconds_since_epoch" << YAML::Value << meta.starting_time_ns << YAML::EndMap;
  out << YAML::Key << "message_count" << YAML::Value << meta.message_count;
  out << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const Rosbag2TopicCount& t : meta.topics) {
    out << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << t.name;
    out << YAML::Key << "type" << YAML::Value << t.type;
    out << YAML::Key << "serialization_format" << YAML::Value << t.serialization_format;
    out << YAML::Key << "offered_qos_profiles" << YAML::Value << "";
    out << YAML::EndMap << YAML::Key << "message_count" << YAML::Value << t.message_count
        << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "compression_format" << YAML::Value << meta.compression_format;
  out << YAML::Key << "compression_mode" << YAML::Value << meta.compression_mode;
  out << YAML::Key << "relative_file_paths" << YAML::Value << YAML::BeginSeq;
  for (const std::string& f : meta.relative_file_paths) out << f;
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace wallcal::io
