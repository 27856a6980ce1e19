#pragma once
// offsets.yaml's content for a calibration result (io/writers.h formats and writes it).

#include "io/types.h"
#include "pipeline/calibration.h"

namespace wallcal::outputs {

// The document for a usable result: the mount, its covariance and the quality keys.
io::OffsetsDocument MakeOffsetsDocument(const pipeline::CalibrationResult& result);

}  // namespace wallcal::outputs
