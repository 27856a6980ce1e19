// SPDX-License-Identifier: Apache-2.0
#pragma once
// The Gauss–Newton normal matrix JᵀJ of a Ceres problem at its current values, accumulated
// residual block by residual block: nothing the size of the Jacobian is ever stored (an
// hour-long session's Jacobian in compressed rows is about 75 MB, and Ceres's own
// Problem::Evaluate makes two copies of it). Used by solvers/information.cc.

#include <vector>

#include <Eigen/SparseCore>
#include <ceres/problem.h>

namespace wallcal::solvers {

// JᵀJ over the parameter blocks `columns` (in that order, each in its tangent space, i.e.
// through its manifold), symmetric, both triangles stored. The robust loss is applied to each
// residual block as Ceres applies it in its solver (Triggs et al.'s correction: the rows scaled
// by √ρ′ and, where ρ″ > 0, the residual's direction by a further factor). A residual block's
// parameter blocks that are not in `columns` must be constant in the problem (they add no
// column). Runs over `threads` threads; the result depends on the count only through the
// order of floating-point sums. False when a cost function fails to evaluate.
bool ProblemNormalMatrix(const ceres::Problem& problem, const std::vector<double*>& columns,
                         int threads, Eigen::SparseMatrix<double>* normal);

}  // namespace wallcal::solvers
