// SPDX-License-Identifier: Apache-2.0
// io::ParseDecimal against std::from_chars: the same double, bit for bit (sign of zero
// included), on the plain decimals its fast path takes and on everything it hands over.
#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <system_error>

#include "io/internal/decimal.h"

namespace wallcal::io {
namespace {

uint64_t Bits(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  return bits;
}

// from_chars's verdict on the token (a leading '+' allowed, as loggers write it).
bool Reference(const std::string& token, double* value) {
  const char* begin = token.data();
  const char* end = begin + token.size();
  if (begin < end && *begin == '+') ++begin;
  const auto result = std::from_chars(begin, end, *value);
  return result.ec == std::errc() && result.ptr == end;
}

void ExpectSame(const std::string& token) {
  double expected = 0.0, got = 0.0;
  const bool expected_ok = Reference(token, &expected);
  const bool got_ok = ParseDecimal(token, &got);
  ASSERT_EQ(got_ok, expected_ok) << "'" << token << "'";
  if (expected_ok) {
    EXPECT_EQ(Bits(got), Bits(expected)) << "'" << token << "': " << got << " vs " << expected;
  }
}

TEST(ParseDecimalTest, RandomPlainDecimalsGiveFromCharsBitForBit) {
  // Up to 17 digits (past the fast path's 15), the point anywhere, either sign: a million
  // tokens, the kind CARMEN and NMEA logs hold and their neighbours at the limits.
  std::mt19937_64 rng(42);
  std::uniform_int_distribution<int> length(1, 17), digit(0, 9), coin(0, 3);
  for (int n = 0; n < 1000000; ++n) {
    std::string token;
    if (coin(rng) == 0) token += '-';
    if (coin(rng) == 0) token = "+" + token;
    const int digits = length(rng);
    std::uniform_int_distribution<int> point(0, digits);
    const int at = coin(rng) == 0 ? -1 : point(rng);
    for (int i = 0; i < digits; ++i) {
      if (i == at) token += '.';
      token += static_cast<char>('0' + digit(rng));
    }
    if (at == digits) token += '.';
    ExpectSame(token);
    if (HasFatalFailure()) return;
  }
}

TEST(ParseDecimalTest, EdgeTokensAgreeWithFromChars) {
  for (const char* token :
       {"0", "-0", "-0.0", "+0", "0.", ".5", "-.5", "1.", "80.000", "-1.5707963267948966",
        "3.141592653589793", "0.017453292519943295", "123456789012345", "1234567890123456",
        "0.0000000000000000000001", "0.00000000000000000000001", "999999999999999.9",
        "1e3", "1E-3", "-2.5e+2", "nan", "inf", "-inf", "", "-", "+", ".", "-.", "+-1", "++1",
        "1.2.3", "1,5", " 1", "1 ", "0x10", "12a", "9007199254740993", "4.9e-324", "1e400"}) {
    ExpectSame(token);
  }
}

}  // namespace
}  // namespace wallcal::io
