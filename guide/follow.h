// SPDX-License-Identifier: Apache-2.0
#pragma once
// Following a session while it is recorded: the logs are looked at every period, and the guide
// refreshes (reading what they gained) when they changed, until the session is enough or the
// time limit.

#include <functional>
#include <string>

#include "guide/guide_session.h"

namespace wallcal::guide {

struct FollowOptions {
  double period_s = 1.0;      // between looks at the logs (> 0)
  double max_seconds = -1.0;  // stop after this long (< 0: no limit)
  // A log that has not grown for this long is warned of (GuideWarningKind::kLogStale), and so is
  // a GNSS log that grew for this long without a fix of accepted quality (kFixesNotAccepted);
  // s, > 0.
  double stale_after_s = 10.0;
};

// Why following ended.
enum class FollowEnd { kEnough, kTimeLimit };

// Refreshes `session` whenever its logs' sizes or modification times changed, and calls `show`
// with each report, its warnings joined by those of the logs over time (stale logs, fixes not
// accepted); the last report is shown again when those change without a refresh. A refresh that throws io::InputError (logs that hold too little yet: no
// fix, no scan) calls `waiting` with the message and is tried again when the logs change.
// Returns when a report is enough or at the time limit. session.yaml itself unreadable:
// io::InputError.
FollowEnd Follow(GuideSession* session, const FollowOptions& follow,
                 const std::function<void(const GuideReport&)>& show,
                 const std::function<void(const std::string&)>& waiting);

}  // namespace wallcal::guide
