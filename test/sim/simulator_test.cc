// SPDX-License-Identifier: Apache-2.0
#include "sim/simulator.h"

#include <gtest/gtest.h>

#include <GeographicLib/LocalCartesian.hpp>
#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "common/angles.h"
#include "test/support/sim_fixtures.h"

namespace wallcal::calib {}
namespace wallcal::sim {
using namespace wallcal::calib;  // NOLINT: the simulator is checked against calib's geometry
namespace {
using namespace testing_fixtures;  // NOLINT: the shared fixtures

// A run of `stations` dwells of `dwell_s` each (long runs for statistics).
sim::SimulationConfig LongConfig(int stations, double dwell_s) {
  sim::SimulationConfig c = DefaultConfig();
  c.num_stations = stations;
  c.dwell_s = dwell_s;
  return c;
}

double WrapPi(double a) { return std::remainder(a, 2.0 * kPi); }

// The truth pose at true time t when the vehicle stands still around t (both bracketing truth
// samples stationary and equal); nullptr otherwise.
const SimTruthPose* StationaryTruth(const SimulatedSession& s, double t_s) {
  const auto k = static_cast<size_t>(std::floor(t_s * 10.0 + 1e-9));
  if (k + 1 >= s.truth_poses.size()) return nullptr;
  const SimTruthPose& a = s.truth_poses[k];
  const SimTruthPose& b = s.truth_poses[k + 1];
  if (!a.stationary || !b.stationary || a.yaw_enu_rad != b.yaw_enu_rad ||
      a.antenna_enu_m != b.antenna_enu_m) {
    return nullptr;
  }
  return &a;
}

// Stations: runs of stationary truth poses.
struct Station {
  double t0_s, t1_s;
  Eigen::Vector2d antenna_enu_m;
  double yaw_rad;
};
std::vector<Station> Stations(const SimulatedSession& s, double start_time_s) {
  std::vector<Station> out;
  bool in = false;
  for (const auto& p : s.truth_poses) {
    const double t = p.stamp_s - start_time_s;
    if (p.stationary && !in) out.push_back({t, t, p.antenna_enu_m, p.yaw_enu_rad});
    if (p.stationary) out.back().t1_s = t;
    in = p.stationary;
  }
  return out;
}

// ---- Tests ----------------------------------------------------------------------------------

TEST(SimulatorTest, SameSeedGivesSameSessionOtherSeedDiffers) {
  const sim::SimulationConfig config = DefaultConfig();
  const Collected a = RunSim(config, SickLms291(), 7);
  const Collected b = RunSim(config, SickLms291(), 7);
  const Collected c = RunSim(config, SickLms291(), 8);
  ASSERT_EQ(a.session.fixes.size(), b.session.fixes.size());
  ASSERT_FALSE(a.session.fixes.empty());
  for (size_t i = 0; i < a.session.fixes.size(); ++i) {
    EXPECT_EQ(a.session.fixes[i].lat_deg, b.session.fixes[i].lat_deg);
    EXPECT_EQ(a.session.fixes[i].lon_deg, b.session.fixes[i].lon_deg);
    EXPECT_EQ(a.session.fixes[i].height_m, b.session.fixes[i].height_m);
  }
  ASSERT_EQ(a.session.headings.size(), b.session.headings.size());
  for (size_t i = 0; i < a.session.headings.size(); ++i) {
    EXPECT_EQ(a.session.headings[i].heading_rad, b.session.headings[i].heading_rad);
  }
  ASSERT_EQ(a.scans.size(), b.scans.size());
  ASSERT_GE(a.scans.size(), 100u);
  for (size_t i = 0; i < 100; ++i) {
    EXPECT_EQ(a.scans[i].stamp_s, b.scans[i].stamp_s);
    EXPECT_EQ(a.scans[i].ranges_m, b.scans[i].ranges_m);
  }
  ASSERT_EQ(a.session.survey.size(), b.session.survey.size());
  for (size_t i = 0; i < a.session.survey.size(); ++i)
    EXPECT_EQ(a.session.survey[i].x_m, b.session.survey[i].x_m);

  int fixes_differing = 0;
  for (size_t i = 0; i < a.session.fixes.size(); ++i) {
    fixes_differing += a.session.fixes[i].lat_deg != c.session.fixes[i].lat_deg;
  }
  EXPECT_GT(fixes_differing, static_cast<int>(a.session.fixes.size()) / 2);
  int scans_differing = 0;
  for (size_t i = 0; i < 100; ++i) scans_differing += a.scans[i].ranges_m != c.scans[i].ranges_m;
  EXPECT_GT(scans_differing, 50);
  EXPECT_NE(a.session.headings[0].heading_rad, c.session.headings[0].heading_rad);
}

TEST(SimulatorTest, ChangingOneNoiseSourceLeavesTheOthersAlone) {
  sim::SimulationConfig config = DefaultConfig();
  const Collected a = RunSim(config, SickLms291(), 3);
  config.mixed_pixel_probability = 0.0;
  config.lost_scan_fraction = 0.01;
  const Collected b = RunSim(config, SickLms291(), 3);
  ASSERT_EQ(a.session.fixes.size(), b.session.fixes.size());
  for (size_t i = 0; i < a.session.fixes.size(); ++i) {
    EXPECT_EQ(a.session.fixes[i].lat_deg, b.session.fixes[i].lat_deg);
  }
  for (size_t i = 0; i < a.session.headings.size(); ++i) {
    EXPECT_EQ(a.session.headings[i].heading_rad, b.session.headings[i].heading_rad);
  }
}

TEST(SimulatorTest, StationsDwellsAndDurationFollowTheConfig) {
  sim::SimulationConfig config = DefaultConfig();
  config.drive_speed_mps = 0.5;  // drives then last lateral step / speed = (6/9 m) / 0.5 m/s
  const Collected run = RunSim(config, CheapPreset(), 1);
  const std::vector<Station> stations = Stations(run.session, config.start_time_s);
  ASSERT_EQ(static_cast<int>(stations.size()), config.num_stations);

  // Total: dwells plus drives; the drives add up to lateral_spread / speed here.
  const double expected_s =
      config.num_stations * config.dwell_s + config.lateral_spread_m / config.drive_speed_mps;
  EXPECT_NEAR(run.session.truth_poses.back().stamp_s - config.start_time_s, expected_s, 0.1 + 1e-5);

  double min_yaw = 1e9, max_yaw = -1e9;
  for (size_t i = 0; i < stations.size(); ++i) {
    const Station& s = stations[i];
    EXPECT_NEAR(s.t1_s - s.t0_s, config.dwell_s, 0.1 + 1e-5) << "station " << i;
    // The default wall is y = 12 m: the antenna stands station_distance_m south of it.
    EXPECT_NEAR(12.0 - s.antenna_enu_m.y(), config.station_distance_m, 1e-9);
    min_yaw = std::min(min_yaw, s.yaw_rad);
    max_yaw = std::max(max_yaw, s.yaw_rad);
    if (i > 0) {
      // Neighbours: one lateral step apart.
      EXPECT_NEAR((s.antenna_enu_m - stations[i - 1].antenna_enu_m).norm(),
                  config.lateral_spread_m / (config.num_stations - 1), 1e-9);
    }
  }
  EXPECT_NEAR(max_yaw - min_yaw, config.heading_spread_rad, 1e-9);
  EXPECT_NEAR(0.5 * (max_yaw + min_yaw), kPi / 2.0, 1e-9);  // centred on facing north, at the wall

  // The vehicle never gets closer to the wall than at its stations.
  for (const auto& p : run.session.truth_poses)
    EXPECT_LE(p.antenna_enu_m.y(), 12.0 - config.station_distance_m + 1e-9);
}

TEST(SimulatorTest, NoiseFreeRangesEqualGeometricDistanceToTheWall) {
  const sim::SimulationConfig config = NoiseFreeConfig();
  const io::ScannerPreset preset = PerfectPreset();
  const Collected run = RunSim(config, preset, 5);
  int checked_perpendicular = 0, checked_oblique = 0, checked_none = 0, scans_checked = 0;
  for (size_t si = 0; si < run.scans.size(); si += 25) {
    const io::ScanRecord& scan = run.scans[si];
    const SimTruthPose* truth = StationaryTruth(run.session, scan.stamp_s - config.start_time_s);
    if (truth == nullptr) continue;
    ++scans_checked;
    const double yaw = truth->yaw_enu_rad;
    const Eigen::Vector2d scanner =
        truth->antenna_enu_m +
        Eigen::Vector2d(std::cos(yaw) * config.mount_x_m - std::sin(yaw) * config.mount_y_m,
                        std::sin(yaw) * config.mount_x_m + std::cos(yaw) * config.mount_y_m);
    for (int i = 0; i < preset.num_beams; ++i) {
      const double alpha =
          yaw + config.mount_yaw_rad + preset.start_angle_rad + i * preset.angular_step_rad;
      const double range = scan.ranges_m[i];
      // Wall line y = 12 m, x in [−15, 15]; the beam meets it at distance (12 − y_s) / sin α.
      const double sin_a = std::sin(alpha);
      const double t = sin_a > 1e-9 ? (12.0 - scanner.y()) / sin_a : -1.0;
      const double x_hit = scanner.x() + t * std::cos(alpha);
      const double incidence = std::acos(std::min(1.0, std::abs(sin_a)));
      if (t > 0.0 && std::abs(x_hit) <= 15.0 - 1e-6 &&
          incidence < preset.max_incidence_rad - 1e-6) {
        if (incidence < 30.0 * kDegToRad) {
          EXPECT_NEAR(range, t, 1e-6) << "scan " << si << " beam " << i;
          ++checked_perpendicular;
        } else {
          EXPECT_NEAR(range, t, 2e-7 * t) << "scan " << si << " beam " << i;
          ++checked_oblique;
        }
      } else if (t < 0.0 || std::abs(x_hit) > 15.0 + 1e-6 ||
                 incidence > preset.max_incidence_rad + 1e-6) {
        EXPECT_EQ(range, static_cast<float>(preset.max_range_m)) << "scan " << si << " beam " << i;
        ++checked_none;
      }
    }
  }
  EXPECT_GT(scans_checked, 50);
  EXPECT_GT(checked_perpendicular, 1000);
  EXPECT_GT(checked_oblique, 1000);
  EXPECT_GT(checked_none, 1000);
}

TEST(SimulatorTest, NoiseFreeGnssAndHeadingReproduceTheTruth) {
  const sim::SimulationConfig config = NoiseFreeConfig();
  const Collected run = RunSim(config, CheapPreset(), 5);
  const GeographicLib::LocalCartesian enu(config.site_lat_deg, config.site_lon_deg,
                                          config.site_height_m);
  ASSERT_EQ(run.session.fixes.size(), run.session.truth_poses.size());  // both 10 Hz from t = 0
  for (size_t i = 0; i < run.session.fixes.size(); ++i) {
    const io::GnssFix& f = run.session.fixes[i];
    double e, n, u;
    enu.Forward(f.lat_deg, f.lon_deg, f.height_m, e, n, u);
    EXPECT_NEAR(e, run.session.truth_poses[i].antenna_enu_m.x(), 1e-6);
    EXPECT_NEAR(n, run.session.truth_poses[i].antenna_enu_m.y(), 1e-6);
    EXPECT_NEAR(u, 0.0, 1e-6);
    EXPECT_EQ(f.quality, 4);
    EXPECT_EQ(f.stamp_s, run.session.truth_poses[i].stamp_s);
  }
  int checked = 0;
  for (const auto& h : run.session.headings) {
    const SimTruthPose* truth = StationaryTruth(run.session, h.stamp_s - config.start_time_s);
    if (truth == nullptr) continue;
    EXPECT_GE(h.heading_rad, 0.0);
    EXPECT_LT(h.heading_rad, 2.0 * kPi);
    EXPECT_NEAR(WrapPi(h.heading_rad - (kPi / 2.0 - truth->yaw_enu_rad)), 0.0, 1e-12);
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST(SimulatorTest, UrgReportsErrorCodesForNoReturns) {
  sim::SimulationConfig config = DefaultConfig();
  config.mount_x_m = 0.3;  // a small robot: the URG sees 4 m at most
  config.mount_y_m = 0.0;
  config.mount_yaw_rad = 0.0;
  config.station_distance_m = 2.5;
  config.lateral_spread_m = 2.0;
  const io::ScannerPreset preset = HokuyoUrg04lx();
  const Collected run = RunSim(config, preset, 11);
  ASSERT_FALSE(run.scans.empty());
  int64_t codes = 0, ranges = 0;
  for (const auto& scan : run.scans) {
    ASSERT_EQ(static_cast<int>(scan.ranges_m.size()), preset.num_beams);
    EXPECT_FLOAT_EQ(scan.max_range_m, preset.max_range_m);
    for (float r : scan.ranges_m) {
      EXPECT_GE(r, 0.0f);
      EXPECT_LT(r, preset.max_range_m);  // the URG never reports its maximum as no-return
      if (r < preset.error_codes_below_m) {
        ++codes;
      } else {
        ++ranges;
      }
    }
  }
  EXPECT_GT(codes, 1000);   // beams behind the scanner and beyond 4 m
  EXPECT_GT(ranges, 1000);  // the wall
}

TEST(SimulatorTest, SickReportsMaximumRangeForNoReturns) {
  const sim::SimulationConfig config = DefaultConfig();
  const io::ScannerPreset preset = SickLms200();  // 8.183 m: the wall ends are out of range
  const Collected run = RunSim(config, preset, 12);
  ASSERT_FALSE(run.scans.empty());
  int64_t no_returns = 0, ranges = 0;
  for (const auto& scan : run.scans) {
    for (float r : scan.ranges_m) {
      if (r == static_cast<float>(preset.max_range_m)) {
        ++no_returns;
      } else {
        EXPECT_GT(r, 0.5f);  // no error codes: the nearest wall is > 5 m away
        EXPECT_LT(r, preset.max_range_m);
        ++ranges;
      }
    }
  }
  EXPECT_GT(no_returns, 1000);
  EXPECT_GT(ranges, 1000);
}

TEST(SimulatorTest, MixedPixelsFallBetweenForegroundAndBackground) {
  sim::SimulationConfig config = NoiseFreeConfig();
  // A post 1.5 m in front of the middle station's scanner, about 3.4 m before the wall.
  config.obstacles.push_back({0.0, 12.0 - config.station_distance_m + config.mount_x_m + 1.5, 0.3});
  const io::ScannerPreset preset = PerfectPreset();
  auto count_mixed = [&](double probability) {
    sim::SimulationConfig c = config;
    c.mixed_pixel_probability = probability;
    const Collected run = RunSim(c, preset, 21);
    int64_t mixed = 0;
    for (const auto& scan : run.scans) {
      for (int i = 1; i + 1 < preset.num_beams; ++i) {
        // A mixed pixel lies clearly between its two neighbours, one on the post (< 4 m away) and
        // one on the wall (> 5.9 m away from every station).
        const double lo = std::min(scan.ranges_m[i - 1], scan.ranges_m[i + 1]);
        const double hi = std::max(scan.ranges_m[i - 1], scan.ranges_m[i + 1]);
        if (lo < 4.0 && hi > 5.0 && hi < 70.0 && scan.ranges_m[i] > lo + 0.3 &&
            scan.ranges_m[i] < hi - 0.3)
          ++mixed;
      }
    }
    return mixed;
  };
  EXPECT_EQ(count_mixed(0.0), 0);
  EXPECT_GT(count_mixed(1.0), 100);
}

// A wall seen obliquely is one surface: its footprint's edges lie more than 0.1 m apart in range
// (at 8 m beyond about 37° of incidence) without a depth jump, and its returns stay the wall's.
TEST(SimulatorTest, ObliqueWallGivesNoMixedPixels) {
  sim::SimulationConfig config = NoiseFreeConfig();
  ASSERT_EQ(config.walls.size(), 1u);
  ASSERT_TRUE(config.obstacles.empty());
  const io::ScannerPreset preset = PerfectPreset();
  sim::SimulationConfig always = config;
  always.mixed_pixel_probability = 1.0;
  const Collected clean = RunSim(config, preset, 22);
  const Collected mixed = RunSim(always, preset, 22);
  ASSERT_EQ(clean.scans.size(), mixed.scans.size());
  int64_t compared = 0, oblique = 0;
  for (size_t k = 0; k < clean.scans.size(); ++k) {
    const auto& a = clean.scans[k].ranges_m;
    const auto& b = mixed.scans[k].ranges_m;
    ASSERT_EQ(a.size(), b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      if (a[i] >= preset.max_range_m) continue;
      ++compared;
      // The footprint's edges ±0.4 step apart differ by more than 0.1 m here.
      if (i > 0 && i + 1 < a.size() && a[i - 1] < preset.max_range_m &&
          a[i + 1] < preset.max_range_m && 0.4 * std::abs(a[i + 1] - a[i - 1]) > 0.1) {
        ++oblique;
      }
      EXPECT_EQ(a[i], b[i]) << "scan " << k << " beam " << i;
    }
  }
  EXPECT_GT(compared, 1000);
  EXPECT_GT(oblique, 100);  // the case is exercised
}

TEST(SimulatorTest, GnssErrorFollowsBiasAndWhiteSigma) {
  sim::SimulationConfig config = LongConfig(3, 1500.0);
  config.gnss_bias_tau_s = 10.0;  // many correlation times in the run
  const Collected run = RunSim(config, CheapPreset(), 31);
  const GeographicLib::LocalCartesian enu(config.site_lat_deg, config.site_lon_deg,
                                          config.site_height_m);
  ASSERT_EQ(run.session.fixes.size(), run.session.truth_poses.size());
  std::vector<double> err_e, err_n;
  for (size_t i = 0; i < run.session.fixes.size(); ++i) {
    const io::GnssFix& f = run.session.fixes[i];
    double e, n, u;
    enu.Forward(f.lat_deg, f.lon_deg, f.height_m, e, n, u);
    err_e.push_back(e - run.session.truth_poses[i].antenna_enu_m.x());
    err_n.push_back(n - run.session.truth_poses[i].antenna_enu_m.y());
  }
  const double expected = std::hypot(config.gnss_bias_sigma_m, config.gnss_white_sigma_m);
  auto stddev = [](const std::vector<double>& v) {
    double mean = 0.0, sq = 0.0;
    for (double x : v) mean += x;
    mean /= v.size();
    for (double x : v) sq += (x - mean) * (x - mean);
    return std::sqrt(sq / (v.size() - 1));
  };
  EXPECT_NEAR(stddev(err_e), expected, 0.3 * expected);
  EXPECT_NEAR(stddev(err_n), expected, 0.3 * expected);
  // Correlated: at a lag of τ the autocorrelation is e⁻¹ of the bias share of the variance.
  const size_t lag = static_cast<size_t>(config.gnss_bias_tau_s * config.gnss_rate_hz);
  double c0 = 0.0, c_lag = 0.0;
  for (size_t i = 0; i + lag < err_e.size(); ++i) {
    c0 += err_e[i] * err_e[i];
    c_lag += err_e[i] * err_e[i + lag];
  }
  const double bias_share = std::pow(config.gnss_bias_sigma_m / expected, 2);
  EXPECT_NEAR(c_lag / c0, std::exp(-1.0) * bias_share, 0.12);
  for (const auto& f : run.session.fixes) {
    EXPECT_EQ(f.quality, 4);
    EXPECT_DOUBLE_EQ(f.sigma_lat_m, expected);
    EXPECT_DOUBLE_EQ(f.sigma_lon_m, expected);
  }
}

TEST(SimulatorTest, FloatPeriodsCoverTheConfiguredShareWithLargerSigma) {
  sim::SimulationConfig config = LongConfig(3, 200.0);
  config.float_fraction = 0.2;
  const Collected run = RunSim(config, CheapPreset(), 32);
  const double fixed_sigma = std::hypot(config.gnss_bias_sigma_m, config.gnss_white_sigma_m);
  int64_t floats = 0, blocks = 0;
  int previous = 4;
  for (const auto& f : run.session.fixes) {
    if (f.quality == 5) {
      ++floats;
      EXPECT_DOUBLE_EQ(f.sigma_lat_m, 10.0 * fixed_sigma);
    } else {
      EXPECT_EQ(f.quality, 4);
      EXPECT_DOUBLE_EQ(f.sigma_lat_m, fixed_sigma);
    }
    blocks += f.quality == 5 && previous == 4;
    previous = f.quality;
  }
  EXPECT_NEAR(static_cast<double>(floats) / run.session.fixes.size(), 0.2, 0.01);
  EXPECT_GE(blocks, 1);
  EXPECT_LE(blocks, 3);

  config.write_gst = false;
  const Collected no_gst = RunSim(config, CheapPreset(), 32);
  EXPECT_TRUE(std::isnan(no_gst.session.fixes.front().sigma_lat_m));
}

TEST(SimulatorTest, HeadingDriftsAtTheConfiguredRate) {
  sim::SimulationConfig config = LongConfig(3, 600.0);
  config.heading_bias_rad = 0.01;
  const Collected run = RunSim(config, CheapPreset(), 41);
  const double duration_s = run.session.truth_poses.back().stamp_s - config.start_time_s;
  double sum_first = 0.0, t_first = 0.0, sum_last = 0.0, t_last = 0.0;
  int n_first = 0, n_last = 0;
  for (const auto& h : run.session.headings) {
    const double t = h.stamp_s - config.start_time_s;
    const SimTruthPose* truth = StationaryTruth(run.session, t);
    if (truth == nullptr) continue;
    const double error = WrapPi(h.heading_rad - (kPi / 2.0 - truth->yaw_enu_rad));
    if (t < 60.0) {
      sum_first += error;
      t_first += t;
      ++n_first;
    } else if (t > duration_s - 60.0) {
      sum_last += error;
      t_last += t;
      ++n_last;
    }
  }
  ASSERT_GT(n_first, 1000);
  ASSERT_GT(n_last, 1000);
  const double elapsed_s = t_last / n_last - t_first / n_first;
  const double change = sum_last / n_last - sum_first / n_first;
  EXPECT_NEAR(std::abs(change), config.heading_drift_rad_per_s * elapsed_s,
              0.1 * config.heading_drift_rad_per_s * elapsed_s);
  // The first minute holds the bias plus ≤ 60 s of drift.
  EXPECT_NEAR(sum_first / n_first, config.heading_bias_rad,
              config.heading_drift_rad_per_s * 60.0 + 1e-4);

  // The drift's sign comes from the seed: both occur.
  std::set<int> signs;
  sim::SimulationConfig short_config = DefaultConfig();
  short_config.heading_white_sigma_rad = 0.0;
  short_config.heading_drift_rad_per_s = 1e-3;
  for (uint64_t seed = 1; seed <= 12; ++seed) {
    const SimulatedSession s = Simulate(short_config, CheapPreset(), seed, nullptr);
    const double first =
        WrapPi(s.headings.front().heading_rad - (kPi / 2.0 - s.truth_poses.front().yaw_enu_rad));
    // The last heading taken while standing still.
    auto last =
        std::find_if(s.headings.rbegin(), s.headings.rend(), [&](const io::HeadingSample& h) {
          return StationaryTruth(s, h.stamp_s - short_config.start_time_s) != nullptr;
        });
    ASSERT_NE(last, s.headings.rend());
    const SimTruthPose* truth = StationaryTruth(s, last->stamp_s - short_config.start_time_s);
    const double final_error = WrapPi(last->heading_rad - (kPi / 2.0 - truth->yaw_enu_rad));
    EXPECT_NEAR(std::abs(final_error - first), 1e-3 * (last->stamp_s - s.headings.front().stamp_s),
                1e-6);
    signs.insert(final_error > first ? 1 : -1);
  }
  EXPECT_EQ(signs.size(), 2u);
}

TEST(SimulatorTest, LostScansAndLoggingRateFollowTheConfig) {
  sim::SimulationConfig config = LongConfig(3, 100.0);
  config.lost_scan_fraction = 0.05;
  const Collected run = RunSim(config, CheapPreset(75.0), 51);
  const SimulatedSession& s = run.session;
  EXPECT_EQ(s.scans_generated, s.scans_lost + s.scans_written);
  EXPECT_EQ(static_cast<int64_t>(run.scans.size()), s.scans_written);
  EXPECT_NEAR(static_cast<double>(s.scans_lost) / s.scans_generated, 0.05, 0.005);
  for (size_t i = 1; i < run.scans.size(); ++i)
    EXPECT_GT(run.scans[i].stamp_s, run.scans[i - 1].stamp_s);

  config.lost_scan_fraction = 0.0;
  config.log_every_n = 3;
  const Collected thinned = RunSim(config, CheapPreset(75.0), 51);
  EXPECT_EQ(thinned.session.scans_generated, s.scans_generated);
  EXPECT_EQ(thinned.session.scans_written, (s.scans_generated + 2) / 3);
  EXPECT_EQ(thinned.session.scans_lost, 0);
  ASSERT_GE(thinned.scans.size(), 2u);
  EXPECT_NEAR(thinned.scans[1].stamp_s - thinned.scans[0].stamp_s, 3.0 / 75.0, 1e-6);
}

TEST(SimulatorTest, ScanStampsRunEarlyByTheTimeOffset) {
  sim::SimulationConfig config = DefaultConfig();
  config.scanner_time_offset_s = 0.25;
  config.lost_scan_fraction = 0.0;
  const Collected run = RunSim(config, SickLms291(), 61);
  ASSERT_FALSE(run.scans.empty());
  EXPECT_NEAR(run.scans.front().stamp_s, config.start_time_s - 0.25, 1e-6);
  EXPECT_NEAR(run.scans[75].stamp_s, config.start_time_s + 1.0 - 0.25, 1e-6);
  EXPECT_EQ(run.session.fixes.front().stamp_s, config.start_time_s);
  EXPECT_EQ(run.session.headings.front().stamp_s, config.start_time_s);
  EXPECT_NEAR(run.scans.front().start_angle_rad, -90.0 * kDegToRad, 1e-12);
  EXPECT_NEAR(run.scans.front().angular_step_rad, 1.0 * kDegToRad, 1e-12);
  EXPECT_EQ(run.scans.front().max_range_m, 80.0);
}

TEST(SimulatorTest, StationsFaceAnyWallFromTheOriginSide) {
  sim::SimulationConfig config = NoiseFreeConfig();
  config.walls = {Wall("east", "E1", 12.0, 10.0, 12.0, -10.0)};  // x = 12 m
  const Collected run = RunSim(config, CheapPreset(), 91);
  const auto stations = Stations(run.session, config.start_time_s);
  ASSERT_EQ(static_cast<int>(stations.size()), config.num_stations);
  double mean_yaw = 0.0;
  for (const auto& s : stations) {
    EXPECT_NEAR(12.0 - s.antenna_enu_m.x(), config.station_distance_m, 1e-9);
    mean_yaw += s.yaw_rad / stations.size();
  }
  EXPECT_NEAR(WrapPi(mean_yaw), 0.0, 1e-9);  // facing east, at the wall
}

TEST(SimulatorTest, RejectsWhatItCannotSimulate) {
  sim::SimulationConfig config = DefaultConfig();
  config.num_stations = 2;
  EXPECT_THROW(Simulate(config, SickLms291(), 1, nullptr), io::InputError);

  config = DefaultConfig();
  config.walls[0].code.clear();
  EXPECT_THROW(Simulate(config, SickLms291(), 1, nullptr), io::InputError);

  config = DefaultConfig();
  config.station_distance_m = 2.0;  // scanner 2.57 m ahead would be through the wall
  EXPECT_THROW(Simulate(config, SickLms291(), 1, nullptr), io::InputError);

  io::ScannerPreset no_beams = SickLms291();
  no_beams.num_beams = 0;
  EXPECT_THROW(Simulate(DefaultConfig(), no_beams, 1, nullptr), io::InputError);
}

}  // namespace
}  // namespace wallcal::sim
