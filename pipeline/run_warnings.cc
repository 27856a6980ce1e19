// SPDX-License-Identifier: Apache-2.0
#include "pipeline/run_warnings.h"

#include <iterator>

namespace wallcal::pipeline {

const char* WarningKindName(WarningKind kind) {
  switch (kind) {
    case WarningKind::kSurveyPoints: return "survey points";
    case WarningKind::kControlFit: return "control fit";
    case WarningKind::kPoseLog: return "pose log";
    case WarningKind::kGnssEpochTime: return "GNSS epoch time";
    case WarningKind::kLinesSkipped: return "lines skipped";
    case WarningKind::kFixesNotUsed: return "fixes not used";
    case WarningKind::kSliceTooLong: return "slice too long";
    case WarningKind::kMovingScansUsed: return "moving scans used";
    case WarningKind::kScansOutOfOrder: return "scans out of order";
    case WarningKind::kBeamCountMismatch: return "beam count mismatch";
    case WarningKind::kDrivesNotUsed: return "drives not used";
    case WarningKind::kFewIndependentGnssErrors:
      return "few independent GNSS errors";
    case WarningKind::kResiduals: return "residuals";
    case WarningKind::kSite: return "site";
    case WarningKind::kNoSigma: return "no sigma";
    case WarningKind::kForcedPresetMismatch: return "forced: preset mismatch";
    case WarningKind::kForcedObservability: return "forced: observability";
    case WarningKind::kForcedMountGuess: return "forced: mount guess";
  }
  return "";
}

bool IsForced(WarningKind kind) {
  return kind == WarningKind::kForcedPresetMismatch || kind == WarningKind::kForcedObservability ||
         kind == WarningKind::kForcedMountGuess;
}

void Append(Warnings* all, Warnings more) {
  all->insert(all->end(), std::make_move_iterator(more.begin()),
              std::make_move_iterator(more.end()));
}

std::vector<std::string> Messages(const Warnings& warnings) {
  std::vector<std::string> messages;
  messages.reserve(warnings.size());
  for (const Warning& w : warnings) messages.push_back(w.message);
  return messages;
}

}  // namespace wallcal::pipeline
