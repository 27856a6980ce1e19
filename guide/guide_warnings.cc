// SPDX-License-Identifier: Apache-2.0
#include "guide/guide_warnings.h"

#include "common/enum_text.h"

namespace wallcal::guide {

const char* GuideWarningKindName(GuideWarningKind kind) {
  static constexpr EnumText<GuideWarningKind> kNames[] = {
      {GuideWarningKind::kLogStale, "log stale"},
      {GuideWarningKind::kFixesNotAccepted, "fixes not accepted"},
      {GuideWarningKind::kWallNotSeen, "wall not seen"},
      {GuideWarningKind::kStopsWithoutWall, "stops without wall"},
      {GuideWarningKind::kRun, "run"},
  };
  return TextOf(kNames, kind, "");
}

}  // namespace wallcal::guide
