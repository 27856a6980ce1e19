// SPDX-License-Identifier: Apache-2.0
// The parts of an NMEA 0183 sentence (io/text/internal/nmea_sentence.h).

#include "io/text/internal/nmea_sentence.h"

#include <charconv>
#include <cmath>

#include "io/internal/decimal.h"

namespace wallcal::io::nmea {
namespace {

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

bool AllDigits(std::string_view text) {
  for (char c : text) {
    if (c < '0' || c > '9') return false;
  }
  return !text.empty();
}

// Days since 1970-01-01 of a proleptic Gregorian date (H. Hinnant's days_from_civil).
int64_t DaysFromCivil(int year, int month, int day) {
  year -= month <= 2 ? 1 : 0;
  const int64_t era = (year >= 0 ? year : year - 399) / 400;
  const int64_t year_of_era = year - era * 400;
  const int64_t day_of_year = (153 * (month + (month > 2 ? -3 : 9)) + 2) / 5 + day - 1;
  const int64_t day_of_era = year_of_era * 365 + year_of_era / 4 - year_of_era / 100 + day_of_year;
  return era * 146097 + day_of_era - 719468;
}

bool ValidDate(int year, int month, int day) {
  return year >= 1980 && year <= 2200 && month >= 1 && month <= 12 && day >= 1 && day <= 31;
}

}  // namespace

// Finds the sentence in a line: the first '$' whose text up to the next '*' matches the two hex
// digits after it. Receivers interleave binary messages with NMEA, so bytes before a '$' (or a
// '$' inside binary data) are not trusted. On failure *reason says why.
bool ExtractSentence(std::string_view text, std::string_view* body, const char** reason,
                     SkipSeverity* severity) {
  *reason = "not NMEA";  // no '$' at all: comments, other protocols
  if (severity != nullptr) *severity = SkipSeverity::kInformational;
  bool saw_checksum = false;
  for (size_t dollar = text.find('$'); dollar != std::string_view::npos;
       dollar = text.find('$', dollar + 1)) {
    const size_t star = text.find('*', dollar + 1);
    if (star == std::string_view::npos || star + 2 >= text.size() || HexValue(text[star + 1]) < 0 ||
        HexValue(text[star + 2]) < 0) {
      if (!saw_checksum) *reason = "no checksum";
      if (severity != nullptr) *severity = SkipSeverity::kProblem;
      continue;
    }
    saw_checksum = true;
    *reason = "bad checksum";
    if (severity != nullptr) *severity = SkipSeverity::kProblem;
    unsigned sum = 0;
    for (size_t i = dollar + 1; i < star; ++i) sum ^= static_cast<unsigned char>(text[i]);
    const unsigned expected =
        static_cast<unsigned>(HexValue(text[star + 1]) * 16 + HexValue(text[star + 2]));
    if (sum == expected) {
      *body = text.substr(dollar + 1, star - dollar - 1);
      return true;
    }
  }
  return false;
}

void Split(std::string_view body, Fields* fields) {
  fields->clear();
  size_t start = 0;
  while (true) {
    const size_t comma = body.find(',', start);
    if (comma == std::string_view::npos) {
      fields->push_back(body.substr(start));
      return;
    }
    fields->push_back(body.substr(start, comma - start));
    start = comma + 1;
  }
}

// "GPGGA" -> "GGA"; proprietary sentences ("PSTI", "PASHR") keep their whole address.
std::string_view SentenceType(std::string_view address) {
  if (!address.empty() && address[0] == 'P') return address;
  return address.size() >= 5 ? address.substr(address.size() - 3) : address;
}

bool ParseDouble(std::string_view token, double* value) {
  return ParseDecimal(token, value) && std::isfinite(*value);
}

bool ParseInt(std::string_view token, int* value) {
  const auto result = std::from_chars(token.data(), token.data() + token.size(), *value);
  return result.ec == std::errc() && result.ptr == token.data() + token.size();
}

// hhmmss[.sss] -> seconds of the UTC day.
bool ParseTimeOfDay(std::string_view field, double* tod_s) {
  if (field.size() < 6 || !AllDigits(field.substr(0, 6))) return false;
  const int hours = (field[0] - '0') * 10 + (field[1] - '0');
  const int minutes = (field[2] - '0') * 10 + (field[3] - '0');
  double seconds = 0.0;
  if (!ParseDouble(field.substr(4), &seconds)) return false;
  if (hours > 23 || minutes > 59 || seconds < 0.0 || seconds >= 61.0) return false;
  *tod_s = hours * 3600.0 + minutes * 60.0 + seconds;
  return true;
}

// The date of an RMC (field 9, ddmmyy) or ZDA (fields 2-4: dd, mm, yyyy) sentence.
std::optional<int64_t> SentenceDate(std::string_view type, const Fields& fields) {
  int day = 0, month = 0, year = 0;
  if (type == "RMC") {
    if (fields.size() < 10 || fields[9].size() != 6 || !AllDigits(fields[9])) return std::nullopt;
    const std::string_view d = fields[9];
    day = (d[0] - '0') * 10 + (d[1] - '0');
    month = (d[2] - '0') * 10 + (d[3] - '0');
    const int yy = (d[4] - '0') * 10 + (d[5] - '0');
    year = yy < 80 ? 2000 + yy : 1900 + yy;
  } else if (type == "ZDA") {
    if (fields.size() < 5 || !ParseInt(fields[2], &day) || !ParseInt(fields[3], &month) ||
        !ParseInt(fields[4], &year)) {
      return std::nullopt;
    }
  } else {
    return std::nullopt;
  }
  if (!ValidDate(year, month, day)) return std::nullopt;
  return DaysFromCivil(year, month, day);
}

// Strips the logger-time prefix "<seconds> " if the line has one.
std::optional<double> TakePrefix(std::string_view* line) {
  size_t i = 0;
  while (i < line->size() && (*line)[i] >= '0' && (*line)[i] <= '9') ++i;
  if (i == 0) return std::nullopt;
  if (i < line->size() && (*line)[i] == '.') {
    ++i;
    while (i < line->size() && (*line)[i] >= '0' && (*line)[i] <= '9') ++i;
  }
  if (i >= line->size() || ((*line)[i] != ' ' && (*line)[i] != '\t')) return std::nullopt;
  double stamp_s = 0.0;
  if (!ParseDouble(line->substr(0, i), &stamp_s)) return std::nullopt;
  size_t rest = i;
  while (rest < line->size() && ((*line)[rest] == ' ' || (*line)[rest] == '\t')) ++rest;
  *line = line->substr(rest);
  return stamp_s;
}

// Latitude "ddmm.mmmm" + hemisphere -> degrees; false if malformed or out of range.
bool ParseLatLon(std::string_view value, std::string_view hemisphere, bool latitude, double* deg) {
  double raw = 0.0;
  if (!ParseDouble(value, &raw) || raw < 0.0) return false;
  const double whole_deg = std::floor(raw / 100.0);
  const double minutes = raw - whole_deg * 100.0;
  if (minutes >= 60.0) return false;
  double angle = whole_deg + minutes / 60.0;
  if (hemisphere.size() != 1) return false;
  const char h = hemisphere[0];
  if (latitude ? (h != 'N' && h != 'S') : (h != 'E' && h != 'W')) return false;
  if (h == 'S' || h == 'W') angle = -angle;
  *deg = angle;
  return true;
}

std::optional<int64_t> LineDate(std::string_view text) {
  TakePrefix(&text);
  std::string_view body;
  const char* reason = nullptr;
  if (!ExtractSentence(text, &body, &reason)) return std::nullopt;
  Fields fields;
  Split(body, &fields);
  return SentenceDate(SentenceType(fields[0]), fields);
}

}  // namespace wallcal::io::nmea
