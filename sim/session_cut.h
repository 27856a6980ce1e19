// SPDX-License-Identifier: Apache-2.0
#pragma once
// A simulated text session as it stood part-way through its recording: the first share of its
// scans, and the GNSS and heading lines up to the last of them. For the guide's checks (its
// prediction on a session cut after 30 %, 60 % and 100 % of its scans against calibrate's σ on
// the same cut) and its benchmarks.

#include <string>

namespace wallcal::sim {

// Copies the session folder `from_dir` (scans.clf, gnss.nmea, heading.nmea as the simulator
// writes them, and every other file unchanged) to `to_dir`, keeping the first
// ceil(scan_fraction × scans) scan lines (comment lines kept) and the GNSS and heading lines
// stamped at or before the last scan kept. scan_fraction in (0, 1]. Throws io::InputError when a
// file cannot be read or written.
void CutTextSession(const std::string& from_dir, const std::string& to_dir, double scan_fraction);

}  // namespace wallcal::sim
