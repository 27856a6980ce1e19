// SPDX-License-Identifier: Apache-2.0
#include "calib/time_alignment_options.h"

namespace wallcal::calib {

void AlignmentOptions::Validate() const {
  io::CheckOptions("alignment.", *this, VisitAlignmentOptions<io::OptionChecker>);
}

}  // namespace wallcal::calib
