// SPDX-License-Identifier: Apache-2.0
#pragma once
// Writing the YAML files a calibration run produces: offsets.yaml and a measured scanner preset.
// The functions only build text; io/output_file.h writes it safely.

#include <string>
#include <vector>

#include "io/config/session_reader.h"
#include "io/types.h"

namespace wallcal::io {

// offsets.yaml with the keys of docs/session-format.md (scanner_mount, barawid_2007_notation,
// quality, warnings, method, source). The stddev values are the square roots of the covariance
// diagonal. The quality_extra values are written verbatim (a number or a YAML flow collection).
std::string FormatOffsetsYaml(const OffsetsDocument& doc);

// A scanner preset in the shipped presets' format (configs/scanners/*.yaml: the keys
// ReadScannerPreset reads, angles in degrees), headed by `comment_lines` as "# " lines.
std::string FormatScannerPreset(const ScannerPreset& preset,
                                const std::vector<std::string>& comment_lines);

}  // namespace wallcal::io
