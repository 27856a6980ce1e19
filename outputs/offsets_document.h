// SPDX-License-Identifier: Apache-2.0
#pragma once
// offsets.yaml's content for a calibration result (io/writers.h formats and writes it).

#include "io/types.h"
#include "outputs/emit.h"
#include "pipeline/calibration.h"

namespace wallcal::outputs {

// The document for a usable result: the frames, the mount, its covariance (or none), the
// quality keys, the verdict, the error budget, the change since the previous calibration and
// the provenance (time, tool, command line, SHA-256 of every input).
io::OffsetsDocument MakeOffsetsDocument(const pipeline::CalibrationResult& result,
                                        const EmitFrames& frames = EmitFrames());

// "{verdict: ACCEPT, reasons: [...]}" and the like, shared with the report's tests.
std::string VerdictYaml(const pipeline::CalibrationResult& result);
std::string DecisionYaml(const pipeline::Decision& decision);
std::string BudgetYaml(const analysis::ErrorBudget& budget);
std::string ChangeYaml(const pipeline::Change& change);

}  // namespace wallcal::outputs
