// SPDX-License-Identifier: Apache-2.0
#pragma once
// The attitude sentences of an NMEA log, for the NMEA reader (io/text/nmea_reader.cc): the
// fields of $PASHR and $PTNL,AVR as the vehicle's roll and pitch (io::AttitudeSample's
// conventions: roll positive right side down, pitch positive nose up). Private to io/.
//
// $PASHR (OxTS RT, Applanix POS, Hemisphere; gpsd's NMEA.adoc "PASHR - RT300 proprietary roll
// and pitch sentence"; Hemisphere's field description):
//   $PASHR,hhmmss.sss,hhh.hh,T,rrr.rr,ppp.pp,xxx.xx,a.aaa,b.bbb,c.ccc,d,e*hh
//   1 UTC time, 2 true heading (deg), 3 'T', 4 roll (deg), 5 pitch (deg), 6 heave (m),
//   7 roll σ (deg), 8 pitch σ (deg), 9 heading σ (deg), 10 aiding status / GNSS quality,
//   11 IMU status.
//   Signs: roll positive with the right (starboard) side down, pitch positive with the nose (bow)
//   up (nmea-kit's PASHR: "negative = port", "negative = bow down"; the INS navigation frame x
//   forward, y right, z down), which are AttitudeSample's, so the degrees are taken as they
//   are. The σ fields are 1σ in degrees; a σ of 0 is read as not given. Fields 10 and 11 mean
//   different things to different makers (Hemisphere: position quality; OxTS, Applanix: aiding
//   and IMU status) and are not used. The heading is not a heading sample. Ashtech's other
//   $PASHR sentences ($PASHR,ATT, $PASHR,POS, ...: a word in field 1) are other sentences.
//
// $PTNL,AVR (Trimble, "Time, yaw, tilt/roll, range for moving baseline RTK"; Trimble OEM
// receiver help, NMEA-0183 message PTNL,AVR):
//   $PTNL,AVR,hhmmss.ss,+yyy.yyyy,Yaw,+t.tttt,Tilt,+r.rrrr,Roll,rr.rrr,q,p.p,ss*hh
//   1 UTC of the vector fix, 2 yaw (deg), 3 "Yaw", 4 tilt (deg), 5 "Tilt", 6 roll (deg),
//   7 "Roll", 8 range between the antennas (m), 9 quality (0 invalid, 1 autonomous, 2 RTK
//   float, 3 RTK fixed, 4 DGPS), 10 PDOP, 11 satellites.
//   The angles are those of the vector between the two antennas: a receiver whose vector lies
//   along the vehicle (Trimble's vector orientation "Pitch") fills Tilt, one whose vector lies
//   across it ("Roll") fills Roll; one sentence gives one of them, the other axis is NaN in the
//   sample. Convention adopted: Tilt is the pitch, positive nose up (the vector pointing
//   forward, its head higher); Roll is the roll, positive right side down (the receiver's
//   vector direction set so); a receiver set the other way round gives the opposite sign, which
//   `inspect --dump attitude` on a known slope shows. Only RTK-fixed vectors (quality 3) are
//   used: a float or code vector over a baseline of a metre gives its angles to degrees.

#include <optional>

#include "io/text/internal/nmea_sentence.h"
#include "io/types.h"

namespace wallcal::io::nmea {

// What one attitude sentence gave: typed, so the reader words the skip and no branch reads text.
enum class AttitudeParse {
  kSample,         // *sample's roll, pitch and σ filled (its stamp and line are the caller's)
  kOtherSentence,  // the address is an attitude sentence's but this is another ($PASHR,ATT)
  kEmptyField,     // a required field missing or empty (no roll or pitch, no AVR quality)
  kBadField,       // not a number, a negative σ, an AVR value without its label
  kOutOfRange,     // |roll| or |pitch| beyond io::kMaxVehicleTiltRad (30°)
  kNoFix,          // AVR quality 0: no vector
  kNotRtkFixed,    // AVR quality other than 3 (RTK fixed)
};

// A $PASHR (fields[0] == "PASHR") as roll, pitch and their σ (NaN when not given). *tod_s: the
// sentence's UTC time of day, nullopt when its time field is empty.
AttitudeParse ParsePashr(const Fields& fields, AttitudeSample* sample,
                         std::optional<double>* tod_s);

// A $PTNL sentence (fields[0] == "PTNL"): kOtherSentence unless fields[1] is "AVR"; then the
// tilt as pitch and the roll as roll (NaN when the sentence does not give it), σ NaN. *tod_s as
// for ParsePashr.
AttitudeParse ParsePtnlAvr(const Fields& fields, AttitudeSample* sample,
                           std::optional<double>* tod_s);

}  // namespace wallcal::io::nmea
