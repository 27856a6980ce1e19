// SPDX-License-Identifier: Apache-2.0
#include "io/survey/internal/leica_gsi.h"

#include <array>
#include <cmath>
#include <cstdint>

#include "common/angles.h"
#include "io/survey/internal/line_splitter.h"

namespace wallcal::io {
namespace {

constexpr double kMetresPerFoot = 0.3048;  // international foot

std::string WordName(const GsiWord& word) {
  const std::string index = word.index < 10 ? "0" + std::to_string(word.index)
                                            : std::to_string(word.index);
  return "word " + std::to_string(word.number) + " (index " + index + ")";
}

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// The word's data as an unsigned integer; throws unless all are digits.
int64_t DataDigits(const GsiWord& word, const std::string& name, int line_number) {
  int64_t value = 0;
  for (char c : word.data) {
    if (!IsDigit(c)) {
      throw InputError(Where(name, line_number,
                             WordName(word) + ": its " + std::to_string(word.data.size()) +
                                 " data characters are not all digits; expected a number"));
    }
    value = value * 10 + (c - '0');  // at most 16 digits: fits in int64
  }
  return value;
}

// A point id or code: leading zeros (GSI's padding) and blanks dropped; "0" when only zeros.
std::string TextOf(const GsiWord& word, const char* what, const std::string& name,
                   int line_number) {
  for (char c : word.data) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (u < 0x20 || u >= 0x7f) {
      throw InputError(Where(name, line_number,
                             WordName(word) + ": the " + what +
                                 " has an unprintable or non-ASCII character; expected letters, "
                                 "digits or punctuation"));
    }
  }
  std::string_view text = word.data;
  while (!text.empty() && text.back() == ' ') text.remove_suffix(1);
  bool zeros = false;
  while (!text.empty() && (text.front() == '0' || text.front() == ' ')) {
    zeros = zeros || text.front() == '0';
    text.remove_prefix(1);
  }
  if (text.empty() && zeros) return "0";
  return std::string(text);
}

}  // namespace

bool LooksLikeGsi(std::string_view line) {
  if (!line.empty() && line.front() == '*') line.remove_prefix(1);
  if (line.size() < 7 || !IsDigit(line[0]) || !IsDigit(line[1])) return false;
  for (size_t i = 2; i < 6; ++i) {
    if (!IsDigit(line[i]) && line[i] != '.') return false;
  }
  return line[6] == '+' || line[6] == '-';
}

std::vector<GsiWord> SplitGsiLine(std::string_view line, const std::string& name,
                                  int line_number) {
  size_t position = 0;
  size_t data_length = 8;
  if (!line.empty() && line.front() == '*') {
    data_length = 16;
    position = 1;
  }
  const size_t word_length = 7 + data_length;
  const char* format = data_length == 16 ? "GSI-16" : "GSI-8";
  std::vector<GsiWord> words;
  while (true) {
    while (position < line.size() && line[position] == ' ') ++position;
    if (position >= line.size()) return words;
    GsiWord word;
    word.number = static_cast<int>(words.size()) + 1;
    const std::string label = "word " + std::to_string(word.number);
    const size_t left = line.size() - position;
    if (left < word_length) {
      throw InputError(Where(name, line_number,
                             label + " is cut short: " + std::to_string(left) +
                                 " characters where a " + format + " word has " +
                                 std::to_string(word_length)));
    }
    const std::string_view text = line.substr(position, word_length);
    if (!IsDigit(text[0]) || !IsDigit(text[1])) {
      throw InputError(Where(name, line_number,
                             label + " does not begin with a word index; expected two digits"));
    }
    word.index = (text[0] - '0') * 10 + (text[1] - '0');
    if (text[6] != '+' && text[6] != '-') {
      throw InputError(Where(name, line_number,
                             WordName(word) + " has no sign after its four information "
                                              "characters; expected + or -"));
    }
    word.unit = text[5];
    word.negative = text[6] == '-';
    word.data = text.substr(7);
    position += word_length;
    if (position < line.size() && line[position] != ' ') {
      throw InputError(Where(name, line_number,
                             WordName(word) + " runs on past the " +
                                 std::to_string(word_length) + " characters of a " + format +
                                 " word; expected a blank after each word (GSI-16 lines begin "
                                 "with '*')"));
    }
    words.push_back(word);
  }
}

double GsiValue(const GsiWord& word, GsiQuantity quantity, const std::string& name,
                int line_number) {
  const bool length_unit = word.unit == '0' || word.unit == '1' || word.unit == '6' ||
                           word.unit == '7' || word.unit == '8';
  const bool angle_unit = word.unit >= '2' && word.unit <= '5';
  const char* expected = quantity == GsiQuantity::kLength
                             ? "expected a length unit: 0, 1, 6, 7 or 8 (metres or feet)"
                             : "expected an angle unit: 2 (gon), 3 (degrees), 4 (DDD.MMSS) or "
                               "5 (mil)";
  if (!length_unit && !angle_unit) {
    const std::string found = IsDigit(word.unit) ? std::string("unit ") + word.unit
                                                 : std::string("a unit that is not a digit");
    throw InputError(Where(name, line_number,
                           WordName(word) + " has " + found + ", not a GSI unit; " + expected));
  }
  if ((quantity == GsiQuantity::kLength) != length_unit) {
    throw InputError(Where(name, line_number,
                           WordName(word) + " has " +
                               (length_unit ? "a length" : "an angle") + " unit (" + word.unit +
                               "); " + expected));
  }
  const int64_t digits = DataDigits(word, name, line_number);
  const double sign = word.negative ? -1.0 : 1.0;
  switch (word.unit) {
    case '0':
      return sign * static_cast<double>(digits) / 1e3;
    case '1':
      return sign * static_cast<double>(digits) / 1e3 * kMetresPerFoot;
    case '6':
      return sign * static_cast<double>(digits) / 1e4;
    case '7':
      return sign * static_cast<double>(digits) / 1e4 * kMetresPerFoot;
    case '8':
      return sign * static_cast<double>(digits) / 1e5;
    case '2':
      return sign * static_cast<double>(digits) / 1e5 * (kPi / 200.0);
    case '3':
      return sign * static_cast<double>(digits) / 1e5 * (kPi / 180.0);
    case '5':
      return sign * static_cast<double>(digits) / 1e4 * (kPi / 3200.0);
    default:
      break;
  }
  // '4': DDD.MMSSs, five digits after the degrees: minutes, seconds, tenths of a second.
  const int64_t degrees = digits / 100000;
  const int64_t minutes = digits / 1000 % 100;
  const int64_t seconds = digits / 10 % 100;
  const int64_t tenths = digits % 10;
  if (minutes >= 60 || seconds >= 60) {
    throw InputError(Where(name, line_number,
                           WordName(word) + " is a DDD.MMSS angle with " +
                               (minutes >= 60 ? "minutes" : "seconds") +
                               " of 60 or more; expected 0 to 59"));
  }
  const int64_t tenth_seconds = ((degrees * 60 + minutes) * 60 + seconds) * 10 + tenths;
  return sign * static_cast<double>(tenth_seconds) * (kPi / (180.0 * 36000.0));
}

GsiPosition ReduceGsiPolar(const GsiSetup& setup, const GsiPolar& polar) {
  const double horizontal_m = polar.slope_m * std::sin(polar.v_rad);
  GsiPosition target;
  target.e_m = setup.e_m + horizontal_m * std::sin(polar.hz_rad);
  target.n_m = setup.n_m + horizontal_m * std::cos(polar.hz_rad);
  target.h_m = setup.h_m + setup.instrument_height_m + polar.slope_m * std::cos(polar.v_rad) -
               polar.reflector_height_m;
  return target;
}

GsiFile ParseGsi(std::string_view text, const std::string& name) {
  GsiFile file;
  GsiSetup setup;
  double reflector_height_m = 0.0;
  bool first_word_line = true;
  LineSplitter lines(text);
  std::string_view line;
  while (lines.Next(&line)) {
    const int line_number = lines.line_number();
    while (!line.empty() && line.front() == ' ') line.remove_prefix(1);
    while (!line.empty() && (line.back() == '\r' || line.back() == ' ' || line.back() == '\t')) {
      line.remove_suffix(1);
    }
    if (line.empty()) continue;
    const std::vector<GsiWord> words = SplitGsiLine(line, name, line_number);
    if (first_word_line) {
      file.gsi16 = line.front() == '*';
      first_word_line = false;
    }
    std::array<const GsiWord*, 100> by_index{};
    for (const GsiWord& word : words) {
      if (by_index[static_cast<size_t>(word.index)] != nullptr) {
        throw InputError(Where(name, line_number,
                               WordName(word) + " repeats an index already on this line; "
                                                "expected each word index at most once a line"));
      }
      by_index[static_cast<size_t>(word.index)] = &word;
    }
    const auto has = [&](int index) { return by_index[static_cast<size_t>(index)] != nullptr; };
    const auto length = [&](int index) {
      return GsiValue(*by_index[static_cast<size_t>(index)], GsiQuantity::kLength, name,
                      line_number);
    };
    const auto angle = [&](int index) {
      return GsiValue(*by_index[static_cast<size_t>(index)], GsiQuantity::kAngle, name,
                      line_number);
    };
    // All three words of a triple, or none.
    const auto triple = [&](int first, const char* what) {
      const int count = (has(first) ? 1 : 0) + (has(first + 1) ? 1 : 0) + (has(first + 2) ? 1 : 0);
      if (count != 0 && count != 3) {
        throw InputError(Where(name, line_number,
                               std::string(what) + " with " + std::to_string(count) +
                                   " of its words " + std::to_string(first) + ", " +
                                   std::to_string(first + 1) + " and " +
                                   std::to_string(first + 2) + "; expected all three"));
      }
      return count == 3;
    };
    const bool is_setup = triple(84, "a station set-up");
    const bool has_coordinates = triple(81, "target coordinates");
    const bool has_polar = has(31);
    if (has_polar && (!has(21) || !has(22))) {
      throw InputError(Where(name, line_number,
                             "a slope distance (word 31) without both angles; expected words "
                             "21 (horizontal) and 22 (vertical) with it"));
    }
    if ((is_setup || has_coordinates || has_polar) && !has(11)) {
      throw InputError(Where(name, line_number,
                             "a position without a point id; expected word 11 on the line"));
    }
    // Heights first: a line's own 87/88 apply to its own observation.
    if (has(88)) setup.instrument_height_m = length(88);
    if (has(87)) reflector_height_m = length(87);
    if (is_setup) {
      setup.e_m = length(84);
      setup.n_m = length(85);
      setup.h_m = length(86);
      setup.line = line_number;
      ++file.setups;
    }
    if (!has_coordinates && !has_polar) {
      if (!is_setup) ++(has(11) ? file.angle_only_lines : file.other_lines);
      continue;
    }
    GsiRecord record;
    record.line = line_number;
    record.id = TextOf(*by_index[11], "point id", name, line_number);
    if (record.id.empty()) {
      throw InputError(Where(name, line_number, "the point id (word 11) is blank; expected one"));
    }
    if (has(71)) record.code = TextOf(*by_index[71], "point code", name, line_number);
    if (has_coordinates) {
      record.has_coordinates = true;
      record.coordinates = {length(81), length(82), length(83)};
    }
    if (has_polar) {
      record.has_polar = true;
      record.polar.hz_rad = angle(21);
      record.polar.v_rad = angle(22);
      record.polar.slope_m = length(31);
      record.polar.reflector_height_m = reflector_height_m;
    }
    record.setup = setup;
    file.records.push_back(std::move(record));
  }
  if (file.records.empty()) {
    throw InputError(Where(name, 0,
                           "no point with a position; expected GSI lines with word 11 and "
                           "coordinates (81/82/83) or a polar observation (21/22/31)"));
  }
  return file;
}

std::vector<SurveyPoint> GsiSurveyPoints(const GsiFile& file) {
  std::vector<SurveyPoint> points;
  points.reserve(file.records.size());
  for (const GsiRecord& record : file.records) {
    SurveyPoint point;
    point.id = record.id;
    point.code = record.code;
    point.line = record.line;
    GsiPosition position = record.coordinates;
    if (record.has_coordinates) {
      point.source = SurveySource::kCoordinates;
    } else {
      position = ReduceGsiPolar(record.setup, record.polar);
      point.source = record.setup.line > 0 ? SurveySource::kPolarFromSetup
                                           : SurveySource::kPolarFromOrigin;
    }
    point.x_m = position.e_m;
    point.y_m = position.n_m;
    point.z_m = position.h_m;
    points.push_back(std::move(point));
  }
  return points;
}

}  // namespace wallcal::io
