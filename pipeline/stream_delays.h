// SPDX-License-Identifier: Apache-2.0
#pragma once
// The scanner clock offset and the heading delay as the run reports them: the value, its σ,
// and whether the data determine it (pipeline::StreamDelay, docs/time-alignment.md).

#include "pipeline/calibration.h"
#include "solvers/time_block.h"

namespace wallcal::pipeline {

// The reported delay: value and joint σ when estimated, and the status: `determined` is
// solvers::DelayDetermined's verdict (the data with the other delay free shrink its prior by
// half), so the report and the clock rounds judge a delay by the same rule.
StreamDelay ClassifyDelay(bool estimated, double value_s, double sigma_s, double prior_sigma_s,
                          bool determined);

}  // namespace wallcal::pipeline
