// SPDX-License-Identifier: Apache-2.0
#pragma once
// The parts of an NMEA 0183 sentence, for the NMEA reader (io/text/nmea_reader.cc): the checked
// sentence in a line, its fields, times, dates and coordinates. Private to io/.

#include <cstdint>
#include <optional>
#include <string_view>
#include <vector>

#include "io/types.h"

namespace wallcal::io::nmea {

inline constexpr double kSecondsPerDay = 86400.0;

using Fields = std::vector<std::string_view>;

// Finds the sentence in a line: the first '$' whose text up to the next '*' matches the two hex
// digits after it (*body: between them). On failure *reason says why and *severity (when not
// null) how much it matters.
bool ExtractSentence(std::string_view text, std::string_view* body, const char** reason,
                     SkipSeverity* severity = nullptr);

// The comma-separated fields of a sentence body; fields[0] is the address ("GPGGA").
void Split(std::string_view body, Fields* fields);

// "GPGGA" -> "GGA"; proprietary sentences ("PSTI", "PASHR") keep their whole address.
std::string_view SentenceType(std::string_view address);

// The whole token as a finite double / an int; false when it is not one.
bool ParseDouble(std::string_view token, double* value);
bool ParseInt(std::string_view token, int* value);

// hhmmss[.sss] -> seconds of the UTC day, in [0, 86401).
bool ParseTimeOfDay(std::string_view field, double* tod_s);

// The date of an RMC (field 9, ddmmyy) or ZDA (fields 2-4: dd, mm, yyyy) sentence, in days
// since 1970-01-01; nullopt for other sentences and invalid dates.
std::optional<int64_t> SentenceDate(std::string_view type, const Fields& fields);

// Strips the logger-time prefix "<seconds> " from *line if it has one and returns it (s).
std::optional<double> TakePrefix(std::string_view* line);

// Latitude or longitude "dddmm.mmmm" + hemisphere letter -> degrees (south and west negative);
// false if malformed (minutes >= 60, a wrong letter).
bool ParseLatLon(std::string_view value, std::string_view hemisphere, bool latitude, double* deg);

// The RMC/ZDA date of one line (a logger-time prefix allowed), days since 1970-01-01; nullopt
// when the line holds no checked RMC/ZDA sentence with a valid date.
std::optional<int64_t> LineDate(std::string_view text);

}  // namespace wallcal::io::nmea
