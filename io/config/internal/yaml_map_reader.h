// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading one YAML mapping strictly: every key known, every value checked where it is read, the
// file and line in every message. Shared by io/session_reader.cc (session.yaml) and
// io/config_reader.cc (presets, options, simulation and truth files). Internal to io/.

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <set>
#include <sstream>

#include "io/config/options_map.h"
#include "io/input_file.h"
#include "io/config/internal/yaml_strict.h"
#include "common/angles.h"

#include "io/config/session_reader.h"

namespace wallcal::io::yaml_detail {

namespace fs = std::filesystem;
// yaml-cpp marks are 0-based; files are read by people counting from 1.
inline int LineOf(const YAML::Node& node) { return YamlLine(node); }

inline std::string Join(const std::vector<std::string>& items, const std::string& separator) {
  std::string text;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i > 0) text += separator;
    text += items[i];
  }
  return text;
}

// Reads the keys of one YAML map, remembers which ones were asked for, and rejects the others
// in Finish(): a misspelt key must not silently fall back to a default. Also the visitor of
// io/config/options_map.h. `prefix` ("scanner.") names the map in messages.
class MapReader : public OptionsMap {
 public:
  MapReader(const YAML::Node& node, std::string file, std::string prefix, int line)
      : node_(node), file_(std::move(file)), prefix_(std::move(prefix)), line_(line) {
    if (node_.IsDefined() && !node_.IsNull() && !node_.IsMap()) {
      const std::string what = prefix_.empty() ? "the file" : Name("");
      throw InputError(Where(file_, LineOf(node_), what + " must be a map of key: value"));
    }
  }

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  std::string Name(const std::string& key) const {
    if (prefix_.empty()) return key;
    if (key.empty()) return prefix_.substr(0, prefix_.size() - 1);
    return prefix_ + key;
  }

  // The value of `key`, or an undefined node when absent. Null values count as absent for
  // nothing: an empty `key:` is reported by the typed getters.
  YAML::Node Find(const std::string& key) {
    if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
    if (!node_.IsMap()) return YAML::Node(YAML::NodeType::Undefined);
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      if (it->first.IsScalar() && it->first.Scalar() == key) return it->second;
    }
    return YAML::Node(YAML::NodeType::Undefined);
  }

  YAML::Node Require(const std::string& key, const std::string& expected) {
    YAML::Node value = Find(key);
    if (!value.IsDefined()) {
      throw InputError(Where(file_, line_, Name(key) + " is missing; expected " + expected));
    }
    return value;
  }

  [[noreturn]] void Bad(const YAML::Node& value, const std::string& key,
                        const std::string& expected) const {
    // The value is the user's own text, but it is escaped and shortened: a message is one line.
    std::string shown = value.IsScalar() ? value.Scalar() : "";
    if (shown.size() > 60) shown = shown.substr(0, 57) + "...";
    std::string got = value.IsScalar() ? "'" + EscapeControl(shown) + "'"
                      : value.IsNull() ? "nothing"
                      : value.IsMap()  ? "a map"
                                       : "a list";
    throw InputError(
        Where(file_, LineOf(value), Name(key) + ": expected " + expected + ", got " + got));
  }

  double ToNumber(const YAML::Node& value, const std::string& key) const {
    double number = 0.0;
    if (!value.IsScalar() || !YAML::convert<double>::decode(value, number) ||
        !std::isfinite(number)) {
      Bad(value, key, "a finite number");
    }
    return number;
  }
  int ToInteger(const YAML::Node& value, const std::string& key) const {
    int number = 0;
    if (!value.IsScalar() || !YAML::convert<int>::decode(value, number)) {
      Bad(value, key, "an integer");
    }
    return number;
  }
  std::string ToText(const YAML::Node& value, const std::string& key) const {
    if (!value.IsScalar() || value.Scalar().empty()) Bad(value, key, "a non-empty text");
    CheckNoControl(value, key);
    return value.Scalar();
  }
  // Names and paths go to terminals and files: no control characters (escape sequences, fake
  // lines). Bytes that are not UTF-8 are allowed (a Latin-1 file name) and escaped on output.
  void CheckNoControl(const YAML::Node& value, const std::string& key) const {
    for (const char c : value.Scalar()) {
      const unsigned char u = static_cast<unsigned char>(c);
      if ((u < 0x20 && c != '\t') || u == 0x7F) {
        Bad(value, key, "text without control characters");
      }
    }
  }

  // --- the visitor interface of io/config/options_map.h (all keys optional; the checks are
  // Validate()'s) ---
  void Number(const std::string& key, double& out, const Check& /*check*/ = {}) override {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToNumber(value, key);
  }
  void Scaled(const std::string& key, double& out, double file_per_unit,
              const Check& /*check*/ = {}) override {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToNumber(value, key) / file_per_unit;
  }
  void Integer(const std::string& key, int& out, const Check& /*check*/ = {}) override {
    const YAML::Node value = Find(key);
    if (value.IsDefined()) out = ToInteger(value, key);
  }
  void Boolean(const std::string& key, bool& out) override {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    bool flag = false;
    if (!value.IsScalar() || !YAML::convert<bool>::decode(value, flag)) {
      Bad(value, key, "true or false");
    }
    out = flag;
  }
  void Text(const std::string& key, std::string& out, const Check& /*check*/ = {}) override {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    if (value.IsNull()) {
      out.clear();
      return;
    }
    if (!value.IsScalar()) Bad(value, key, "a text");
    CheckNoControl(value, key);
    out = value.Scalar();
  }
  void Numbers(const std::string& key, std::vector<double>& out,
               const Check& /*check*/ = {}) override {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    out.clear();
    if (value.IsNull()) return;
    if (!value.IsSequence()) Bad(value, key, "a list of numbers");
    for (size_t i = 0; i < value.size(); ++i) {
      out.push_back(ToNumber(value[i], key + "[" + std::to_string(i) + "]"));
    }
  }
  void ListOfMaps(const std::string& key, const std::function<void()>& clear,
                  const std::function<void(OptionsMap&)>& item) override {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    clear();
    if (value.IsNull()) return;
    if (!value.IsSequence()) Bad(value, key, "a list");
    for (size_t i = 0; i < value.size(); ++i) {
      const YAML::Node element = value[i];
      if (!element.IsMap()) Bad(element, key + "[" + std::to_string(i) + "]", "a map");
      MapReader item_reader(element, file_, Name(key) + "[" + std::to_string(i) + "].",
                            LineOf(element));
      item(item_reader);
      item_reader.Finish();
    }
  }

  template <class T, class F>
  void List(const std::string& key, std::vector<T>& out, F visit_item) {
    ListOfMaps(key, [&out] { out.clear(); }, [&out, &visit_item](OptionsMap& item_map) {
      T element;
      visit_item(static_cast<MapReader&>(item_map), element);
      out.push_back(std::move(element));
    });
  }

  // Declares keys read later, so that Finish() can report a misspelt key before a later
  // "missing key" message would hide it.
  void Allow(std::initializer_list<const char*> keys) {
    for (const char* key : keys) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.emplace_back(key);
    }
  }

  void Allow(const std::vector<std::string>& keys) override {
    for (const std::string& key : keys) {
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) known_.push_back(key);
    }
  }

  void Section(const std::string& key, const std::function<void(OptionsMap&)>& visit) override {
    const YAML::Node value = Find(key);
    if (!value.IsDefined()) return;
    MapReader child = Child(key, value);
    visit(child);
    child.Finish();
  }

  void RequiredSection(const std::string& key, const std::string& expected,
                       const std::function<void(OptionsMap&)>& visit) override {
    MapReader child = Child(key, Require(key, expected));
    visit(child);
    child.Finish();
  }

  MapReader Child(const std::string& key, const YAML::Node& value) const {
    return MapReader(value, file_, Name(key) + ".", LineOf(value));
  }

  void AllowOthers() override { allow_others_ = true; }

  // Rejects every key that was not asked for.
  void Finish() const {
    if (!node_.IsMap() || allow_others_) return;
    for (auto it = node_.begin(); it != node_.end(); ++it) {
      const std::string key = it->first.IsScalar() ? it->first.Scalar() : "?";
      if (std::find(known_.begin(), known_.end(), key) == known_.end()) {
        throw InputError(
            Where(file_, LineOf(it->first),
                  "unknown key '" + Name(key) + "'; expected one of: " + Join(known_, ", ")));
      }
    }
  }

 private:
  YAML::Node node_;
  std::string file_;
  std::string prefix_;
  int line_ = 0;
  std::vector<std::string> known_;
  bool allow_others_ = false;
};

// Runs Validate() and puts the file name, and the line of the key at fault, in front of its
// message.
template <class T>
void ValidateIn(const std::string& file, const T& options, const YAML::Node& root) {
  try {
    options.Validate();
  } catch (const OptionError& e) {
    throw InputError(Where(file, LineOfKey(root, e.key()), e.what()));
  } catch (const InputError& e) {
    throw InputError(Where(file, 0, e.what()));
  }
}


}  // namespace wallcal::io::yaml_detail
