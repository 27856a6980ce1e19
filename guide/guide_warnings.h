// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the guide warns the crew of while a session is collected, as typed values: the kind is
// what a display may act on (a colour, an icon), the message is for people.

#include <string>
#include <vector>

namespace wallcal::guide {

enum class GuideWarningKind {
  // --follow: a log has not grown for FollowOptions::stale_after_s (the logger stopped, a cable).
  kLogStale,
  // No GNSS fix of accepted quality (gnss.min_fix_quality: RTK fixed by default) over a recent
  // period while the GNSS log grew (float or worse), or a run's fixes not used.
  kFixesNotAccepted,
  // A surveyed wall not detected from any station so far.
  kWallNotSeen,
  // The vehicle stood where no wall was detected (dwells of the pose logs without a station).
  kStopsWithoutWall,
  // One of calibrate's run warnings on the logs read (pipeline::WarningKind), passed on.
  kRun,
};

// "log stale", "fixes not accepted", "wall not seen", "stops without wall", "run".
const char* GuideWarningKindName(GuideWarningKind kind);

struct GuideWarning {
  GuideWarningKind kind = GuideWarningKind::kRun;
  std::string subject;  // what it is about: a log's path, a wall's id; may be empty
  std::string message;  // one line for people
};

}  // namespace wallcal::guide
