// SPDX-License-Identifier: Apache-2.0
// The normal matrix accumulated block by block (solvers/normal_matrix.h) against JᵀJ of the
// Jacobian Ceres itself evaluates (Problem::Evaluate, loss applied), on problems with every
// feature the adjustment uses: a robust loss in both its regions, a manifold holding one
// coordinate, a constant block, residual blocks that follow each other with the same blocks
// (one summed run) and with different ones.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <array>
#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "solvers/normal_matrix.h"

namespace wallcal::solvers {
namespace {

// r = [a·x0·y1 − c0; sin(x1) + b·y0² − c1]: non-linear in both blocks.
struct Pair {
  Pair(double a_in, double b_in, double c0_in, double c1_in)
      : a(a_in), b(b_in), c0(c0_in), c1(c1_in) {}
  template <typename T>
  bool operator()(const T* x, const T* y, T* r) const {
    r[0] = a * x[0] * y[1] - c0;
    r[1] = sin(x[1]) + b * y[0] * y[0] - c1 + x[2];
    return true;
  }
  double a, b, c0, c1;
};

Eigen::MatrixXd CeresNormal(ceres::Problem& problem, const std::vector<double*>& columns) {
  ceres::Problem::EvaluateOptions options;
  options.parameter_blocks = columns;
  options.apply_loss_function = true;
  ceres::CRSMatrix crs;
  EXPECT_TRUE(problem.Evaluate(options, nullptr, nullptr, nullptr, &crs));
  Eigen::MatrixXd j = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r) {
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) j(r, crs.cols[k]) = crs.values[k];
  }
  return j.transpose() * j;
}

TEST(ProblemNormalMatrixTest, MatchesCeresJacobianWithLossManifoldAndConstantBlocks) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<std::array<double, 3>> xs(4);
  std::vector<std::array<double, 2>> ys(6);
  for (auto& x : xs) x = {1.0 + u(rng), u(rng), u(rng)};
  for (auto& y : ys) y = {u(rng), 1.0 + u(rng)};
  ceres::Problem problem;
  // Large offsets c put some residuals in the Huber loss's linear region (ρ″ < 0: rows scaled
  // by √ρ′ only), small ones in its quadratic region; one block has a loss with ρ″ > 0, where
  // the correction also scales the residual's direction.
  struct Convex : ceres::LossFunction {
    void Evaluate(double s, double rho[3]) const override {  // ρ = s + s²/2
      rho[0] = s + 0.5 * s * s;
      rho[1] = 1.0 + s;
      rho[2] = 1.0;
    }
  };
  ceres::LossFunction* huber = new ceres::HuberLoss(0.5);
  ceres::LossFunction* convex = new Convex;
  int added = 0;
  for (size_t i = 0; i < xs.size(); ++i) {
    for (size_t k = 0; k < ys.size(); ++k) {
      // Runs of residual blocks on the same pair, then a change of pair.
      for (int repeat = 0; repeat < 3; ++repeat) {
        const double c = (added % 4 == 0) ? 5.0 * u(rng) : 0.1 * u(rng);
        auto* cost = new ceres::AutoDiffCostFunction<Pair, 2, 3, 2>(
            new Pair(1.0 + u(rng), 0.5 * u(rng), c, 0.1 * u(rng)));
        ceres::LossFunction* loss = added % 7 == 3 ? nullptr : huber;
        problem.AddResidualBlock(cost, loss, xs[i].data(), ys[k].data());
        ++added;
      }
    }
  }
  problem.AddResidualBlock(new ceres::AutoDiffCostFunction<Pair, 2, 3, 2>(
                               new Pair(2.0, 0.3, 0.4, -0.2)),
                           convex, xs[0].data(), ys[1].data());
  // x1 holds its middle coordinate; y5 is constant (no column).
  problem.SetManifold(xs[1].data(), new ceres::SubsetManifold(3, {1}));
  problem.SetParameterBlockConstant(ys[5].data());

  std::vector<double*> columns;
  for (size_t k = 0; k < ys.size() - 1; ++k) columns.push_back(ys[k].data());
  for (auto& x : xs) columns.push_back(x.data());
  const Eigen::MatrixXd expected = CeresNormal(problem, columns);
  for (int threads : {1, 2, 3}) {
    Eigen::SparseMatrix<double> normal;
    ASSERT_TRUE(ProblemNormalMatrix(problem, columns, threads, &normal));
    const Eigen::MatrixXd got(normal);
    ASSERT_EQ(got.rows(), expected.rows());
    ASSERT_EQ(got.cols(), expected.cols());
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12 * expected.cwiseAbs().maxCoeff())
        << "threads " << threads;
  }
}

// A cost whose evaluation fails: no matrix, and false.
struct Failing : ceres::SizedCostFunction<1, 1> {
  bool Evaluate(double const* const*, double* r, double**) const override {
    r[0] = 0.0;
    return false;
  }
};

TEST(ProblemNormalMatrixTest, FailsWhenACostFails) {
  double x[1] = {0.0};
  ceres::Problem problem;
  problem.AddResidualBlock(new Failing, nullptr, x);
  Eigen::SparseMatrix<double> normal;
  EXPECT_FALSE(ProblemNormalMatrix(problem, {x}, 1, &normal));
}

}  // namespace
}  // namespace wallcal::solvers
