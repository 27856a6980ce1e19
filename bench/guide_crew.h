// SPDX-License-Identifier: Apache-2.0
#pragma once
// The crew loop of guide_bench: a crew following the guide stop by stop on the simulator,
// against the field guide's fixed pattern.

#include <filesystem>

namespace wallcal::bench {

// Prints, over `seeds` seeds, the stations and time each crew needs to reach the default
// acceptance and the σ each reaches in a given time (median and worst). 0 on success.
int RunCrew(int seeds, const std::filesystem::path& scratch);

// One guided crew (seed 2000), printing the guide's report after each stop; the session is left
// in `dir`.
int Transcript(const std::filesystem::path& dir);

}  // namespace wallcal::bench
