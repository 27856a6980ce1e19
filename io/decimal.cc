// SPDX-License-Identifier: Apache-2.0
#include "io/internal/decimal.h"

#include <charconv>
#include <cstdint>
#include <system_error>

namespace wallcal::io {
namespace {

constexpr int kMaxFastDigits = 15;     // 10^15 < 2^53: the digits are an exact double
constexpr int kMaxFastFraction = 22;   // 10^22 is the largest exact power of ten
constexpr double kPowersOfTen[kMaxFastFraction + 1] = {
    1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
    1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

// The fast path: true and *value set when [p, end) is [-]digits[.digits] within the limits.
bool FastDecimal(const char* p, const char* end, double* value) {
  const bool negative = p < end && *p == '-';
  if (negative) ++p;
  uint64_t digits_value = 0;
  int digits = 0, fraction = 0;
  bool point = false;
  for (; p < end; ++p) {
    const char c = *p;
    if (c >= '0' && c <= '9') {
      if (++digits > kMaxFastDigits) return false;
      digits_value = digits_value * 10 + static_cast<uint64_t>(c - '0');
      if (point) ++fraction;
    } else if (c == '.' && !point) {
      point = true;
    } else {
      return false;
    }
  }
  if (digits == 0 || fraction > kMaxFastFraction) return false;
  double v = static_cast<double>(digits_value);
  if (fraction > 0) v /= kPowersOfTen[fraction];
  *value = negative ? -v : v;
  return true;
}

}  // namespace

bool ParseDecimal(std::string_view token, double* value) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin < end && *begin == '+') ++begin;  // from_chars rejects a leading '+'
  if (FastDecimal(begin, end, value)) return true;
  const auto result = std::from_chars(begin, end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

}  // namespace wallcal::io
