// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading a decimal number from a log field, as std::from_chars does but faster for the plain
// form loggers write ("80.000", "-1.5707963267948966").

#include <string_view>

namespace wallcal::io {

// The value of `token` (the whole of it: an optional sign, digits, an optional fraction, an
// optional exponent, or what else std::from_chars accepts for doubles, plus a leading '+').
// False, with *value unspecified, when the token is not such a number.
//
// Tokens of at most 15 digits with at most 22 after the point and no exponent take a fast
// path: the digits m and 10^k are both exact doubles, so m / 10^k is one correctly rounded
// division, the value std::from_chars gives (Clinger, "How to read floating point numbers
// accurately", PLDI 1990). Every other token goes to std::from_chars.
bool ParseDecimal(std::string_view token, double* value);

}  // namespace wallcal::io
