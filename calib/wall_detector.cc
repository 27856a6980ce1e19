// SPDX-License-Identifier: Apache-2.0
#include "calib/wall_detector.h"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <limits>

#include "calib/internal/line_fit.h"
#include "common/angles.h"
#include "common/format.h"

namespace wallcal::calib {
namespace {
using internal::FillDetection;
using internal::LineFit;
using internal::RefineAlongBeams;
using internal::TrimmedFit;

// Floor on the per-point σ used for trimming: about a 1 cm quantisation step / √12 plus the
// flatness of a real wall. Keeps a preset with a tiny σ from trimming a wall to nothing.
constexpr double kMinPointSigmaM = 0.003;
// Peaks tried before giving up: the strongest in-gate peak can be clutter (a hedge row seen
// edge-on) while the wall is the second one.
constexpr int kMaxPeaksTried = 3;
// Rounds of peak search; a new round follows when a peak turned out to be a line outside the
// gate and its points withdrew their votes.
constexpr int kMaxRounds = 4;
// A refined line may leave the gate by this many accumulator cells: the gate's edge is only
// resolved to a cell. Any more and a strong line just outside the gate, which can win the gate's
// edge cells when it lies within a cell or two of them, would be accepted.
constexpr double kGateToleranceCells = 0.5;
// Cap on accumulator cells, against nonsensical step sizes.
constexpr int64_t kMaxCells = 20'000'000;

double WrapAngle(double a) {
  a = std::remainder(a, 2.0 * kPi);  // [-π, π]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

struct Peak {
  int votes = 0;
  int row = 0, col = 0;
};

// An accumulator cell with two votes or more: rho column j, theta row k.
struct BusyCell {
  int j = 0, k = 0;
};

// Whether a point lies along the gate's surveyed segment, within a margin (m), measured along
// the segment. The segment's direction and length are computed once per scan.
class SegmentTest {
 public:
  SegmentTest(const LineGate& gate, double margin_m)
      : a_(gate.segment_a_scanner),
        ab_(gate.segment_b_scanner - gate.segment_a_scanner),
        length_(ab_.norm()),
        margin_m_(margin_m) {}
  bool Contains(const Eigen::Vector2d& p) const {
    if (length_ < 1e-9) return (p - a_).norm() <= margin_m_;
    const double along = (p - a_).dot(ab_) / length_;
    return along >= -margin_m_ && along <= length_ + margin_m_;
  }

 private:
  Eigen::Vector2d a_, ab_;
  double length_;
  double margin_m_;
};

// Local maxima of the accumulator (stored rho-major: acc_t(j, k), j rho cell, k theta row)
// inside the gate (rows row_first..row_last, columns 1..n_in), and of these the strongest
// kMaxPeaksTried, one per plateau. A cell on the gate's edge that only carries the flank of a
// stronger line outside the gate has a bigger neighbour in the margin, so it is not a maximum.
std::vector<Peak> StrongestPeaks(const cv::Mat_<int>& acc_t, const BusyCell* busy_cells,
                                 size_t num_busy, int n_theta, int n_in, int row_first,
                                 int row_last, bool full_circle) {
  auto neighbour_row = [&](int k) {
    if (full_circle) return (k % n_theta + n_theta) % n_theta;
    return k;  // margins make k - 1 and k + 1 valid for every in-gate row
  };
  std::vector<Peak> peaks;
  for (size_t b = 0; b < num_busy; ++b) {
    const int j = busy_cells[b].j, k = busy_cells[b].k;
    if (k < row_first || k > row_last || j < 1 || j > n_in) continue;
    const int v = acc_t(j, k);
    if (v < 2) continue;  // votes may have been withdrawn
    bool is_max = true;
    for (int dj = -1; dj <= 1 && is_max; ++dj) {
      const int* column = acc_t[j + dj];
      for (int dk = -1; dk <= 1; ++dk) {
        if ((dk != 0 || dj != 0) && column[neighbour_row(k + dk)] > v) {
          is_max = false;
          break;
        }
      }
    }
    if (is_max) peaks.push_back({v, k, j});
  }
  // Repeated selection rather than a sort: a cluttered scan has many two-vote maxima.
  auto better = [](const Peak& a, const Peak& b) {
    if (a.votes != b.votes) return a.votes > b.votes;
    return a.row != b.row ? a.row < b.row : a.col < b.col;
  };
  auto near = [&](const Peak& a, const Peak& b) {  // same plateau
    int drow = std::abs(a.row - b.row);
    if (full_circle) drow = std::min(drow, n_theta - drow);
    return drow <= 2 && std::abs(a.col - b.col) <= 2;
  };
  std::vector<Peak> distinct;
  while (static_cast<int>(distinct.size()) < kMaxPeaksTried) {
    const Peak* best = nullptr;
    for (const Peak& p : peaks) {
      if (best != nullptr && !better(p, *best)) continue;
      bool taken = false;
      for (const Peak& q : distinct) taken = taken || near(p, q);
      if (!taken) best = &p;
    }
    if (best == nullptr) break;
    distinct.push_back(*best);
  }
  return distinct;
}

// Each theta row's cell for the point (x, y): cell[k] = j·n_theta + k for the rho column j that
// x cos θ_k + y sin θ_k falls in, or `spare` when it falls outside the n_rho columns. The vote
// loops' arithmetic, one row after another; GCC builds an AVX2 version beside the baseline one
// and picks by the CPU at run time (ifunc). Vector lanes do the same IEEE operations in the same
// order as the scalar code (no fused multiply-add: AVX2 alone has none), so the cells, hence
// the detections, are identical on every CPU.
#if defined(__GNUC__) && !defined(__clang__) && defined(__x86_64__)
__attribute__((target_clones("avx2", "default"), optimize("vect-cost-model=dynamic")))
#endif
void RowCells(double x, double y, const double* cos_k, const double* sin_k, int n_theta,
              double rho0, double inv_r_step, int n_rho, int spare, int* cell) {
  const double n_rho_d = n_rho;
  for (int k = 0; k < n_theta; ++k) {
    const double rho = x * cos_k[k] + y * sin_k[k];
    const double f = (rho - rho0) * inv_r_step + 0.5;  // cell j covers f in [j, j + 1)
    const bool inside = f >= 0.0 && f < n_rho_d;
    // (f is converted only when inside: outside, it may not fit an int)
    const int j = static_cast<int>(inside ? f : 0.0);
    cell[k] = inside ? j * n_theta + k : spare;
  }
}


}  // namespace

WallDetection DetectWall(const ScanPoints& points, const LineGate& gate,
                         const calib::DetectorOptions& options, double range_sigma_m,
                         bool keep_accumulator) {
  WallDetection det;
  const double t_step = options.hough_theta_step_rad;
  const double r_step = options.hough_rho_step_m;
  if (!(t_step > 0.0) || !(r_step > 0.0) || !std::isfinite(gate.theta_rad) ||
      !std::isfinite(gate.rho_m) || !(gate.theta_halfwidth_rad >= 0.0) ||
      !(gate.rho_halfwidth_m >= 0.0)) {
    det.reason = "invalid detector options or gate";
    return det;
  }
  const int num_points = static_cast<int>(points.p_scanner_m.size());
  assert(points.range_m.size() == points.p_scanner_m.size() &&
         points.mixed_suspect.size() == points.p_scanner_m.size());

  // ---- Accumulator geometry: only the gate (plus one margin cell each side). ----------------
  // Theta rows. A gate spanning the whole circle wraps instead of having margins.
  const double theta_c = WrapAngle(gate.theta_rad);
  const bool full_circle = gate.theta_halfwidth_rad >= kPi - 0.5 * t_step;
  int n_theta = 0, row_first = 0, row_last = 0;
  double theta0 = 0.0, theta_step = t_step;
  if (full_circle) {
    n_theta = std::max(1, static_cast<int>(std::lround(2.0 * kPi / t_step)));
    theta_step = 2.0 * kPi / n_theta;
    theta0 = theta_c - kPi + theta_step;
    row_first = 0;
    row_last = n_theta - 1;
  } else {
    const int n_half = static_cast<int>(std::floor(gate.theta_halfwidth_rad / t_step + 0.5));
    n_theta = 2 * n_half + 3;
    theta0 = theta_c - (n_half + 1) * t_step;
    row_first = 1;
    row_last = n_theta - 2;
  }
  // Rho columns: rho > 0 by convention, and no point can lie on a line farther than its range.
  double max_range = 0.0;
  for (int i = 0; i < num_points; ++i) {
    if (!points.mixed_suspect[i]) max_range = std::max(max_range, double(points.range_m[i]));
  }
  const double rho_gate_lo = std::max(0.0, gate.rho_m - gate.rho_halfwidth_m);
  const double rho_gate_hi = gate.rho_m + gate.rho_halfwidth_m;
  const double rho_hi = std::min(rho_gate_hi, max_range + r_step);
  if (num_points == 0 || rho_hi < rho_gate_lo) {
    det.reason = "no line within the gates";
    return det;
  }
  const int n_in = static_cast<int>(std::floor((rho_hi - rho_gate_lo) / r_step)) + 1;
  const int n_rho = n_in + 2;
  const double rho0 = rho_gate_lo - r_step;  // centre of column 0 (a margin column)
  if (static_cast<int64_t>(n_theta) * n_rho > kMaxCells) {
    det.reason = "accumulator too large (check hough steps)";
    return det;
  }

  // ---- Voting (Barawid 2007 Eq. 2: r = x cos θ + y sin θ). ---------------------------------------
  // Stored rho-major (one column of theta cells per rho cell): a point's votes in neighbouring
  // theta rows fall at nearly the same rho, so they land in the same cache lines. Transposed to
  // the documented theta-rows layout only when the caller keeps it.
  // The accumulator, the angle table and the per-point flags live in per-thread storage that
  // grows to the largest gate seen: a pass over a long log allocates nothing per scan. One cell
  // past the end takes the votes that fall outside the accumulator (no branch in the loop).
  thread_local std::vector<int> acc_storage;
  thread_local std::vector<double> cos_t, sin_t;
  thread_local std::vector<int> row_cells;
  thread_local std::vector<uint8_t> voter, withdrawn;
  const int cells = n_rho * n_theta;
  acc_storage.assign(static_cast<size_t>(cells) + 1, 0);
  int* const acc = acc_storage.data();
  const cv::Mat_<int> acc_t(n_rho, n_theta, acc);  // a view, no copy
  cos_t.resize(static_cast<size_t>(n_theta));
  sin_t.resize(static_cast<size_t>(n_theta));
  row_cells.resize(static_cast<size_t>(n_theta));
  for (int k = 0; k < n_theta; ++k) {
    cos_t[k] = std::cos(theta0 + k * theta_step);
    sin_t[k] = std::sin(theta0 + k * theta_step);
  }
  const double inv_r_step = 1.0 / r_step;
  const double min_voting_range = rho0 - 0.5 * r_step;  // |rho| <= range
  const double* const cos_k = cos_t.data();
  const double* const sin_k = sin_t.data();
  int* const cell_k = row_cells.data();
  // delta = +1 casts point i's votes, −1 withdraws them. Cell (j, k) is acc[j·n_theta + k].
  // Point i's cells, one per theta row, handed to on_cell (the spare cell `cells` for a row whose
  // rho falls outside the accumulator: no branch in the loop).
  auto for_each_cell = [&](int i, auto&& on_cell) {
    RowCells(points.p_scanner_m[i].x(), points.p_scanner_m[i].y(), cos_k, sin_k, n_theta, rho0,
             inv_r_step, n_rho, cells, cell_k);
    for (int k = 0; k < n_theta; ++k) on_cell(cell_k[k]);
  };
  auto vote = [&](int i, int delta) { for_each_cell(i, [&](int cell) { acc[cell] += delta; }); };
  // Points that vote: not mixed (they lie between two surfaces and must not build or shift a
  // peak), and not closer than the gate (|rho| <= range).
  voter.assign(static_cast<size_t>(num_points), 0);
  int64_t voters = 0;
  for (int i = 0; i < num_points; ++i) {
    voter[i] = !points.mixed_suspect[i] && points.range_m[i] >= min_voting_range;
    voters += voter[i];
  }
  // Cells with two votes or more are the only possible peaks (votes are only ever withdrawn
  // afterwards): listed once, in-gate rows and columns only. A wide gate (the first pass: about
  // 100 000 cells for 30 000 votes) notes the cells as they reach two votes, one test a vote;
  // a tight one (the second pass: 500 cells for 3 000 votes) looks through its cells after.
  // The peak search does not depend on the list's order. The list is written through a pointer
  // into per-thread storage that only grows (a push_back per cell was 3 % of a long run).
  thread_local std::vector<BusyCell> busy_storage;
  thread_local std::vector<int> reached_two;
  reached_two.clear();
  const bool note_while_voting = static_cast<int64_t>(cells) > 2 * voters * n_theta;
  if (!note_while_voting) {
    for (int i = 0; i < num_points; ++i) {
      if (voter[i]) vote(i, +1);
    }
  } else {
    for (int i = 0; i < num_points; ++i) {
      if (!voter[i]) continue;
      for_each_cell(i, [&](int cell) {
        if (++acc[cell] == 2) reached_two.push_back(cell);
      });
    }
  }
  // The list of busy cells, made when the peak search first needs it (a tight gate's first
  // peak is found without it, below). Votes withdrawn since voting only take cells off it, and
  // StrongestPeaks skips the cells that fell below two votes, so a late list finds the same peaks.
  BusyCell* busy_cells = nullptr;
  size_t num_busy = 0;
  auto list_busy_cells = [&]() {
    const size_t most_busy = note_while_voting
                                 ? reached_two.size()
                                 : static_cast<size_t>(n_in) * (row_last - row_first + 1);
    if (busy_storage.size() < most_busy) busy_storage.resize(most_busy);
    busy_cells = busy_storage.data();
    if (note_while_voting) {
      for (int cell : reached_two) {
        const int j = cell / n_theta, k = cell % n_theta;  // the spare cell has j = n_rho
        if (j >= 1 && j <= n_in && k >= row_first && k <= row_last) busy_cells[num_busy++] = {j, k};
      }
    } else {
      for (int j = 1; j <= n_in; ++j) {
        const int* column = acc + static_cast<size_t>(j) * n_theta;
        for (int k = row_first; k <= row_last; ++k) {
          if (column[k] >= 2) busy_cells[num_busy++] = {j, k};
        }
      }
    }
  };
  withdrawn.assign(static_cast<size_t>(num_points), 0);  // given to a line outside the gate
  if (keep_accumulator) {
    det.accumulator = acc_t.t();
    det.acc_theta0_rad = theta0;
    det.acc_theta_step_rad = theta_step;
    det.acc_rho0_m = rho0;
    det.acc_rho_step_m = r_step;
  }

  const double point_sigma = std::max(range_sigma_m, kMinPointSigmaM);
  const double trim_m = options.refine_sigma_factor * point_sigma;
  std::string first_reason;
  // A peak's refinement: found (det filled), a line outside the gate (its inliers withdrew their
  // votes: look again), or too few inliers (try the next peak).
  enum class Tried { kFound, kOutsideGate, kTooFew };
  auto try_peak = [&](const Peak& peak) {
    const double theta_p = theta0 + peak.row * theta_step;
    const double rho_p = rho0 + peak.col * r_step;
    const Eigen::Vector2d n_p(std::cos(theta_p), std::sin(theta_p));

    thread_local std::vector<int> candidates;  // reused: no allocation per scan once warm
    candidates.clear();
    const SegmentTest on_segment(gate, options.wall_extent_margin_m);
    for (int i = 0; i < num_points; ++i) {
      if (points.mixed_suspect[i] || withdrawn[i]) continue;
      const Eigen::Vector2d& p = points.p_scanner_m[i];
      if (std::abs(n_p.dot(p) - rho_p) > options.inlier_band_m) continue;
      if (gate.has_segment && !on_segment.Contains(p)) continue;
      candidates.push_back(i);
    }

    LineFit fit;
    std::vector<int> set;
    const bool ok = TrimmedFit(points, candidates, trim_m, options.inlier_band_m, &fit, &set);
    const int n = static_cast<int>(set.size());
    if (!ok || n < options.min_inliers) {
      if (first_reason.empty()) {
        first_reason = "only " + std::to_string(ok ? n : 0) + " inliers (need " +
                       std::to_string(options.min_inliers) + ")";
      }
      return Tried::kTooFew;
    }
    // The trimmed set chosen, its line along the beams (the trimming's few-mdeg difference
    // moves a residual by well under a millimetre: the set would not change).
    RefineAlongBeams(points, set, &fit);

    const double theta = WrapAngle(std::atan2(fit.normal.y(), fit.normal.x()));
    const double rho = fit.rho_m;
    const bool theta_in_gate =
        full_circle || std::abs(WrapAngle(theta - theta_c)) <=
                           gate.theta_halfwidth_rad + kGateToleranceCells * t_step;
    const bool rho_in_gate = rho >= rho_gate_lo - kGateToleranceCells * r_step &&
                             rho <= rho_gate_hi + kGateToleranceCells * r_step;
    if (!theta_in_gate || !rho_in_gate) {
      if (first_reason.empty()) {
        first_reason = Format("best line (theta %.2f deg, rho %.3f m) lies outside the gates",
                              theta * 180.0 / kPi, rho);
      }
      for (int i : set) {
        if (voter[i]) vote(i, -1);
        voter[i] = 0;
        withdrawn[i] = 1;
      }
      return Tried::kOutsideGate;
    }

    FillDetection(points, fit, set, range_sigma_m, peak.votes, &det);
    return Tried::kFound;
  };

  // A tight gate's first peak, without the list of busy cells: the in-gate cell with the most
  // votes (ties: the lower row, then column, StrongestPeaks's order) is the strongest local
  // maximum when no margin cell beside it has more. It is tried first; the list is made only
  // when it fails (a clean scan's wall is its first peak: the list was a quarter of the
  // detector's time).
  int round = 0;
  Peak tried_first;
  bool first_tried = false;
  if (!note_while_voting && !full_circle) {
    Peak best;
    for (int j = 1; j <= n_in; ++j) {
      const int* column = acc + static_cast<size_t>(j) * n_theta;
      for (int k = row_first; k <= row_last; ++k) {
        // Columns ascend, so among equal votes only a lower row replaces the best.
        if (column[k] > best.votes || (column[k] == best.votes && k < best.row)) {
          best = {column[k], k, j};
        }
      }
    }
    bool is_max = best.votes >= 2;
    for (int dj = -1; dj <= 1 && is_max; ++dj) {
      const int* column = acc + static_cast<size_t>(best.col + dj) * n_theta;
      for (int dk = -1; dk <= 1; ++dk) is_max = is_max && column[best.row + dk] <= best.votes;
    }
    if (is_max) {
      switch (try_peak(best)) {
        case Tried::kFound:
          return det;
        case Tried::kOutsideGate:
          round = 1;  // the first round ends at a line outside the gate
          break;
        case Tried::kTooFew:
          tried_first = best;  // the first round goes on with the next peaks
          first_tried = true;
          break;
      }
    }
  }

  // Each round: peaks -> refinement of the strongest few. A peak whose refined line falls
  // outside the gate belongs to a line beyond it (its flank reached into the gate, possibly as
  // several peaks along the gate's edge): its inliers withdraw their votes and the next round
  // looks again.
  for (; round < kMaxRounds; ++round) {
    if (busy_cells == nullptr) list_busy_cells();
    const std::vector<Peak> distinct =
        StrongestPeaks(acc_t, busy_cells, num_busy, n_theta, n_in, row_first, row_last,
                       full_circle);
    if (distinct.empty()) break;
    bool revote = false;
    for (const Peak& peak : distinct) {
      if (round == 0 && first_tried && peak.row == tried_first.row &&
          peak.col == tried_first.col) {
        continue;  // tried above
      }
      const Tried tried = try_peak(peak);
      if (tried == Tried::kFound) return det;
      if (tried == Tried::kOutsideGate) {
        revote = true;
        break;
      }
    }
    if (!revote) break;
  }
  det.reason = first_reason.empty() ? "no line within the gates" : first_reason;
  return det;
}

}  // namespace wallcal::calib
