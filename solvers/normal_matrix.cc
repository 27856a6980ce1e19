// SPDX-License-Identifier: Apache-2.0
#include "solvers/normal_matrix.h"

#include <ceres/cost_function.h>
#include <ceres/loss_function.h>
#include <ceres/manifold.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <thread>
#include <unordered_map>

namespace wallcal::solvers {
namespace {

using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// A parameter block as a set of columns.
struct Column {
  int offset = 0;        // first column
  int tangent = 0;       // columns
  int ambient = 0;       // values
  RowMajor plus_jacobian;  // ambient x tangent; empty: no manifold (the identity)
};

// The blocks (i, j), i <= j (column indices), of JᵀJ summed so far: dense, row-major, in one
// pool. Residual blocks that follow each other with the same columns (the scans of one GNSS
// slice) are summed into a dense `run` first and handed over once.
class Accumulator {
 public:
  explicit Accumulator(const std::vector<Column>& columns) : columns_(columns) {}

  // Adds the Jacobian rows `rows` (residuals x Σ tangent sizes, the blocks `blocks` side by
  // side) to the current run, starting a new run when the blocks differ.
  void Add(const std::vector<int>& blocks, const RowMajor& rows) {
    if (blocks != run_blocks_) {
      Flush();
      run_blocks_ = blocks;
      run_ = Eigen::MatrixXd::Zero(rows.cols(), rows.cols());
    }
    run_.noalias() += rows.transpose() * rows;
  }

  void Flush() {
    int offset_a = 0;
    for (size_t a = 0; a < run_blocks_.size(); ++a) {
      const Column& ca = columns_[run_blocks_[a]];
      int offset_b = 0;
      for (size_t b = 0; b < run_blocks_.size(); ++b) {
        const Column& cb = columns_[run_blocks_[b]];
        if (run_blocks_[a] <= run_blocks_[b]) {
          double* cell = Cell(run_blocks_[a], run_blocks_[b]);
          for (int r = 0; r < ca.tangent; ++r) {
            for (int c = 0; c < cb.tangent; ++c) {
              cell[r * cb.tangent + c] += run_(offset_a + r, offset_b + c);
            }
          }
        }
        offset_b += cb.tangent;
      }
      offset_a += ca.tangent;
    }
    run_blocks_.clear();
  }

  // Adds another accumulator's sums to this one (both flushed).
  void Merge(const Accumulator& other) {
    for (const auto& [key, at] : other.cells_) {
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      double* cell = Cell(a, b);
      const int size = columns_[a].tangent * columns_[b].tangent;
      for (int k = 0; k < size; ++k) cell[k] += other.pool_[at + k];
    }
  }

  // Both triangles of the sum.
  void Triplets(std::vector<Eigen::Triplet<double>>* out) const {
    for (const auto& [key, at] : cells_) {
      const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
      const Column& ca = columns_[a];
      const Column& cb = columns_[b];
      for (int r = 0; r < ca.tangent; ++r) {
        for (int c = 0; c < cb.tangent; ++c) {
          const double v = pool_[at + static_cast<size_t>(r * cb.tangent + c)];
          out->emplace_back(ca.offset + r, cb.offset + c, v);
          if (a != b) out->emplace_back(cb.offset + c, ca.offset + r, v);
        }
      }
    }
  }

 private:
  double* Cell(int a, int b) {
    const uint64_t key = (static_cast<uint64_t>(a) << 32) | static_cast<uint32_t>(b);
    const auto [it, inserted] = cells_.try_emplace(key, pool_.size());
    if (inserted) pool_.resize(pool_.size() + columns_[a].tangent * columns_[b].tangent, 0.0);
    return pool_.data() + it->second;
  }

  const std::vector<Column>& columns_;
  std::unordered_map<uint64_t, size_t> cells_;
  std::vector<double> pool_;
  std::vector<int> run_blocks_;
  Eigen::MatrixXd run_;
};

// Scales the Jacobian rows of a residual block as Ceres's robust-loss corrector does (Triggs
// et al. 1999, "Bundle adjustment: a modern synthesis", Sec. 4.3): with s = |r|² and ρ′, ρ″ of
// the loss at s, J ← √ρ′ (I − α r rᵀ / s) J, α = 1 − √(1 + 2 s ρ″/ρ′) when ρ″ > 0, else 0.
void CorrectForLoss(const ceres::LossFunction& loss, const double* residuals, int num_residuals,
                    RowMajor* rows) {
  const Eigen::Map<const Eigen::VectorXd> r(residuals, num_residuals);
  const double s = r.squaredNorm();
  double rho[3];
  loss.Evaluate(s, rho);
  const double sqrt_rho1 = std::sqrt(std::max(0.0, rho[1]));
  if (s > 0.0 && rho[2] > 0.0 && rho[1] > 0.0) {
    const double alpha = 1.0 - std::sqrt(1.0 + 2.0 * s * rho[2] / rho[1]);
    const Eigen::RowVectorXd rt_j = r.transpose() * *rows;
    *rows -= (alpha / s) * r * rt_j;
  }
  *rows *= sqrt_rho1;
}

// Sums the residual blocks ids[begin, end) into `sum`.
bool AccumulateRange(const ceres::Problem& problem,
                     const std::vector<ceres::ResidualBlockId>& ids, size_t begin, size_t end,
                     const std::unordered_map<const double*, int>& index,
                     const std::vector<Column>& columns, Accumulator* sum) {
  std::vector<double*> parameters;
  std::vector<double> residuals;
  std::vector<std::vector<double>> jacobian_storage;
  std::vector<double*> jacobians;
  std::vector<int> blocks;
  RowMajor rows;
  for (size_t id = begin; id < end; ++id) {
    problem.GetParameterBlocksForResidualBlock(ids[id], &parameters);
    const ceres::CostFunction* cost = problem.GetCostFunctionForResidualBlock(ids[id]);
    const int m = cost->num_residuals();
    const std::vector<int32_t>& sizes = cost->parameter_block_sizes();
    residuals.resize(static_cast<size_t>(m));
    if (jacobian_storage.size() < parameters.size()) jacobian_storage.resize(parameters.size());
    jacobians.resize(parameters.size());
    blocks.clear();
    int width = 0;
    for (size_t b = 0; b < parameters.size(); ++b) {
      const auto found = index.find(parameters[b]);
      jacobians[b] = nullptr;
      if (found == index.end()) continue;  // constant: no column
      jacobian_storage[b].resize(static_cast<size_t>(m) * sizes[b]);
      jacobians[b] = jacobian_storage[b].data();
      blocks.push_back(found->second);
      width += columns[found->second].tangent;
    }
    if (blocks.empty()) continue;
    if (!cost->Evaluate(parameters.data(), residuals.data(), jacobians.data())) return false;
    rows.resize(m, width);
    int at = 0;
    size_t next_block = 0;  // blocks[] lists the columns of the non-null jacobians, in order
    for (size_t b = 0; b < parameters.size(); ++b) {
      if (jacobians[b] == nullptr) continue;
      const Column& column = columns[blocks[next_block++]];
      const Eigen::Map<const RowMajor> ambient(jacobians[b], m, sizes[b]);
      if (column.plus_jacobian.size() == 0) {
        rows.middleCols(at, column.tangent) = ambient;
      } else {
        rows.middleCols(at, column.tangent).noalias() = ambient * column.plus_jacobian;
      }
      at += column.tangent;
    }
    if (!rows.allFinite()) return false;
    const ceres::LossFunction* loss = problem.GetLossFunctionForResidualBlock(ids[id]);
    if (loss != nullptr) CorrectForLoss(*loss, residuals.data(), m, &rows);
    sum->Add(blocks, rows);
  }
  sum->Flush();
  return true;
}

}  // namespace

bool ProblemNormalMatrix(const ceres::Problem& problem, const std::vector<double*>& columns,
                         int threads, Eigen::SparseMatrix<double>* normal) {
  std::vector<Column> layout(columns.size());
  std::unordered_map<const double*, int> index;
  int total = 0;
  for (size_t k = 0; k < columns.size(); ++k) {
    Column& column = layout[k];
    column.offset = total;
    column.ambient = problem.ParameterBlockSize(columns[k]);
    column.tangent = problem.ParameterBlockTangentSize(columns[k]);
    const ceres::Manifold* manifold = problem.GetManifold(columns[k]);
    if (manifold != nullptr) {
      column.plus_jacobian.resize(column.ambient, column.tangent);
      if (!manifold->PlusJacobian(columns[k], column.plus_jacobian.data())) return false;
    }
    total += column.tangent;
    index.emplace(columns[k], static_cast<int>(k));
  }
  std::vector<ceres::ResidualBlockId> ids;
  problem.GetResidualBlocks(&ids);

  const size_t workers = std::clamp<size_t>(static_cast<size_t>(std::max(1, threads)), 1,
                                            std::max<size_t>(1, ids.size() / 1024));
  std::vector<Accumulator> sums(workers, Accumulator(layout));
  std::vector<char> ok(workers, 0);
  const size_t per = (ids.size() + workers - 1) / workers;
  const auto run = [&](size_t w) {
    const size_t begin = std::min(ids.size(), w * per);
    const size_t end = std::min(ids.size(), begin + per);
    ok[w] = AccumulateRange(problem, ids, begin, end, index, layout, &sums[w]);
  };
  std::vector<std::thread> pool;
  for (size_t w = 1; w < workers; ++w) pool.emplace_back(run, w);
  run(0);
  for (std::thread& t : pool) t.join();
  for (size_t w = 0; w < workers; ++w) {
    if (!ok[w]) return false;
    if (w > 0) sums[0].Merge(sums[w]);
  }
  std::vector<Eigen::Triplet<double>> triplets;
  sums[0].Triplets(&triplets);
  normal->resize(total, total);
  normal->setFromTriplets(triplets.begin(), triplets.end());
  return true;
}

}  // namespace wallcal::solvers
