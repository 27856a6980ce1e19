// SPDX-License-Identifier: Apache-2.0
#pragma once
// The generic side of option files: each module declares its own option struct and the list of
// its YAML keys (a Visit function over any visitor with the methods below), and io/ reads the
// file strictly without knowing any module's settings. The same Visit function drives the
// writer (io/config/options_text.h), so that what is written reads back.
//
// A visitor V provides:
//   v.Number(key, double&)                 the value as written
//   v.Scaled(key, double&, file_per_unit)  the file holds value * file_per_unit (degrees ...)
//   v.Integer(key, int&), v.Boolean(key, bool&), v.Text(key, std::string&)
//   v.List(key, std::vector<T>&, visit_item)  a list of maps, each visited by visit_item(v, T&)
// Every key is optional: an absent key leaves the default of the declaration.

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

// The checks a Validate() makes, each throwing OptionError "KEY must be REQUIREMENT, got VALUE"
// (the value as the file spells it: give angles in the file's unit).
namespace option_checks {
[[noreturn]] void Fail(const std::string& key, const std::string& requirement,
                       const std::string& got);
std::string Number(double value);  // the shortest readable form for messages
void CheckFinite(const std::string& key, double value);
void CheckPositive(const std::string& key, double value);
void CheckNonNegative(const std::string& key, double value);
void CheckRange(const std::string& key, double value, double lo, double hi);
void CheckAtLeast(const std::string& key, int value, int lo);
// An angle given in degrees in the file (key ends in _deg), held in radians: in (0, max_deg].
void CheckAnglePositive(const std::string& key_deg, double rad, double max_deg);
}  // namespace option_checks

// One YAML map being read strictly: the visitor above (every key optional, every value checked
// as it is read, the file and line in every message), plus sections. Made by ReadOptionsFile.
class OptionsMap {
 public:
  virtual ~OptionsMap() = default;
  virtual void Number(const std::string& key, double& value) = 0;
  virtual void Scaled(const std::string& key, double& value, double file_per_unit) = 0;
  virtual void Integer(const std::string& key, int& value) = 0;
  virtual void Boolean(const std::string& key, bool& value) = 0;
  virtual void Text(const std::string& key, std::string& value) = 0;
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
