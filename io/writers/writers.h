// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writing the simulator's session as text logs (CARMEN, NMEA, survey CSV, session.yaml; the
// simulator writes truth.yaml itself, sim/simulated_session.cc). The Format* functions only build text; each line formatter returns one line
// without its newline. Angles in the files are degrees where the format says so.

#include <cstdint>
#include <string>
#include <vector>

#include "io/config/session_reader.h"
#include "io/types.h"

namespace wallcal::io {

// "RAWLASER1 0 start fov res maxrange 0.01 0 n r1 .. rn 0 ts wallcal-sim ts"
// with fov = step * (n - 1), ranges in mm resolution, ts = scan.stamp_s.
std::string FormatCarmenRawlaser(const ScanRecord& scan);

// "<stamp> $GNGGA,..." : logger-time prefix = fix.stamp_s, UTC field from stamp_s as UNIX time,
// latitude/longitude with 7 decimals of minutes, altitude = height_m, geoid separation 0.
std::string FormatGgaLine(const GnssFix& fix);

// "<stamp> $GNGST,time,rms,smaj,smin,orient,sigma_lat,sigma_lon,sigma_alt*hh" from the fix's σ.
// sigma_alt is written as twice the larger horizontal σ (wallcal does not read it).
std::string FormatGstLine(const GnssFix& fix);

// "<stamp> $HEHDT,ddd.dddd,T*hh" (degrees clockwise from north, 4 decimals).
std::string FormatHdtLine(double stamp_s, double heading_rad);

// The attitude sentences (io/text/internal/nmea_attitude.h), logger-stamped with
// sample.stamp_s, the UTC field from it as UNIX time. Angles in degrees with 4 decimals (σ too);
// a NaN roll, pitch, σ or heading is an empty field. heading_rad: clockwise from north.
// "<stamp> $PASHR,hhmmss.ss,hhh.hh,T,±r.rrrr,±p.pppp,0.00,σr,σp,,1,0*hh" (heave 0, no heading σ).
std::string FormatPashrLine(const AttitudeSample& sample, double heading_rad);
// "<stamp> $PTNL,AVR,hhmmss.ss,+yyy.yyyy,Yaw,±t.tttt,Tilt,±r.rrrr,Roll,1.000,3,1.5,12*hh": the
// heading as yaw, the pitch as tilt and the roll as roll (a receiver gives one of the two; the
// simulator gives both), quality 3 (RTK fixed), a 1 m baseline.
std::string FormatAvrLine(const AttitudeSample& sample, double heading_rad);

// CSV with the header "id,x,y,z,code", coordinates with 4 decimals.
std::string FormatSurveyCsv(const std::vector<SurveyPoint>& points);

// A rover's export: the header "Name,Latitude,Longitude,Ellipsoidal height,Code", lat_deg and
// lon_deg with 9 decimals (0.1 mm), z_m (the ellipsoidal height) with 4.
std::string FormatRoverSurveyCsv(const std::vector<SurveyPoint>& points);

// session.yaml for `spec`; paths written relative to spec.dir; a scanner's z_m when set and its
// pitch_deg and roll_deg when its tilt is given. ReadSession reads it back to the same spec.
std::string FormatSessionYaml(const SessionSpec& spec);

// Two upper-case hex digits: XOR of the bytes of `body` (the text between '$' and '*').
std::string NmeaChecksum(const std::string& body);

}  // namespace wallcal::io
