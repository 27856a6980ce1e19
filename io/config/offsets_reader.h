// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading an earlier offsets.yaml (written by io/config/config_writer.h FormatOffsetsYaml) for
// `calibrate --compare`: the mount, its covariance and when it was made; for a session with
// several scanners, each scanner's mount and each relative transform.

#include <string>

#include "io/types.h"

namespace wallcal::io {

// Reads `scanner_mount: {x, y, yaw, covariance}` and `source.created_utc` (optional). Throws
// InputError ("file:line: ...") when the file is missing, is not YAML, or has no finite
// scanner_mount x, y and yaw. A covariance that is null or absent leaves sigma_known false.
// A file with `scanner_mounts:` (several scanners) is an InputError saying so.
PreviousOffsets ReadPreviousOffsets(const std::string& file);

// Reads either form: `scanner_mounts:` (each {id, x, y, yaw, covariance}) with
// `relative_mounts:` (each {from, to, x, y, yaw, covariance}; optional), or one
// `scanner_mount:` (its child_frame as the id). Throws InputError ("file:line: ...") when the
// file is missing, is not YAML, has neither, or an entry lacks a finite x, y, yaw or an id.
PreviousSeveralOffsets ReadPreviousSeveralOffsets(const std::string& file);

}  // namespace wallcal::io
