#pragma once
// The scanner clock offset and the heading delay as the run reports them: the value, its σ,
// and whether the data determine it (pipeline::StreamDelay, docs/time-alignment.md).

#include <Eigen/Core>

#include "pipeline/calibration.h"

namespace wallcal::pipeline {

// The σ (s) a delay would have from the data with the other delay left free, and its own prior.
// time_covariance: the solve's [dt, δh] covariance (s²); priors in s (heading_prior_s 0: the
// heading delay is not estimated); index 0 the clock offset, 1 the heading delay.
double DelayOwnSigma(const Eigen::Matrix2d& time_covariance, double clock_prior_s,
                     double heading_prior_s, int index);

// The reported delay: value and joint σ when estimated; determined when DelayOwnSigma is below
// half the prior's σ.
StreamDelay ClassifyDelay(bool estimated, double value_s, double sigma_s, double prior_sigma_s,
                          double own_sigma_s);

}  // namespace wallcal::pipeline
