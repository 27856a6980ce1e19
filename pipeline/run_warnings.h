// SPDX-License-Identifier: Apache-2.0
#pragma once
// What weakens a calibration without stopping it, as typed values: the kind says what a program
// may act on, the message is for people (the summary, offsets.yaml's `warnings:`, the report).
// Each step's result carries the warnings it raised; CalibrationResult::AllWarnings lists them
// in step order.

#include <string>
#include <vector>

namespace wallcal::pipeline {

enum class WarningKind {
  kSurveyPoints,              // the survey reader combined or questioned repeated points
  kControlFit,                // the control points fit the survey worse than RTK + total station
  kPoseLog,                   // the GNSS / heading reader's own warnings (a recording's topics)
  kGnssEpochTime,             // the GGA epochs could not be mapped onto the logger clock
  kLinesSkipped,              // a log had lines that could not be read
  kFixesNotUsed,              // GGA fixes below gnss.min_fix_quality or out of time order
  kSliceTooLong,              // alignment.segment_max_s long against solver.gnss_bias_tau_s
  kMovingScansUsed,           // too few stations: the drives are used with a clock offset
  kScansOutOfOrder,           // scans not later than the scan before them
  kBeamCountMismatch,         // scans whose beam count is not the preset's
  kDrivesNotUsed,             // the drives' timing was not determined: their scans left out
  kFewIndependentGnssErrors,  // the stations count as few independent GNSS errors
  kResiduals,                 // the residual analysis flagged a pattern
  kSite,                      // the site's geometry: the attitude stream, the yard, the height
  kNoSigma,                   // the method gives no σ (barawid)
  kForcedPresetMismatch,      // --force: the preset does not fit the scans
  kForcedObservability,       // --force: an observability check refused the estimate
  kForcedMountGuess,          // --force: the estimate is outside scanner.mount_guess's tolerance
};

// "survey points", "control fit", ... (lower case, for logs and tests).
const char* WarningKindName(WarningKind kind);
// True for the kinds written only because of --force.
bool IsForced(WarningKind kind);

struct Warning {
  WarningKind kind = WarningKind::kSurveyPoints;
  std::string message;  // one line for people; a forced kind's (IsForced) starts with "FORCED: "
};
using Warnings = std::vector<Warning>;

// Appends `more` to `*all`, keeping the order.
void Append(Warnings* all, Warnings more);
// The messages alone, in order (offsets.yaml, the summary, the report).
std::vector<std::string> Messages(const Warnings& warnings);

}  // namespace wallcal::pipeline
