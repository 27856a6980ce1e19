// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide program's command line (becomes `wallcal guide`): parsing, the follow loop and the
// exit status. The work is in guide.h.

#include <iosfwd>
#include <string>
#include <vector>

namespace wallcal::guide {

// Exit status: 0 done (and, with --follow, enough or stopped); 2 bad input or usage; 3 a bug.
int RunGuide(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);
int RunGuide(int argc, char** argv);

}  // namespace wallcal::guide
