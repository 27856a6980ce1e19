#pragma once
// Writing files: offsets.yaml, and the simulator's session (CARMEN, NMEA, CSV, session.yaml,
// truth.yaml). The Format* functions only build text; each line formatter returns one line
// without its newline. Angles in the files are degrees where the format says so.

#include <cstdint>
#include <string>
#include <vector>

#include "io/options.h"
#include "io/types.h"

namespace wallcal::io {

// Writes `content` to PATH.tmp-XXXXXX in the same folder, fsyncs it and renames it over `path`,
// so a reader sees the old file or the whole new one. On failure the temporary file is removed
// and InputError naming `path` is thrown; `path` is then untouched.
void WriteFileAtomically(const std::string& path, const std::string& content);

// offsets.yaml with the keys of docs/session-format.md (scanner_mount, seed_002_notation, quality, warnings,
// method, source). The stddev values are the square roots of the covariance diagonal. The
// quality_extra values are written verbatim (a number or a YAML flow collection).
std::string FormatOffsetsYaml(const OffsetsDocument& doc);

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

// CSV with the header "id,x,y,z,code", coordinates with 4 decimals.
std::string FormatSurveyCsv(const std::vector<SurveyPoint>& points);

// session.yaml for `spec`; paths written relative to spec.dir. ReadSession reads it back to the
// same spec.
std::string FormatSessionYaml(const SessionSpec& spec);

// truth.yaml: `truth: {x, y, yaw, yaw_deg}` (the true mount), `seed:` and `simulation:` with
// every SimulationConfig key (names as in ReadSimulationConfig). ReadTruthYaml reads it back.
std::string FormatTruthYaml(const SimulationConfig& config, uint64_t seed);

// A scanner preset in the shipped presets' format (configs/scanners/*.yaml: the keys
// ReadScannerPreset reads, angles in degrees), headed by `comment_lines` as "# " lines.
std::string FormatScannerPreset(const ScannerPreset& preset,
                                const std::vector<std::string>& comment_lines);

// Two upper-case hex digits: XOR of the bytes of `body` (the text between '$' and '*').
std::string NmeaChecksum(const std::string& body);

}  // namespace wallcal::io
