// SPDX-License-Identifier: Apache-2.0
#include "analysis/repeatability.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "calib/wall_geometry.h"
#include "common/angles.h"
#include "common/parallel_for.h"

namespace wallcal::analysis {
namespace {

// Iterations of a warm-started re-solve: the problem is nearly linear about the full solution.
constexpr int kRefitIterations = 15;

}  // namespace

ThinnedObservations ThinForRefits(const std::vector<calib::WallObservation>& observations) {
  const size_t stride =
      std::max<size_t>(1, (observations.size() + kMaxRefitObservations - 1) / kMaxRefitObservations);
  ThinnedObservations thin;
  thin.stride = static_cast<double>(stride);
  thin.observations.reserve(observations.size() / stride + 1);
  for (size_t i = 0; i < observations.size(); i += stride) {
    thin.observations.push_back(observations[i]);
  }
  return thin;
}

Repeatability AssessRepeatability(const std::vector<calib::WallObservation>& observations,
                                  const std::vector<calib::WallGeometry>& walls,
                                  const solvers::SolverOptions& options, const solvers::Mount& full,
                                  int samples, uint64_t seed,
                                  const std::array<double, 2>* held_time_block,
                                  const solvers::WarmStart* warm) {
  Repeatability out;
  // Stations in time order.
  std::map<int, std::pair<double, int>> sums;
  for (const auto& o : observations) {
    auto& entry = sums[o.pose.segment];
    entry.first += o.pose.stamp_s;
    entry.second += 1;
  }
  std::vector<std::pair<double, int>> order;
  for (const auto& [segment, sum] : sums) order.emplace_back(sum.first / sum.second, segment);
  std::sort(order.begin(), order.end());
  const int num_stations = static_cast<int>(order.size());
  if (num_stations < 4) return out;
  std::map<int, int> rank;
  for (int k = 0; k < num_stations; ++k) rank[order[k].second] = k;

  // The re-solves get only the thinned observations (an hour-long session's re-solves would
  // otherwise walk 90 times as many observations of weight 0 each).
  const ThinnedObservations thin = ThinForRefits(observations);
  const std::vector<calib::WallObservation>& thinned = thin.observations;
  std::vector<int> station_of;
  for (const calib::WallObservation& o : thinned) station_of.push_back(rank[o.pose.segment]);
  const auto weights_for = [&](const std::vector<double>& station_weight) {
    std::vector<double> w(thinned.size(), 0.0);
    for (size_t i = 0; i < thinned.size(); ++i) {
      w[i] = station_weight[station_of[i]] * thin.stride;
    }
    return w;
  };

  // Splits, then the bootstrap by station: the station weights of every re-solve are drawn
  // first (in order, from one generator), the re-solves then run over the threads, each with
  // one Ceres thread, and are summed in order: the outcome does not depend on the count.
  struct SplitSpec {
    const char* name;
    bool (*take)(int k, int n);
  };
  const SplitSpec specs[] = {
      {"first half", [](int k, int n) { return k < (n + 1) / 2; }},
      {"second half", [](int k, int n) { return k >= (n + 1) / 2; }},
      {"odd stations", [](int k, int) { return k % 2 == 0; }},  // 1st, 3rd, ... (1-based odd)
      {"even stations", [](int k, int) { return k % 2 == 1; }},
  };
  constexpr int kNumSplits = 4;
  std::vector<std::vector<double>> station_weights;
  for (const SplitSpec& spec : specs) {
    std::vector<double> station_weight(num_stations, 0.0);
    for (int k = 0; k < num_stations; ++k) station_weight[k] = spec.take(k, num_stations) ? 1.0 : 0.0;
    station_weights.push_back(std::move(station_weight));
  }
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, num_stations - 1);
  for (int b = 0; b < samples; ++b) {
    std::vector<double> station_weight(num_stations, 0.0);
    for (int k = 0; k < num_stations; ++k) station_weight[pick(rng)] += 1.0;
    station_weights.push_back(std::move(station_weight));
  }
  solvers::SolverOptions one_thread = options;
  one_thread.num_threads = 1;
  std::vector<solvers::Refit> refits(station_weights.size());
  ParallelFor(static_cast<int>(refits.size()), options.num_threads, [&](int r) {
    refits[r] = solvers::RefitMount(thinned, walls, one_thread, full,
                                    weights_for(station_weights[r]), kRefitIterations,
                                    held_time_block, warm);
  });

  for (int r = 0; r < kNumSplits; ++r) {
    const solvers::Refit& refit = refits[r];
    RepeatabilitySplit split;
    split.name = specs[r].name;
    split.mount = refit.mount;
    split.usable = refit.converged && refit.determined;
    if (split.usable) {
      out.max_split_shift_x_m = std::max(out.max_split_shift_x_m, std::abs(refit.mount.x_m - full.x_m));
      out.max_split_shift_y_m = std::max(out.max_split_shift_y_m, std::abs(refit.mount.y_m - full.y_m));
      out.max_split_shift_yaw_rad =
          std::max(out.max_split_shift_yaw_rad,
                   std::abs(WrapAngle(refit.mount.yaw_rad - full.yaw_rad)));
    }
    out.splits.push_back(split);
  }

  double sum_sq[3] = {0.0, 0.0, 0.0};
  double sum[3] = {0.0, 0.0, 0.0};
  int used = 0;
  for (size_t r = kNumSplits; r < refits.size(); ++r) {
    const solvers::Refit& refit = refits[r];
    if (!refit.converged || !refit.determined) continue;
    const double d[3] = {refit.mount.x_m - full.x_m, refit.mount.y_m - full.y_m,
                         WrapAngle(refit.mount.yaw_rad - full.yaw_rad)};
    for (int a = 0; a < 3; ++a) {
      sum[a] += d[a];
      sum_sq[a] += d[a] * d[a];
    }
    ++used;
  }
  out.bootstrap_samples = used;
  if (used >= 2) {
    double s[3];
    for (int a = 0; a < 3; ++a) {
      const double mean = sum[a] / used;
      s[a] = std::sqrt(std::max(0.0, (sum_sq[a] - used * mean * mean) / (used - 1)));
    }
    out.bootstrap_sigma_x_m = s[0];
    out.bootstrap_sigma_y_m = s[1];
    out.bootstrap_sigma_yaw_rad = s[2];
  }
  out.done = true;
  return out;
}

}  // namespace wallcal::analysis
