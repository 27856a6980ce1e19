// SPDX-License-Identifier: Apache-2.0
// guide: at the wall, the σ the session's logs hold now and the next stops (guide/run_guide.h).

#include "guide/run_guide.h"

int main(int argc, char** argv) { return wallcal::guide::RunGuide(argc, argv); }
