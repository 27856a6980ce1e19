#include "analysis/repeatability.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <random>

#include "calib/wall_geometry.h"
#include "common/angles.h"

namespace wallcal::analysis {
namespace {

// Iterations of a warm-started re-solve: the problem is nearly linear about the full solution.
constexpr int kRefitIterations = 15;

}  // namespace

Repeatability AssessRepeatability(const std::vector<calib::WallObservation>& observations,
                                  const std::vector<calib::WallGeometry>& walls,
                                  const io::SolverOptions& options, const solvers::Mount& full,
                                  int samples, uint64_t seed) {
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

  // Thinning: every stride-th observation, weighted by the stride.
  const size_t stride =
      std::max<size_t>(1, (observations.size() + kMaxRefitObservations - 1) / kMaxRefitObservations);
  std::vector<int> station_of(observations.size());
  for (size_t i = 0; i < observations.size(); ++i) station_of[i] = rank[observations[i].pose.segment];
  const auto weights_for = [&](const std::vector<double>& station_weight) {
    std::vector<double> w(observations.size(), 0.0);
    for (size_t i = 0; i < observations.size(); i += stride) {
      w[i] = station_weight[station_of[i]] * static_cast<double>(stride);
    }
    return w;
  };

  // Splits.
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
  for (const SplitSpec& spec : specs) {
    std::vector<double> station_weight(num_stations, 0.0);
    for (int k = 0; k < num_stations; ++k) station_weight[k] = spec.take(k, num_stations) ? 1.0 : 0.0;
    const solvers::Refit refit = solvers::RefitMount(observations, walls, options, full,
                                                     weights_for(station_weight), kRefitIterations);
    RepeatabilitySplit split;
    split.name = spec.name;
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

  // Bootstrap by station.
  std::mt19937_64 rng(seed);
  std::uniform_int_distribution<int> pick(0, num_stations - 1);
  double sum_sq[3] = {0.0, 0.0, 0.0};
  double sum[3] = {0.0, 0.0, 0.0};
  int used = 0;
  for (int b = 0; b < samples; ++b) {
    std::vector<double> station_weight(num_stations, 0.0);
    for (int k = 0; k < num_stations; ++k) station_weight[pick(rng)] += 1.0;
    const solvers::Refit refit = solvers::RefitMount(observations, walls, options, full,
                                                     weights_for(station_weight), kRefitIterations);
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
