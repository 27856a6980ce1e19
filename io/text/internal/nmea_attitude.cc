// SPDX-License-Identifier: Apache-2.0
// The attitude sentences of an NMEA log (io/text/internal/nmea_attitude.h).

#include "io/text/internal/nmea_attitude.h"

#include <cmath>

#include "common/angles.h"

namespace wallcal::io::nmea {
namespace {

bool Present(const Fields& fields, size_t index) {
  return index < fields.size() && !fields[index].empty();
}

// An optional number field: absent is fine, present must be a finite number.
bool OptionalNumber(const Fields& fields, size_t index, double* value) {
  return !Present(fields, index) || ParseDouble(fields[index], value);
}

// An optional σ field in degrees: absent or 0 -> NaN (not given); negative -> false.
bool OptionalSigma(const Fields& fields, size_t index, double* sigma_rad) {
  *sigma_rad = kNaN;
  if (!Present(fields, index)) return true;
  double sigma_deg = 0.0;
  if (!ParseDouble(fields[index], &sigma_deg) || sigma_deg < 0.0) return false;
  if (sigma_deg > 0.0) *sigma_rad = sigma_deg * kDegToRad;
  return true;
}

// The time field at `index`: empty -> nullopt; malformed -> false.
bool OptionalTime(const Fields& fields, size_t index, std::optional<double>* tod_s) {
  tod_s->reset();
  if (!Present(fields, index)) return true;
  double tod = 0.0;
  if (!ParseTimeOfDay(fields[index], &tod)) return false;
  *tod_s = tod;
  return true;
}

// Within what a vehicle stands on (io::kMaxVehicleTiltRad, inclusive).
bool InRange(double angle_deg) { return std::abs(angle_deg * kDegToRad) <= kMaxVehicleTiltRad; }

}  // namespace

AttitudeParse ParsePashr(const Fields& fields, AttitudeSample* sample,
                         std::optional<double>* tod_s) {
  // Ashtech's own $PASHR sentences carry a word in field 1 ("ATT", "POS"); the attitude
  // sentence a time (gpsd tells them apart the same way).
  if (Present(fields, 1) && (fields[1][0] < '0' || fields[1][0] > '9')) {
    return AttitudeParse::kOtherSentence;
  }
  if (!Present(fields, 4) || !Present(fields, 5)) return AttitudeParse::kEmptyField;
  double roll_deg = 0.0, pitch_deg = 0.0, unused = 0.0;
  if (!ParseDouble(fields[4], &roll_deg) || !ParseDouble(fields[5], &pitch_deg) ||
      !OptionalTime(fields, 1, tod_s) || !OptionalNumber(fields, 2, &unused) ||
      !OptionalNumber(fields, 6, &unused) || !OptionalSigma(fields, 7, &sample->roll_sigma_rad) ||
      !OptionalSigma(fields, 8, &sample->pitch_sigma_rad) || !OptionalSigma(fields, 9, &unused)) {
    return AttitudeParse::kBadField;
  }
  if (!InRange(roll_deg) || !InRange(pitch_deg)) return AttitudeParse::kOutOfRange;
  sample->roll_rad = roll_deg * kDegToRad;
  sample->pitch_rad = pitch_deg * kDegToRad;
  return AttitudeParse::kSample;
}

AttitudeParse ParsePtnlAvr(const Fields& fields, AttitudeSample* sample,
                           std::optional<double>* tod_s) {
  if (fields.size() < 2 || fields[1] != "AVR") return AttitudeParse::kOtherSentence;
  // Fields after the address "PTNL": [1] AVR, [2] time, [3] yaw, [4] "Yaw", [5] tilt, [6] "Tilt",
  // [7] roll, [8] "Roll", [9] range, [10] quality, [11] PDOP, [12] satellites.
  const bool tilt = Present(fields, 5), roll = Present(fields, 7);
  if (!tilt && !roll) return AttitudeParse::kEmptyField;
  if (!Present(fields, 10)) return AttitudeParse::kEmptyField;
  double tilt_deg = kNaN, roll_deg = kNaN, unused = 0.0;
  int quality = 0, satellites = 0;
  const auto labelled = [&fields](size_t index, const char* label) {
    return index < fields.size() && fields[index] == label;
  };
  const bool labels_ok = (!tilt || labelled(6, "Tilt")) && (!roll || labelled(8, "Roll"));
  if (!labels_ok || (tilt && !ParseDouble(fields[5], &tilt_deg)) ||
      (roll && !ParseDouble(fields[7], &roll_deg)) || !OptionalTime(fields, 2, tod_s) ||
      !OptionalNumber(fields, 3, &unused) || !OptionalNumber(fields, 9, &unused) ||
      !ParseInt(fields[10], &quality) || !OptionalNumber(fields, 11, &unused) ||
      (Present(fields, 12) && !ParseInt(fields[12], &satellites))) {
    return AttitudeParse::kBadField;
  }
  if (quality == 0) return AttitudeParse::kNoFix;
  if (quality != 3) return AttitudeParse::kNotRtkFixed;
  if ((tilt && !InRange(tilt_deg)) || (roll && !InRange(roll_deg))) {
    return AttitudeParse::kOutOfRange;
  }
  sample->pitch_rad = tilt ? tilt_deg * kDegToRad : kNaN;
  sample->roll_rad = roll ? roll_deg * kDegToRad : kNaN;
  sample->roll_sigma_rad = sample->pitch_sigma_rad = kNaN;
  return AttitudeParse::kSample;
}

}  // namespace wallcal::io::nmea
