// SPDX-License-Identifier: Apache-2.0
#pragma once
// The generic side of option files: each module declares its own option struct and the list of
// its YAML keys, each with the check its value must pass (a Visit function over any visitor
// with the methods below), and io/ reads the file strictly without knowing any module's
// settings. The same Visit function drives the writer (io/config/options_text.h), so that what
// is written reads back, and the struct's Validate() (OptionChecker, CheckOptions below), so
// that the key list and the checks are one list.
//
// A visitor V provides:
//   v.Number(key, double&, check)                 the value as written
//   v.Scaled(key, double&, file_per_unit, check)  the file holds value * file_per_unit (degrees)
//   v.Integer(key, int&, check), v.Boolean(key, bool&), v.Text(key, std::string&, check)
//   v.List(key, std::vector<T>&, visit_item)  a list of maps, each visited by visit_item(v, T&)
//   v.Numbers(key, std::vector<double>&, check)  a list of numbers ([0.3, 2.5]), each checked
// Every key is optional: an absent key leaves the default of the declaration. Every check is
// optional too (Check{}: any value the reader takes). A key left unset (a NaN with an
// OrUnset() check, an empty list of numbers) is not written (io/config/options_text.h).

#include <functional>
#include <string>
#include <vector>

#include "common/angles.h"
#include "io/types.h"

namespace wallcal::io {

// What an option struct's Validate() throws: an InputError that also carries the YAML key at
// fault ("detector.hough_rho_step_m"), so that the file's reader can add the key's line.
class OptionError : public InputError {
 public:
  OptionError(std::string key, const std::string& message)
      : InputError(message), key_(std::move(key)) {}
  const std::string& key() const { return key_; }

 private:
  std::string key_;
};

// What a Validate() check that spans several keys (beyond each key's Check below) throws:
// OptionError "KEY must be REQUIREMENT, got VALUE" (the value as the file spells it: give
// angles in the file's unit).
namespace option_checks {
[[noreturn]] void Fail(const std::string& key, const std::string& requirement,
                       const std::string& got);
std::string Number(double value);  // the shortest readable form for messages
}  // namespace option_checks

// What a key's value must be, checked by Validate() on the value as the file spells it (a
// Scaled key in the file's unit). A failed check throws OptionError "KEY must be REQUIREMENT,
// got VALUE" (option_checks::Fail). Made by the functions below; Check{} passes everything.
struct Check {
  enum class Kind {
    kAny,
    kFinite,
    kPositive,     // > 0
    kNonNegative,  // >= 0
    kAtLeast,      // >= lo
    kInRange,      // [lo, hi]
    kAboveUpTo,    // (lo, hi]
    kUpToBelow,    // [lo, hi)
    kNonEmpty,     // text
  };
  Kind kind = Kind::kAny;
  double lo = 0.0;
  double hi = 0.0;
  bool nan_is_unset = false;  // NaN means "not set" and passes (OrUnset)

  // The same check, passing NaN (a key whose NaN default means "take it from elsewhere").
  Check OrUnset() const {
    Check check = *this;
    check.nan_is_unset = true;
    return check;
  }
  void Apply(const std::string& key, double value) const;
  void Apply(const std::string& key, int value) const;
  void Apply(const std::string& key, const std::string& value) const;
};

inline Check Finite() { return {Check::Kind::kFinite}; }
inline Check Positive() { return {Check::Kind::kPositive}; }
inline Check NonNegative() { return {Check::Kind::kNonNegative}; }
inline Check AtLeast(double lo) { return {Check::Kind::kAtLeast, lo}; }
inline Check InRange(double lo, double hi) { return {Check::Kind::kInRange, lo, hi}; }
inline Check AboveUpTo(double lo, double hi) { return {Check::Kind::kAboveUpTo, lo, hi}; }
inline Check UpToBelow(double lo, double hi) { return {Check::Kind::kUpToBelow, lo, hi}; }
inline Check NonEmpty() { return {Check::Kind::kNonEmpty}; }

// The visitor a Validate() runs: each key's check on its value, the key named prefix + key
// ("detector.min_inliers", "simulation.walls[2].height_m") in the message.
class OptionChecker {
 public:
  explicit OptionChecker(std::string prefix) : prefix_(std::move(prefix)) {}
  void Number(const std::string& key, const double& value, const Check& check = {}) const {
    check.Apply(prefix_ + key, value);
  }
  void Scaled(const std::string& key, const double& value, double file_per_unit,
              const Check& check = {}) const {
    check.Apply(prefix_ + key, value * file_per_unit);
  }
  void Integer(const std::string& key, const int& value, const Check& check = {}) const {
    check.Apply(prefix_ + key, value);
  }
  void Boolean(const std::string& /*key*/, const bool& /*value*/) const {}
  void Text(const std::string& key, const std::string& value, const Check& check = {}) const {
    check.Apply(prefix_ + key, value);
  }
  void Numbers(const std::string& key, const std::vector<double>& values,
               const Check& check = {}) const {
    for (size_t i = 0; i < values.size(); ++i) {
      check.Apply(prefix_ + key + "[" + std::to_string(i) + "]", values[i]);
    }
  }
  template <class T, class F>
  void List(const std::string& key, std::vector<T>& items, F visit_item) const {
    for (size_t i = 0; i < items.size(); ++i) {
      OptionChecker item(prefix_ + key + "[" + std::to_string(i) + "].");
      visit_item(item, items[i]);
    }
  }
  template <class F>
  void Section(const std::string& key, F visit) const {
    OptionChecker section(prefix_ + key + ".");
    visit(section);
  }

 private:
  std::string prefix_;
};

// Validate()'s key checks: runs `visit` (a module's Visit function, instantiated for
// OptionChecker) over a copy of `options` (visitors take the struct by mutable reference).
template <class T>
void CheckOptions(const std::string& prefix, const T& options, void (*visit)(OptionChecker&, T&)) {
  T copy = options;
  OptionChecker checker(prefix);
  visit(checker, copy);
}

// One YAML map being read strictly: the visitor above (every key optional, every value checked
// as it is read, the file and line in every message), plus sections. Made by ReadOptionsFile.
class OptionsMap {
 public:
  virtual ~OptionsMap() = default;
  // The checks are Validate()'s (OptionChecker): reading takes any value of the key's type.
  virtual void Number(const std::string& key, double& value, const Check& check = {}) = 0;
  virtual void Scaled(const std::string& key, double& value, double file_per_unit,
                      const Check& check = {}) = 0;
  virtual void Integer(const std::string& key, int& value, const Check& check = {}) = 0;
  virtual void Boolean(const std::string& key, bool& value) = 0;
  virtual void Text(const std::string& key, std::string& value, const Check& check = {}) = 0;
  // A list of finite numbers; an empty value (`key:` or `key: []`) clears it.
  virtual void Numbers(const std::string& key, std::vector<double>& values,
                       const Check& check = {}) = 0;

  // The map under `key`, when present: visit(it), then its unknown keys are refused.
  virtual void Section(const std::string& key, const std::function<void(OptionsMap&)>& visit) = 0;
  // Like Section, but refuses a file without the key (`expected` says what it holds).
  virtual void RequiredSection(const std::string& key, const std::string& expected,
                               const std::function<void(OptionsMap&)>& visit) = 0;
  // Keys that may stand in this map and are read by someone else (left alone here).
  virtual void Allow(const std::vector<std::string>& keys) = 0;
  // Every other key of this map is left alone (an output document read for a few keys).
  virtual void AllowOthers() = 0;

  template <class T, class F>
  void List(const std::string& key, std::vector<T>& items, F visit_item) {
    ListOfMaps(key, [&items] { items.clear(); }, [&items, &visit_item](OptionsMap& item_map) {
      T item;
      visit_item(item_map, item);
      items.push_back(std::move(item));
    });
  }

 protected:
  // A list of maps under `key`, when present: clear(), then item(map) for each, in order.
  virtual void ListOfMaps(const std::string& key, const std::function<void()>& clear,
                          const std::function<void(OptionsMap&)>& item) = 0;
};

// Reads FILE as strict YAML (one document, no duplicate keys, within the byte budget), runs
// read(top-level map), refuses the keys it did not ask for, then runs validate(). An
// OptionError from validate is rethrown as "FILE:LINE: message" with the line of its key.
// Throws InputError for every fault.
void ReadOptionsFile(const std::string& file, const std::function<void(OptionsMap&)>& read,
                     const std::function<void()>& validate);

}  // namespace wallcal::io
