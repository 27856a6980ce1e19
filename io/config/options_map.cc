// SPDX-License-Identifier: Apache-2.0
#include "io/config/options_map.h"

#include <cmath>
#include <sstream>

#include "io/config/internal/yaml_map_reader.h"
#include "io/config/internal/yaml_strict.h"
#include "io/config/options_text.h"

namespace wallcal::io {

namespace option_checks {

std::string Number(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

void Fail(const std::string& key, const std::string& requirement, const std::string& got) {
  throw OptionError(key, key + " must be " + requirement + ", got " + got);
}

void CheckFinite(const std::string& key, double value) {
  if (!std::isfinite(value)) Fail(key, "a finite number", Number(value));
}
void CheckPositive(const std::string& key, double value) {
  if (!(std::isfinite(value) && value > 0.0)) Fail(key, "> 0", Number(value));
}
void CheckNonNegative(const std::string& key, double value) {
  if (!(std::isfinite(value) && value >= 0.0)) Fail(key, ">= 0", Number(value));
}
void CheckRange(const std::string& key, double value, double lo, double hi) {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    Fail(key, "in [" + Number(lo) + ", " + Number(hi) + "]", Number(value));
  }
}
void CheckAtLeast(const std::string& key, int value, int lo) {
  if (value < lo) Fail(key, ">= " + std::to_string(lo), std::to_string(value));
}
void CheckAnglePositive(const std::string& key_deg, double rad, double max_deg) {
  const double deg = rad * kRadToDeg;
  if (!(std::isfinite(deg) && deg > 0.0 && deg <= max_deg)) {
    Fail(key_deg, "in (0, " + Number(max_deg) + "]", Number(deg));
  }
}

}  // namespace option_checks

void ReadOptionsFile(const std::string& file, const std::function<void(OptionsMap&)>& read,
                     const std::function<void()>& validate) {
  const YAML::Node root = LoadYamlStrict(file);
  yaml_detail::MapReader top(root, file, "", 1);
  read(top);
  top.Finish();
  try {
    validate();
  } catch (const OptionError& e) {
    throw InputError(Where(file, LineOfKey(root, e.key()), e.what()));
  } catch (const InputError& e) {
    throw InputError(Where(file, 0, e.what()));
  }
}

std::string OptionsText::Flow() const {
  std::string text = "{";
  for (size_t i = 0; i < entries_.size(); ++i) {
    if (i > 0) text += ", ";
    text += entries_[i].key + ": " + entries_[i].value;
  }
  return text + "}";
}

std::string OptionsText::Block(int indent) const {
  const std::string pad(static_cast<size_t>(indent), ' ');
  std::string text;
  for (const Entry& entry : entries_) {
    if (!entry.is_list) {
      text += pad + entry.key + ": " + entry.value + "\n";
    } else if (entry.items.empty()) {
      text += pad + entry.key + ": []\n";
    } else {
      text += pad + entry.key + ":\n";
      for (const std::string& item : entry.items) text += pad + "  - " + item + "\n";
    }
  }
  return text;
}

}  // namespace wallcal::io
