// SPDX-License-Identifier: Apache-2.0
#pragma once
// The one information / covariance path of the adjustment. Everything that needs the mount's
// uncertainty (its σ, the observability checks, the refits of the repeatability analysis) takes
// it from the Gauss–Newton normal matrix JᵀJ of the problem at its current values (robust loss
// applied), with the nuisance parameters marginalised by a Schur complement.

#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

#include "solvers/mount_problem.h"

namespace wallcal::solvers {

// The information of the parameter blocks `kept` (mount first: x, y, yaw; then e.g. the clock
// offset and the drift rate, one value each), every other free parameter block marginalised.
// Units follow the blocks (1/m², 1/(m·rad), 1/rad², 1/s², ...). Empty when the problem cannot
// be evaluated or the nuisance block cannot be factored.
Eigen::MatrixXd MarginalInformation(MountProblem& problem, const std::vector<double*>& kept,
                                    int threads = 1);

// The information of the first k coordinates of a symmetric normal matrix (both triangles
// stored), the others marginalised (a Schur complement, the rest factored as a Jacobi-scaled
// sparse LDLᵀ). Empty when the rest cannot be factored.
Eigen::MatrixXd SchurComplement(const Eigen::SparseMatrix<double>& normal, int k);

// The mount's own information (x, y, yaw), everything else marginalised (clock offset and drift
// included). Singular when a mount direction is not determined at all; zero on failure.
Eigen::Matrix3d MountInformation(MountProblem& problem, int threads = 1);

// The covariance from an information matrix: false when it is empty, not finite or rank
// deficient (its reciprocal condition number, after scaling to a unit diagonal, below 1e-14).
bool CovarianceOfKept(const Eigen::MatrixXd& information, Eigen::MatrixXd* covariance);

}  // namespace wallcal::solvers
