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

}  // namespace option_checks

using namespace option_checks;  // NOLINT: Check::Apply makes these checks

namespace {

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

}  // namespace

void Check::Apply(const std::string& key, double value) const {
  if (nan_is_unset && std::isnan(value)) return;
  switch (kind) {
    case Kind::kAny:
    case Kind::kNonEmpty:
      return;
    case Kind::kFinite:
      return CheckFinite(key, value);
    case Kind::kPositive:
      return CheckPositive(key, value);
    case Kind::kNonNegative:
      return CheckNonNegative(key, value);
    case Kind::kAtLeast:
      if (!(std::isfinite(value) && value >= lo)) Fail(key, ">= " + Number(lo), Number(value));
      return;
    case Kind::kInRange:
      return CheckRange(key, value, lo, hi);
    case Kind::kAboveUpTo:
      if (!(std::isfinite(value) && value > lo && value <= hi)) {
        Fail(key, "in (" + Number(lo) + ", " + Number(hi) + "]", Number(value));
      }
      return;
    case Kind::kUpToBelow:
      if (!(std::isfinite(value) && value >= lo && value < hi)) {
        Fail(key, "in [" + Number(lo) + ", " + Number(hi) + ")", Number(value));
      }
      return;
  }
}

void Check::Apply(const std::string& key, int value) const {
  if (kind == Kind::kAtLeast && value < lo) {
    Fail(key, ">= " + Number(lo), std::to_string(value));
  }
  if (kind != Kind::kAtLeast) Apply(key, static_cast<double>(value));
}

void Check::Apply(const std::string& key, const std::string& value) const {
  if (kind == Kind::kNonEmpty && value.empty()) Fail(key, "non-empty", "\"\"");
}

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
