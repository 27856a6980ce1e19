// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writing an option struct as YAML through its Visit function (io/config/options_map.h): the
// writing visitor collects `key: value` pairs; lists become one flow map per item.

#include <cmath>
#include <string>
#include <vector>

#include "io/config/options_map.h"
#include "io/config/yaml_text.h"

namespace wallcal::io {

class OptionsText {
 public:
  // The checks are Validate()'s: what is written is the struct as it stands, but for a key
  // left unset (NaN with an OrUnset() check, an empty list of numbers): that is left out, so
  // that a file without the key reads back the same.
  void Number(const std::string& key, double& value, const Check& check = {}) {
    if (check.nan_is_unset && std::isnan(value)) return;
    Add(key, ShortestNumber(value));
  }
  void Scaled(const std::string& key, double& value, double file_per_unit,
              const Check& check = {}) {
    if (check.nan_is_unset && std::isnan(value)) return;
    Add(key, ShortestScaled(value, file_per_unit));
  }
  void Numbers(const std::string& key, std::vector<double>& values, const Check& /*check*/ = {}) {
    if (values.empty()) return;
    std::string text = "[";
    for (size_t i = 0; i < values.size(); ++i) {
      text += (i > 0 ? ", " : "") + ShortestNumber(values[i]);
    }
    Add(key, text + "]");
  }
  void Integer(const std::string& key, int& value, const Check& /*check*/ = {}) {
    Add(key, std::to_string(value));
  }
  void Boolean(const std::string& key, bool& value) { Add(key, value ? "true" : "false"); }
  void Text(const std::string& key, std::string& value, const Check& /*check*/ = {}) {
    Add(key, YamlText(value));
  }
  template <class T, class F>
  void List(const std::string& key, std::vector<T>& items, F visit_item) {
    Entry entry;
    entry.key = key;
    entry.is_list = true;
    for (T& item : items) {
      OptionsText item_writer;
      visit_item(item_writer, item);
      entry.items.push_back(item_writer.Flow());
    }
    entries_.push_back(std::move(entry));
  }

  // A key with text that is already YAML (a number, a flow map).
  void Add(const std::string& key, const std::string& value) {
    Entry entry;
    entry.key = key;
    entry.value = value;
    entries_.push_back(std::move(entry));
  }

  // "{a: 1, b: 2}" (one level: lists inside are written as their flow maps).
  std::string Flow() const;
  // One key a line at `indent` spaces; a list as "key:" and "  - {…}" lines.
  std::string Block(int indent) const;

 private:
  struct Entry {
    std::string key;
    std::string value;               // scalar text, or empty for a list
    std::vector<std::string> items;  // flow maps of a list
    bool is_list = false;
  };
  std::vector<Entry> entries_;
};

}  // namespace wallcal::io
