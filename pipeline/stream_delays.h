#pragma once
// The scanner clock offset and the heading delay as the run reports them: the value, its σ,
// and whether the data determine it (pipeline::StreamDelay, docs/time-alignment.md).

#include "pipeline/calibration.h"
#include "solvers/time_block.h"

namespace wallcal::pipeline {

// The reported delay: value and joint σ when estimated; determined when DelayOwnSigma is below
// half the prior's σ (solvers::DelayOwnSigma).
StreamDelay ClassifyDelay(bool estimated, double value_s, double sigma_s, double prior_sigma_s,
                          double own_sigma_s);

}  // namespace wallcal::pipeline
