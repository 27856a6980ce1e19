// SPDX-License-Identifier: Apache-2.0
#pragma once
// The text of an enum value, from a table of {value, text} pairs beside the enum's users: one
// lookup instead of a switch for each name.

#include <cstddef>
#include <utility>

namespace wallcal {

template <class Enum>
using EnumText = std::pair<Enum, const char*>;

// The text `table` gives `value`, or `otherwise` when the table does not list it.
template <class Enum, std::size_t N>
const char* TextOf(const EnumText<Enum> (&table)[N], Enum value, const char* otherwise) {
  for (std::size_t i = 0; i < N; ++i) {
    if (table[i].first == value) return table[i].second;
  }
  return otherwise;
}

}  // namespace wallcal
