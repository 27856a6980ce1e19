// SPDX-License-Identifier: Apache-2.0
#include "solvers/information.h"

#include <ceres/ceres.h>

#include <Eigen/Eigenvalues>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>
#include <algorithm>
#include <cmath>

#include "solvers/normal_matrix.h"

namespace wallcal::solvers {

Eigen::MatrixXd MarginalInformation(MountProblem& mp, const std::vector<double*>& kept,
                                    int threads) {
  int k = 0;
  for (double* block : kept) {
    if (!mp.problem.HasParameterBlock(block)) return Eigen::MatrixXd();
    k += mp.problem.ParameterBlockTangentSize(block);  // a held coordinate has no column
  }
  std::vector<double*> blocks;
  mp.problem.GetParameterBlocks(&blocks);
  std::vector<double*> columns = kept;
  for (double* block : blocks) {
    if (std::find(kept.begin(), kept.end(), block) != kept.end() ||
        mp.problem.IsParameterBlockConstant(block)) {
      continue;
    }
    columns.push_back(block);
  }
  Eigen::SparseMatrix<double> h;
  if (!ProblemNormalMatrix(mp.problem, columns, threads, &h)) return Eigen::MatrixXd();
  return SchurComplement(h, k);
}

Eigen::MatrixXd SchurComplement(const Eigen::SparseMatrix<double>& h, int k) {
  const int n = static_cast<int>(h.rows()) - k;
  if (n < 0 || h.cols() != h.rows()) return Eigen::MatrixXd();
  Eigen::MatrixXd information = Eigen::MatrixXd(h.topLeftCorner(k, k));
  if (n > 0) {
    // Schur complement: the nuisance block has priors on every coordinate, so it is positive
    // definite. It is sparse (a GNSS-error slice touches its neighbours in the Gauss–Markov
    // chain and the few session-wide blocks: walls, drift, clock offset) and large for long
    // sessions (two unknowns per 0.25 s slice): factored as a sparse LDLᵀ. Its scales differ by
    // many orders of magnitude (a drift rate in rad/s with a prior of 2.4e-6 has information
    // ~1e11, a GNSS bias ~1e4): Jacobi-scaled to a unit diagonal, with a tiny ridge against
    // round-off only.
    Eigen::SparseMatrix<double> hnn = h.bottomRightCorner(n, n);
    Eigen::VectorXd scale(n);
    for (int i = 0; i < n; ++i) {
      scale[i] = 1.0 / std::sqrt(std::max(std::abs(hnn.coeff(i, i)), 1e-300));
    }
    hnn = scale.asDiagonal() * hnn * scale.asDiagonal();
    Eigen::SparseMatrix<double> ridge(n, n);
    ridge.setIdentity();
    hnn += 1e-12 * ridge;
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(hnn);
    if (ldlt.info() != Eigen::Success) return Eigen::MatrixXd();
    const Eigen::MatrixXd hnk = scale.asDiagonal() * Eigen::MatrixXd(h.bottomLeftCorner(n, k));
    information -= hnk.transpose() * ldlt.solve(hnk);
  }
  return 0.5 * (information + information.transpose());
}

Eigen::Matrix3d MountInformation(MountProblem& mp, int threads) {
  std::vector<double*> kept = {mp.mount.data()};
  const Eigen::MatrixXd information = MarginalInformation(mp, kept, threads);
  if (information.rows() != 3) return Eigen::Matrix3d::Zero();
  return information;
}

bool CovarianceOfKept(const Eigen::MatrixXd& information, Eigen::MatrixXd* covariance) {
  const int k = static_cast<int>(information.rows());
  if (k == 0 || information.cols() != k || !information.allFinite()) return false;
  Eigen::VectorXd scale(k);
  for (int i = 0; i < k; ++i) {
    if (!(information(i, i) > 0.0)) return false;
    scale[i] = 1.0 / std::sqrt(information(i, i));
  }
  const Eigen::MatrixXd scaled = scale.asDiagonal() * information * scale.asDiagonal();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scaled);
  if (eigen.info() != Eigen::Success) return false;
  const double largest = eigen.eigenvalues().maxCoeff();
  const double smallest = eigen.eigenvalues().minCoeff();
  if (!(largest > 0.0) || !(smallest > 1e-14 * largest)) return false;
  const Eigen::MatrixXd inverse = eigen.eigenvectors() *
                                  eigen.eigenvalues().cwiseInverse().asDiagonal() *
                                  eigen.eigenvectors().transpose();
  *covariance = scale.asDiagonal() * inverse * scale.asDiagonal();
  *covariance = 0.5 * (*covariance + covariance->transpose());
  return covariance->allFinite();
}

}  // namespace wallcal::solvers
