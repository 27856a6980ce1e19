// SPDX-License-Identifier: Apache-2.0
#pragma once
// The crew loop of guide_bench: a crew following the guide stop by stop on the simulator,
// against the field guide's fixed pattern.

#include <filesystem>

namespace wallcal::bench {

// Prints, over `seeds` seeds, the stations and time each crew needs to reach the default
// acceptance and the σ each reaches in a given time (median and worst). 0 on success.
int RunCrew(int seeds, const std::filesystem::path& scratch);

// Writes the fixed pattern's first `count` stations (seed 2000) as a session into `dir`.
int WriteFixed(int count, const std::filesystem::path& dir);

}  // namespace wallcal::bench
