// SPDX-License-Identifier: Apache-2.0
#pragma once
// For the program-level tests: every library of the flow reachable by its short names inside
// namespace wallcal (RunCalibration, FormatSummary, WriteSimulatedSession, ...).

namespace wallcal {
namespace pipeline {}
namespace outputs {}
namespace analysis {}
namespace preflight {}
namespace sim {}
using namespace wallcal::pipeline;   // NOLINT
using namespace wallcal::outputs;    // NOLINT
using namespace wallcal::analysis;   // NOLINT
using namespace wallcal::preflight;  // NOLINT
using namespace wallcal::sim;        // NOLINT
}  // namespace wallcal
