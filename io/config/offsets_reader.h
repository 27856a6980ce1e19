// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading an earlier offsets.yaml (written by io/config/config_writer.h FormatOffsetsYaml) for
// `calibrate --compare`: the mount, its covariance and when it was made.

#include <string>

#include "io/types.h"

namespace wallcal::io {

// Reads `scanner_mount: {x, y, yaw, covariance}` and `source.created_utc` (optional). Throws
// InputError ("file:line: ...") when the file is missing, is not YAML, or has no finite
// scanner_mount x, y and yaw. A covariance that is null or absent leaves sigma_known false.
PreviousOffsets ReadPreviousOffsets(const std::string& file);

}  // namespace wallcal::io
