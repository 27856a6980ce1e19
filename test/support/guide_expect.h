// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's σ read on from where it stopped against the same logs read whole: the scans read
// before the cut keep the detections of the first read's gates, which moves a σ made of
// thousands of observations by far less than 1 %.

#include <gtest/gtest.h>

#include "guide/prediction.h"

namespace wallcal::testing_support {

// Each σ (x, y, yaw) of `grown` within a fraction `relative` of `whole`'s.
inline void ExpectSameSigma(const guide::Prediction& grown, const guide::Prediction& whole,
                            double relative = 0.01) {
  EXPECT_NEAR(grown.sigma_x_m() / whole.sigma_x_m(), 1.0, relative);
  EXPECT_NEAR(grown.sigma_y_m() / whole.sigma_y_m(), 1.0, relative);
  EXPECT_NEAR(grown.sigma_yaw_rad() / whole.sigma_yaw_rad(), 1.0, relative);
}

}  // namespace wallcal::testing_support
