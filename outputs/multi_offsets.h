// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a multi-scanner run gives people and navigation stacks (pipeline/multi_scanner.h):
// offsets.yaml with `scanner_mounts:`, `relative_mounts:` and the joint covariance, the summary,
// and the emitted transforms as one tree (base_link -> gnss_antenna -> each scanner).

#include <string>

#include "outputs/emit.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::outputs {

// offsets.yaml of a multi-scanner run that is not kFailed (docs/session-format.md):
//   verdict:          the run's (pipeline::DecideSeveral)
//   scanner_mounts:   one map per calibrated scanner, in session.yaml's order: id,
//                     parent_frame (frames.parent), child_frame (the scanner's frame), x, y (m),
//                     yaw (rad), yaw_deg, stddev {x, y, yaw_deg}, covariance (3x3 row-major),
//                     time_offset_s, quality {...}, verdict {...}, change_since_previous {...}
//                     (--compare, when the file has the scanner)
//   relative_mounts:  for each pair (from listed earlier, to later): the pose of `to` in the
//                     frame of `from`, with stddev and covariance from the joint covariance,
//                     verdict {...} and change_since_previous {...} (as above)
//   joint_covariance: {order: [id.x, id.y, id.yaw, ...], matrix: [[...], ...]} (m, rad)
//   refused:          the scanners left out (--allow-partial), with the reason
//   compared_with:    --compare: the file, the scanners in one of the two files only
//   method, source (the provenance of every input, each file once).
std::string FormatSeveralOffsetsYaml(const pipeline::SeveralScannersResult& several,
                                     const EmitFrames& frames = EmitFrames());

// The summary: the run's verdict, each scanner's mount with σ and verdict (with the reasons and
// the change since --compare's file), the relative transforms likewise, the refused scanners
// and the scanners found in one file only (ends with a newline).
std::string FormatSeveralSummary(const pipeline::SeveralScannersResult& several);

// --emit for several scanners: one tree, base -> frames.parent (with antenna_in_base) and
// frames.parent -> each calibrated scanner's frame (z from its z_m, 0 and a note when unknown).
// The JSON is {"method", "parent_frame", "scanners": [{"id", "child_frame", "mount", "z_known",
// "sigma", "covariance", "verdict"}...], "relative": [{"from", "to", x_m, y_m, yaw_rad, yaw_deg,
// "sigma", "verdict"}], "verdict", "base_link"}: each verdict is offsets.yaml's
// ({"verdict", "reasons"}, outputs::JsonDecision), the last the run's. Frame names must satisfy IsValidFrameName (std::invalid_argument otherwise).
std::string FormatSeveralEmit(EmitFormat format, const pipeline::SeveralScannersResult& several,
                              const EmitFrames& frames);

}  // namespace wallcal::outputs
