// SPDX-License-Identifier: Apache-2.0
#include "solvers/solver_options.h"

namespace wallcal::solvers {

void SolverOptions::Validate() const {
  io::CheckOptions("solver.", *this, VisitSolverOptions<io::OptionChecker>);
}

}  // namespace wallcal::solvers
