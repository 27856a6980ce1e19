// SPDX-License-Identifier: Apache-2.0
#include "calib/time_alignment.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "calib/geodesy.h"
#include "common/circular.h"
#include "common/angles.h"
#include "common/enum_text.h"

namespace wallcal::calib {
namespace {

// Moving data: the length of the stretches that count as one "station" (pose.segment).
constexpr double kMovingStretchS = 5.0;
// A moving stretch at most this long between two dwells is a drive between stops (rates over a
// narrow window: PoseInterpolator::At).
constexpr double kShortDriveS = 10.0;

// floor(elapsed_s / length_s) as an int, 0 for a non-positive length or elapsed time, clamped
// below INT_MAX (a slice key must never overflow, whatever the stamps).
int SliceIndex(double elapsed_s, double length_s) {
  if (!(length_s > 0.0) || !(elapsed_s > 0.0)) return 0;
  const double slice = std::floor(elapsed_s / length_s);
  constexpr double kMax = static_cast<double>(std::numeric_limits<int>::max() - (1 << 20));
  return static_cast<int>(std::min(slice, kMax));
}

template <typename Sample>
void CheckStream(const std::vector<Sample>& samples, const char* what) {
  if (samples.size() < 2) {
    throw std::invalid_argument(std::string("PoseInterpolator: ") + what +
                                ": need at least 2 samples, got " + std::to_string(samples.size()));
  }
  for (size_t i = 1; i < samples.size(); ++i) {
    // Written so that a NaN stamp fails too.
    if (!(samples[i].stamp_s > samples[i - 1].stamp_s)) {
      throw std::invalid_argument(std::string("PoseInterpolator: ") + what +
                                  ": stamps not strictly increasing at sample " +
                                  std::to_string(i));
    }
  }
}

template <typename Sample>
double MedianPeriod(const std::vector<Sample>& samples) {
  std::vector<double> periods;
  periods.reserve(samples.size() - 1);
  for (size_t i = 1; i < samples.size(); ++i) {
    periods.push_back(samples[i].stamp_s - samples[i - 1].stamp_s);
  }
  const size_t mid = periods.size() / 2;
  std::nth_element(periods.begin(), periods.begin() + mid, periods.end());
  return periods[mid];
}

// Index lo of the bracketing pair (lo, lo + 1) for a stamp inside [front, back].
template <typename Sample>
size_t Bracket(const std::vector<Sample>& samples, double stamp_s) {
  const auto it =
      std::upper_bound(samples.begin(), samples.end(), stamp_s,
                       [](double t, const Sample& sample) { return t < sample.stamp_s; });
  size_t hi = static_cast<size_t>(it - samples.begin());
  if (hi >= samples.size()) hi = samples.size() - 1;  // stamp_s == back
  return hi - 1;
}

// The samples a and b bracketing a stamp, and its fraction f of the way from a to b.
template <typename Sample>
struct Span {
  const Sample* a = nullptr;
  const Sample* b = nullptr;
  double f = 0.0;
};

// The span of a stamp; empty with the reason in *failure when the stamp is outside the stream or
// its bracketing samples are further apart than max_gap_s (then gap_status).
template <typename Sample>
std::optional<Span<Sample>> SpanAt(const std::vector<Sample>& samples, double stamp_s,
                                   double max_gap_s, PoseStatus gap_status, PoseStatus* failure) {
  if (!(stamp_s >= samples.front().stamp_s)) {
    *failure = PoseStatus::kBeforeStart;
    return std::nullopt;
  }
  if (stamp_s > samples.back().stamp_s) {
    *failure = PoseStatus::kAfterEnd;
    return std::nullopt;
  }
  const size_t lo = Bracket(samples, stamp_s);
  const Sample& a = samples[lo];
  const Sample& b = samples[lo + 1];
  if (b.stamp_s - a.stamp_s > max_gap_s) {
    *failure = gap_status;
    return std::nullopt;
  }
  return Span<Sample>{&a, &b, (stamp_s - a.stamp_s) / (b.stamp_s - a.stamp_s)};
}

// Cubic Hermite weights at fraction f of [t0, t1] with the tangents from central differences
// over the neighbours t_-1 and t2 (non-uniform spacing allowed): the value is
// w[0]·v_-1 + w[1]·v0 + w[2]·v1 + w[3]·v2. Exact for quadratics (a vehicle speeding up or
// slowing down), where the straight chord between two samples is off by a·T²/8 at the middle.
std::array<double, 4> HermiteWeights(double tm1, double t0, double t1, double t2, double f) {
  const double h = t1 - t0;
  const double h00 = 2 * f * f * f - 3 * f * f + 1, h10 = f * f * f - 2 * f * f + f;
  const double h01 = -2 * f * f * f + 3 * f * f, h11 = f * f * f - f * f;
  // m0 = (v1 − v_-1)/(t1 − t_-1), m1 = (v2 − v0)/(t2 − t0), each scaled by h.
  const double a = h * h10 / (t1 - tm1), b = h * h11 / (t2 - t0);
  return {-a, h00 - b, h01 + a, b};
}
}  // namespace

const char* PoseStatusName(PoseStatus status) {
  static const EnumText<PoseStatus> kTexts[] = {
      {PoseStatus::kOk, "ok"}, {PoseStatus::kBeforeStart, "before the GNSS/heading logs"},
      {PoseStatus::kAfterEnd, "after the GNSS/heading logs"},
      {PoseStatus::kGnssGap, "in a GNSS gap"}, {PoseStatus::kHeadingGap, "in a heading gap"}};
  return TextOf(kTexts, status, "unknown");
}

PoseInterpolator::PoseInterpolator(std::vector<PositionSample> positions,
                                   std::vector<YawSample> yaws, const calib::AlignmentOptions& options)
    : positions_(std::move(positions)), yaws_(std::move(yaws)), options_(options) {
  CheckStream(positions_, "GNSS positions");
  CheckStream(yaws_, "yaws");
  gnss_period_s_ = MedianPeriod(positions_);
  heading_period_s_ = MedianPeriod(yaws_);
  gnss_max_gap_s_ = options_.max_gap_periods * gnss_period_s_;
  heading_max_gap_s_ = options_.max_gap_periods * heading_period_s_;
  start_s_ = std::max(positions_.front().stamp_s, yaws_.front().stamp_s);
  end_s_ = std::min(positions_.back().stamp_s, yaws_.back().stamp_s);
  FindDwells();
}

bool PoseInterpolator::PositionAt(double stamp_s, Eigen::Vector2d* p_local_m, double* sigma_m,
                                  PoseStatus* failure) const {
  const auto s = SpanAt(positions_, stamp_s, gnss_max_gap_s_, PoseStatus::kGnssGap, failure);
  if (!s) return false;
  *p_local_m = s->a->p_local_m + s->f * (s->b->p_local_m - s->a->p_local_m);
  *sigma_m = s->a->sigma_m + s->f * (s->b->sigma_m - s->a->sigma_m);
  return true;
}

bool PoseInterpolator::YawAt(double stamp_s, double* yaw_rad, PoseStatus* failure) const {
  const auto s = SpanAt(yaws_, stamp_s, heading_max_gap_s_, PoseStatus::kHeadingGap, failure);
  if (!s) return false;
  // The shorter arc: a vehicle does not turn by more than π between two heading samples.
  *yaw_rad = WrapAngle(s->a->yaw_rad + s->f * WrapAngle(s->b->yaw_rad - s->a->yaw_rad));
  return true;
}

bool PoseInterpolator::CubicAt(double stamp_s, double yaw_stamp_s, Eigen::Vector2d* p_local_m,
                               double* yaw_rad, std::array<double, 4>* position_weights,
                               std::array<double, 4>* yaw_weights) const {
  // Four samples of each stream around its time, every gap bridgeable; otherwise no cubic.
  const size_t lo = Bracket(positions_, stamp_s);
  const size_t yo = Bracket(yaws_, yaw_stamp_s);
  if (lo < 1 || lo + 2 >= positions_.size() || yo < 1 || yo + 2 >= yaws_.size()) return false;
  for (size_t k = lo - 1; k < lo + 2; ++k) {
    if (positions_[k + 1].stamp_s - positions_[k].stamp_s > gnss_max_gap_s_) return false;
  }
  for (size_t k = yo - 1; k < yo + 2; ++k) {
    if (yaws_[k + 1].stamp_s - yaws_[k].stamp_s > heading_max_gap_s_) return false;
  }
  const auto weights = [](const auto& v, size_t k, double t_s) {
    const double f = (t_s - v[k].stamp_s) / (v[k + 1].stamp_s - v[k].stamp_s);
    return HermiteWeights(v[k - 1].stamp_s, v[k].stamp_s, v[k + 1].stamp_s, v[k + 2].stamp_s, f);
  };
  const std::array<double, 4> wp = weights(positions_, lo, stamp_s);
  *p_local_m = Eigen::Vector2d::Zero();
  for (int j = 0; j < 4; ++j) *p_local_m += wp[j] * positions_[lo - 1 + j].p_local_m;
  // Yaw: the samples unwrapped about yaws_[yo] (shorter arcs), then wrapped back.
  const std::array<double, 4> wy = weights(yaws_, yo, yaw_stamp_s);
  const double base = yaws_[yo].yaw_rad;
  double yaw = 0.0;
  for (int j = 0; j < 4; ++j) yaw += wy[j] * WrapAngle(yaws_[yo - 1 + j].yaw_rad - base);
  *yaw_rad = WrapAngle(base + yaw);
  *position_weights = wp;
  *yaw_weights = wy;
  return true;
}

PoseStatus PoseInterpolator::At(double stamp_s, double heading_shift_s, VehiclePose* pose) const {
  const double yaw_stamp_s = stamp_s + heading_shift_s;
  if (!(stamp_s >= start_s_) || !(yaw_stamp_s >= start_s_)) return PoseStatus::kBeforeStart;
  if (stamp_s > end_s_ || yaw_stamp_s > end_s_) return PoseStatus::kAfterEnd;
  Eigen::Vector2d p_local_m;
  double sigma_m = 0.0, yaw_rad = 0.0;
  PoseStatus failure = PoseStatus::kOk;
  if (!PositionAt(stamp_s, &p_local_m, &sigma_m, &failure)) return failure;
  if (!YawAt(yaw_stamp_s, &yaw_rad, &failure)) return failure;

  pose->stamp_s = stamp_s;
  pose->heading_shift_s = heading_shift_s;
  pose->antenna_local_m = p_local_m;
  pose->yaw_rad = yaw_rad;
  pose->gnss_sigma_m = sigma_m;
  pose->gnss_period_s = gnss_period_s_;
  // The fixes and heading samples it lies between (PositionAt and YawAt have checked the
  // brackets).
  const auto fraction = [](const auto& samples, size_t lo, double t_s) {
    return std::clamp((t_s - samples[lo].stamp_s) / (samples[lo + 1].stamp_s - samples[lo].stamp_s),
                      0.0, 1.0);
  };
  const size_t fix = Bracket(positions_, stamp_s);
  const size_t sample = Bracket(yaws_, yaw_stamp_s);
  const double f = fraction(positions_, fix, stamp_s);
  const double g = fraction(yaws_, sample, yaw_stamp_s);
  pose->gnss_fix = static_cast<int>(fix);
  pose->gnss_fix_weights = {0.0, 1.0 - f, f, 0.0};
  pose->heading_sample = static_cast<int>(sample);
  pose->heading_sample_weights = {0.0, 1.0 - g, g, 0.0};
  pose->stationary = false;
  // The last dwell starting at or before stamp_s is the only one that can contain it.
  const auto it = std::upper_bound(dwells_.begin(), dwells_.end(), stamp_s,
                                   [](double t, const Dwell& d) { return t < d.start_s; });
  pose->velocity_local_mps.setZero();
  pose->yaw_rate_rps = 0.0;
  if (it != dwells_.begin() && stamp_s <= std::prev(it)->end_s) {
    pose->stationary = true;
    pose->segment = static_cast<int>(std::prev(it) - dwells_.begin());
    const Dwell& dwell = *std::prev(it);
    pose->dwell_yaw_rad = dwell.mean_yaw_rad;
    pose->dwell_yaw_samples = dwell.num_yaw_samples;
    pose->dwell_mid_s = 0.5 * (dwell.start_s + dwell.end_s);
  } else {
    pose->dwell_yaw_rad = 0.0;
    pose->dwell_yaw_samples = 0;
    pose->dwell_mid_s = 0.0;
    // Driving: the pose from cubics through the samples around (a straight chord between two
    // GNSS fixes misplaces a vehicle speeding up at a m/s² by up to a·T²/8: 4 mm at 3 m/s² and
    // 10 Hz, the same sign over half a drive). Linear where a neighbour is missing.
    CubicAt(stamp_s, yaw_stamp_s, &pose->antenna_local_m, &pose->yaw_rad,
            &pose->gnss_fix_weights, &pose->heading_sample_weights);
    // Moving scans count in stretches of kMovingStretchS as "stations" (geometry checks,
    // bootstrap by station); their GNSS error is sliced finer, below.
    pose->segment = static_cast<int>(dwells_.size()) + SliceIndex(stamp_s - start_s_, kMovingStretchS);
  }
  // The GNSS-error slice: the RTK error is a function of time, so the slices are one grid of
  // segment_max_s over the log, whether the vehicle stands or drives (a dwell spans many).
  pose->gnss_segment = SliceIndex(stamp_s - start_s_, options_.segment_max_s);
  // Rates by central differences over a window (half the stationary window each side, at
  // least one sample period): a single GNSS period would turn 3 mm of white noise into cm/s.
  // The window is clipped to the span where both streams interpolate. Computed inside dwells
  // too: a scan stamped at a dwell's edge may have been taken as the vehicle moved off, and
  // the rate is what lets the solver's clock offset account for it (mm/s of noise otherwise).
  // The yaw rate of a scan on a drive between two stops over ±one sample period instead: such
  // a drive turns through its whole angle in about a second, and the wide window smoothed its
  // rate so much that the offset + heading delay the turns fix came out 4× further off than
  // its σ (benchmark (a)). Not while driving on (continuous driving, turns over tens of
  // seconds): there the heading's noise in a narrow window's rate (about 6 mrad/s) is a fair
  // share of the slow turn rates and shrank a 36 ms heading delay's estimate by 5 ms
  // (errors in variables). The velocity keeps the wide window everywhere: over ±0.1 s its
  // noise (30 mm/s) made the clock offset look determined where drives run along the wall.
  const double wide_s = std::max(0.5 * options_.stationary_window_s,
                                 std::max(gnss_period_s_, heading_period_s_));
  // A drive between two stops: the moving stretch between the dwell before and the one after.
  bool between_stops = false;
  if (!pose->stationary && it != dwells_.begin() && it != dwells_.end()) {
    between_stops = it->start_s - std::prev(it)->end_s <= kShortDriveS;
  }
  const double narrow_s =
      between_stops ? std::max(gnss_period_s_, heading_period_s_) : wide_s;
  const auto rates = [&](double half_s, bool velocity) {
    const double centre_s = velocity ? stamp_s : yaw_stamp_s;
    const double t0 = std::max(start_s_, centre_s - half_s);
    const double t1 = std::min(end_s_, centre_s + half_s);
    if (!(t1 > t0)) return;
    PoseStatus ignored = PoseStatus::kOk;
    if (velocity) {
      Eigen::Vector2d p0, p1;
      double s0 = 0.0, s1 = 0.0;
      if (PositionAt(t0, &p0, &s0, &ignored) && PositionAt(t1, &p1, &s1, &ignored)) {
        pose->velocity_local_mps = (p1 - p0) / (t1 - t0);
      }
    } else {
      double y0 = 0.0, y1 = 0.0;
      if (YawAt(t0, &y0, &ignored) && YawAt(t1, &y1, &ignored)) {
        pose->yaw_rate_rps = WrapAngle(y1 - y0) / (t1 - t0);
      }
    }
  };
  rates(wide_s, true);
  rates(narrow_s, false);
  return PoseStatus::kOk;
}

void PoseInterpolator::FindDwells() {
  dwells_.clear();
  const size_t n = positions_.size();
  const double window_s = options_.stationary_window_s;
  const double half_s = 0.5 * window_s;
  const double max_step_m = options_.stationary_speed_mps * window_s;
  const double max_turn_rad = options_.stationary_yaw_rate_rps * window_s;

  // Yaw at every GNSS sample (for the run means and the edge growth).
  std::vector<double> yaw_at(n, 0.0);
  std::vector<bool> yaw_ok(n, false);
  PoseStatus failure = PoseStatus::kOk;
  for (size_t i = 0; i < n; ++i) {
    double yaw_rad = 0.0;
    yaw_ok[i] = YawAt(positions_[i].stamp_s, &yaw_rad, &failure);
    yaw_at[i] = yaw_rad;
  }

  // 1. The window test at every GNSS sample.
  std::vector<bool> still(n, false);
  for (size_t i = 0; i < n; ++i) {
    const double t = positions_[i].stamp_s;
    Eigen::Vector2d p0, p1;
    double s0 = 0.0, s1 = 0.0, y0 = 0.0, y1 = 0.0;
    if (!PositionAt(t - half_s, &p0, &s0, &failure) ||
        !PositionAt(t + half_s, &p1, &s1, &failure) || !YawAt(t - half_s, &y0, &failure) ||
        !YawAt(t + half_s, &y1, &failure)) {
      continue;
    }
    still[i] = (p1 - p0).norm() < max_step_m && std::abs(WrapAngle(y1 - y0)) < max_turn_rad;
  }

  // 2. Runs of still samples without a GNSS gap inside.
  struct Run {
    size_t first, last;
    Eigen::Vector2d mean_p;
    double mean_yaw;
    bool yaw_known;
  };
  const auto summarise = [&](Run* run) {
    run->mean_p.setZero();
    std::vector<double> run_yaws;
    for (size_t i = run->first; i <= run->last; ++i) {
      run->mean_p += positions_[i].p_local_m;
      if (yaw_ok[i]) run_yaws.push_back(yaw_at[i]);
    }
    run->mean_p /= static_cast<double>(run->last - run->first + 1);
    run->yaw_known = !run_yaws.empty();
    run->mean_yaw = run->yaw_known ? WrapAngle(CircularMean(run_yaws)) : 0.0;
  };
  const auto gap_free = [&](size_t from, size_t to) {
    for (size_t i = from + 1; i <= to; ++i) {
      if (positions_[i].stamp_s - positions_[i - 1].stamp_s > gnss_max_gap_s_) return false;
    }
    return true;
  };
  std::vector<Run> runs;
  for (size_t i = 0; i < n; ++i) {
    if (!still[i]) continue;
    if (!runs.empty() && runs.back().last + 1 == i && gap_free(i - 1, i)) {
      runs.back().last = i;
    } else {
      runs.push_back(Run{i, i, Eigen::Vector2d::Zero(), 0.0, false});
    }
  }
  for (Run& run : runs) summarise(&run);

  // 3. Grow each run outwards while the samples sit at its mean pose: the window test marks a
  // sample still only once the whole window is, which trims ~window/2 off each end of a stop.
  // Tolerances: half the window's displacement threshold and the whole window's yaw threshold,
  // widened to 3.5× the scatter seen within the runs themselves (heading noise of 0.1° σ is a
  // third of the yaw threshold: per-sample tests at the bare threshold stop at random). One
  // sample off in yaw alone is passed over when the sample beyond it is at rest again; a turn on
  // the spot is off for every sample.
  double sum_sq_p_m2 = 0.0, sum_sq_yaw_rad2 = 0.0;
  int count_p = 0, count_yaw = 0;
  for (const Run& run : runs) {
    if (run.last - run.first < 2) continue;  // too few samples for a fair scatter
    for (size_t i = run.first; i <= run.last; ++i) {
      sum_sq_p_m2 += (positions_[i].p_local_m - run.mean_p).squaredNorm();
      ++count_p;
      if (yaw_ok[i] && run.yaw_known) {
        sum_sq_yaw_rad2 += std::pow(WrapAngle(yaw_at[i] - run.mean_yaw), 2);
        ++count_yaw;
      }
    }
  }
  const double scatter_p_m = count_p > 0 ? std::sqrt(sum_sq_p_m2 / count_p) : 0.0;
  const double scatter_yaw_rad = count_yaw > 0 ? std::sqrt(sum_sq_yaw_rad2 / count_yaw) : 0.0;
  const double grow_p_m = std::min(std::max(0.5 * max_step_m, 3.5 * scatter_p_m), 2.0 * max_step_m);
  const double grow_yaw_rad =
      std::min(std::max(max_turn_rad, 3.5 * scatter_yaw_rad), 4.0 * max_turn_rad);
  enum class Rest { kAtRest, kYawOff, kMoved };
  const auto rest_state = [&](const Run& run, size_t i) {
    if ((positions_[i].p_local_m - run.mean_p).norm() > grow_p_m) return Rest::kMoved;
    if (!yaw_ok[i] || !run.yaw_known) return Rest::kMoved;
    return std::abs(WrapAngle(yaw_at[i] - run.mean_yaw)) <= grow_yaw_rad ? Rest::kAtRest
                                                                         : Rest::kYawOff;
  };
  // How many samples (0, 1 or 2) the run can take beyond its edge in direction step (±1)
  // without passing limit (inclusive) or a GNSS gap.
  const auto growth = [&](const Run& run, long edge, long step, long limit) -> long {
    const auto usable = [&](long i) {
      const bool inside = step < 0 ? i >= limit : i <= limit;
      return inside && gap_free(static_cast<size_t>(std::min(i, i - step)),
                                static_cast<size_t>(std::max(i, i - step)));
    };
    const long first = edge + step, second = edge + 2 * step;
    if (!usable(first)) return 0;
    const Rest state = rest_state(run, static_cast<size_t>(first));
    if (state == Rest::kAtRest) return 1;
    if (state == Rest::kMoved || !usable(second)) return 0;
    return rest_state(run, static_cast<size_t>(second)) == Rest::kAtRest ? 2 : 0;
  };
  const auto grow_all = [&](std::vector<Run>* all) {
    std::vector<Run>& v = *all;
    for (size_t r = 0; r < v.size(); ++r) {
      Run& run = v[r];
      const long floor_index = r == 0 ? 0 : static_cast<long>(v[r - 1].last) + 1;
      const long ceiling_index =
          r + 1 < v.size() ? static_cast<long>(v[r + 1].first) - 1 : static_cast<long>(n) - 1;
      for (long k; (k = growth(run, static_cast<long>(run.first), -1, floor_index)) > 0;) {
        run.first -= static_cast<size_t>(k);
      }
      for (long k; (k = growth(run, static_cast<long>(run.last), +1, ceiling_index)) > 0;) {
        run.last += static_cast<size_t>(k);
      }
    }
    for (Run& run : v) summarise(&run);  // more samples: steadier means
  };

  // 4. Merge neighbouring runs at the same pose: one noisy heading pair is enough to fail a
  // window test and split a stop; growth closes such a split only when every sample between is
  // at rest, so a break shorter than the window is forgiven as well.
  const auto merge_all = [&](const std::vector<Run>& all) {
    std::vector<Run> merged;
    for (const Run& run : all) {
      if (!merged.empty()) {
        Run& previous = merged.back();
        const bool close =
            positions_[run.first].stamp_s - positions_[previous.last].stamp_s <= window_s;
        const bool same_pose = (run.mean_p - previous.mean_p).norm() < max_step_m &&
                               run.yaw_known && previous.yaw_known &&
                               std::abs(WrapAngle(run.mean_yaw - previous.mean_yaw)) < grow_yaw_rad;
        if (close && same_pose && gap_free(previous.last, run.first)) {
          previous.last = run.last;
          summarise(&previous);
          continue;
        }
      }
      merged.push_back(run);
    }
    return merged;
  };
  // Growth from a fragment of one or two samples starts from a noisy mean and may stop short;
  // once merged, the stop's full mean lets a second growth reach its true ends.
  grow_all(&runs);
  std::vector<Run> merged = merge_all(runs);
  grow_all(&merged);
  merged = merge_all(merged);

  // 5. Each run loses options_.dwell_guard_s at both ends (the growth of step 3 admits samples
  // up to its tolerances away from the mean pose: the last moments of a turn); long enough
  // runs are the dwells.
  for (const Run& grown : merged) {
    Run run = grown;
    const double guard_s = options_.dwell_guard_s;
    const double first_s = positions_[grown.first].stamp_s + guard_s;
    const double last_s = positions_[grown.last].stamp_s - guard_s;
    while (run.first < run.last && positions_[run.first].stamp_s < first_s) ++run.first;
    while (run.last > run.first && positions_[run.last].stamp_s > last_s) --run.last;
    Dwell dwell;
    dwell.start_s = positions_[run.first].stamp_s;
    dwell.end_s = positions_[run.last].stamp_s;
    if (dwell.end_s - dwell.start_s < options_.min_dwell_s) continue;
    Run final_run = run;
    summarise(&final_run);
    dwell.mean_p_local_m = final_run.mean_p;
    // The yaw samples themselves (not the values interpolated at GNSS times) over the dwell.
    std::vector<double> dwell_yaws;
    const auto first =
        std::lower_bound(yaws_.begin(), yaws_.end(), dwell.start_s,
                         [](const YawSample& sample, double t) { return sample.stamp_s < t; });
    for (auto it = first; it != yaws_.end() && it->stamp_s <= dwell.end_s; ++it) {
      dwell_yaws.push_back(it->yaw_rad);
    }
    dwell.mean_yaw_rad = dwell_yaws.empty() ? final_run.mean_yaw : WrapAngle(CircularMean(dwell_yaws));
    dwell.num_yaw_samples = static_cast<int>(dwell_yaws.size());
    dwells_.push_back(dwell);
  }
}

}  // namespace wallcal::calib
