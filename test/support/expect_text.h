// SPDX-License-Identifier: Apache-2.0
#pragma once
// Expectations on what a program printed or a reader said: each part of a message checked on its
// own (a failure names the part and shows the whole text), so a test lists the parts it needs
// instead of one EXPECT per part.

#include <gtest/gtest.h>

#include <initializer_list>
#include <string>

namespace wallcal::testing_support {

// Expects `text` to contain every one of `parts`.
inline void ExpectContains(const std::string& text, std::initializer_list<std::string> parts) {
  for (const std::string& part : parts) {
    EXPECT_NE(text.find(part), std::string::npos) << "missing \"" << part << "\" in:\n" << text;
  }
}

// Expects `text` to contain none of `parts`.
inline void ExpectLacks(const std::string& text, std::initializer_list<std::string> parts) {
  for (const std::string& part : parts) {
    EXPECT_EQ(text.find(part), std::string::npos) << "unexpected \"" << part << "\" in:\n" << text;
  }
}

// The message of the `Error` that `call()` throws, "" when it throws none.
template <class Error, class Call>
std::string ThrownMessage(Call&& call) {
  try {
    call();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

// The same, and a test failure when `call()` throws none.
template <class Error, class Call>
std::string MessageOf(Call&& call) {
  const std::string message = ThrownMessage<Error>(call);
  if (message.empty()) ADD_FAILURE() << "no exception";
  return message;
}

// For each {input, part} of `cases`: `read(input)` throws an `Error` whose message contains
// `part` (a bad file's text and what its message must say).
template <class Error, class Cases, class Read>
void ExpectEachThrows(const Cases& cases, Read&& read) {
  for (const auto& [input, part] : cases) {
    SCOPED_TRACE(input);
    ExpectContains(MessageOf<Error>([&read, input = input] { read(input); }), {part});
  }
}

// Expects a program to have exited with `expected_status` (`status` is what it exited with) and
// `text`, what it printed, to contain every one of `parts`.
inline void ExpectExitSaying(int status, int expected_status, const std::string& text,
                             std::initializer_list<std::string> parts) {
  EXPECT_EQ(status, expected_status) << text;
  ExpectContains(text, parts);
}

}  // namespace wallcal::testing_support
