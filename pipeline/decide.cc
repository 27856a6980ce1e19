// SPDX-License-Identifier: Apache-2.0
// The decide step of a calibration run (pipeline/internal/steps.h): the verdict, the change
// since the previous calibration and the provenance.

#include "common/format.h"
#include "io/version.h"
#include "pipeline/internal/steps.h"
#include "pipeline/several_verdict.h"

namespace wallcal::pipeline {

DecideResult Decide(const CalibrateRequest& request, const CalibrationResult& so_far,
                    const RunState& state) {
  DecideResult step;
  if (state.previous && so_far.solve.estimate.usable) {
    step.change = CompareMounts(so_far.solve.estimate, *state.previous);
  }
  step.decision = DecideCalibration(so_far, step.change);

  Provenance& p = step.provenance;
  p.created_utc = NowUtcIso8601();
  p.tool_version = io::kToolVersion;
  p.command_line = request.command_line;
  if (request.preview) return step;
  p.inputs = state.digests.valid() ? state.digests.get()
                                   : DigestInputs(so_far.loaded.session, request.config_path,
                                                  so_far.loaded.preset.file, request.compare_path);
  return step;
}

}  // namespace wallcal::pipeline
