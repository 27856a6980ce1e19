// SPDX-License-Identifier: Apache-2.0
#include "calib/white_noise.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "common/angles.h"

namespace wallcal::calib {
namespace {

constexpr double kGnssWhiteM = 0.003;

// Ten stops of 4 s at 20 Hz (800 samples, 790 degrees of freedom) at headings around ±π (the
// wrap inside a stop must not count), turns of 30° between them at 20°/s.
struct Log {
  std::vector<PositionSample> positions;
  std::vector<YawSample> yaws;
  std::vector<Dwell> dwells;
};

Log MakeLog(double sigma_rad, std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, sigma_rad);
  std::normal_distribution<double> position(0.0, kGnssWhiteM);
  Log log;
  double t_s = 0.0, yaw_rad = kPi - 0.2;
  for (int stop = 0; stop < 10; ++stop) {
    Dwell dwell;
    dwell.start_s = t_s;
    for (int k = 0; k < 80; ++k, t_s += 0.05) {
      log.yaws.push_back({t_s, WrapAngle(yaw_rad + normal(*rng))});
      // 10 Hz GNSS, white 3 mm per axis on a drift of 2 mm/s (the RTK error's slow part).
      if (k % 2 == 0) {
        const Eigen::Vector2d p_m(5.0 * stop + 0.002 * t_s + position(*rng),
                                  1.0 - 0.002 * t_s + position(*rng));
        log.positions.push_back({t_s, p_m, 0.0});
      }
    }
    dwell.end_s = t_s - 0.05;
    log.dwells.push_back(dwell);
    for (int k = 0; k < 30; ++k, t_s += 0.05) {  // the turn: 1.5 s at 20°/s
      yaw_rad += 20.0 * kDegToRad * 0.05;
      log.yaws.push_back({t_s, WrapAngle(yaw_rad + normal(*rng))});
    }
  }
  return log;
}

TEST(WhiteNoiseTest, MeasuresTheHeadingNoiseAtTheStopsOnly) {
  std::mt19937 rng(3);
  const double sigma_rad = 0.05 * kDegToRad;
  const Log log = MakeLog(sigma_rad, &rng);
  const MeasuredWhiteNoise noise = MeasureWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_EQ(noise.heading_degrees_of_freedom, 790);
  // Relative standard error 1/√(2·790) = 2.5 %; four of them.
  EXPECT_NEAR(noise.heading_sigma_rad / sigma_rad, 1.0, 0.10);
  // 40 positions a stop: 2 × 38 degrees of freedom each, 760 in all (2.6 %; four of them).
  EXPECT_EQ(noise.gnss_degrees_of_freedom, 760);
  EXPECT_NEAR(noise.gnss_white_sigma_m / kGnssWhiteM, 1.0, 0.11);
}

TEST(WhiteNoiseTest, TooFewSamplesGiveNoEstimate) {
  std::mt19937 rng(4);
  Log log = MakeLog(0.001, &rng);
  log.dwells.resize(1);  // 79 degrees of freedom
  const MeasuredWhiteNoise noise = MeasureWhiteNoise(log.positions, log.yaws, log.dwells);
  EXPECT_EQ(noise.heading_degrees_of_freedom, 79);
  EXPECT_EQ(noise.heading_sigma_rad, 0.0);
  EXPECT_EQ(noise.gnss_white_sigma_m, 0.0);  // 76 degrees of freedom
}

}  // namespace
}  // namespace wallcal::calib
