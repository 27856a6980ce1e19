// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's report as text for people and as one JSON object.

#include <string>

#include "guide/guide.h"

namespace wallcal::guide {

// The stations, the predicted σ against the tolerances, enough yes/no and the next stops.
std::string GuideText(const GuideReport& report);

// A move in words a driver follows: "back 2.0 m, 1.5 m to the right, turn 15° left" (parts under
// 0.25 m or 1° left out; "stay where you are" when none is left).
std::string MoveWords(const VehicleMove& move);

// Stop i of the report (of `next`, or of the plan) in words: the wait, the move from the vehicle
// (or the stop before), how long to stand ("after 15 s: back 2.0 m, turn 15° left, stand 20 s");
// without a move, where to stand. Empty when there is no such stop.
std::string StopInstruction(const GuideReport& report, size_t i);

// Why the session is not enough yet, for people: the axis over its tolerance (and the scanner
// guided), or why no σ is known; empty when enough.
std::string NotEnoughReason(const GuideReport& report);

// One object: {"stations": N, "predicted_sigma": {"x_m": …, "y_m": …, "yaw_deg": …},
// "enough": true|false, "next": [{"vehicle_to_wall_deg": …, "distance_m": …, "dwell_s": …,
// "wait_s": …, "wall", "target": {x_m, y_m, yaw_deg}, "move": {forward_m, left_m, turn_deg} | null,
// "instruction", "sigma_after"}, …], then what a map of the site needs: "session", "scanner",
// "tolerance", "worst_axis", "worst_ratio", "reason", "message", "logged_s", "sigma_ellipse",
// "walls", "station_poses", "stops_without_wall", "vehicle", "mount", "scanner_pose",
// "warnings", "plan"}, on one line. A σ not known yet is null. For --plan, "next" lists the
// plan's stops. Positions are in the local frame (m), yaws ccw from grid east (deg).
std::string GuideJson(const GuideReport& report);

}  // namespace wallcal::guide
