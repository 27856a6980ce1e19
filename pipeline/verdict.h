// SPDX-License-Identifier: Apache-2.0
#pragma once
// The decision a field engineer acts on: ACCEPT, REVIEW or REJECT against the tolerances of
// `acceptance:` (pipeline::AcceptanceOptions), with the reasons; the change since the previous
// calibration (calibrate --compare); and the provenance of the run. Computed once here, shown by
// the summary, offsets.yaml and the report.

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "analysis/error_budget.h"
#include "io/types.h"
#include "pipeline/calibrate_options.h"
#include "solvers/mount_solver.h"

namespace wallcal::pipeline {

enum class Verdict {
  kAccept,  // usable, σ within the tolerances, no change beyond them, nothing flagged
  kReview,  // usable, but a person should look: a change beyond the tolerances, σ unknown,
            // residual trends flagged
  kReject,  // not determined, forced, refused by a check, or σ beyond the tolerances
};
const char* VerdictName(Verdict verdict);  // "ACCEPT", "REVIEW", "REJECT"

// The change since a previous calibration: now − previous.
struct Change {
  std::string previous_file;
  std::string previous_created_utc;  // empty when that file does not say
  double dx_m = 0.0, dy_m = 0.0, dyaw_rad = 0.0;
  // |Δ| / (σ_now² + σ_previous²)^½ per axis; NaN when either σ is unknown.
  double x_sigmas = 0.0, y_sigmas = 0.0, yaw_sigmas = 0.0;
  // A relative transform of several scanners only: the previous file holds it the other way
  // round, (to, from), and its pose and covariance were inverted for the comparison
  // (pipeline::InvertPrevious).
  bool previous_inverted = false;
};

// Now minus previous (yaw wrapped to (−π, π]); σ units from both covariances (a covariance
// with a NaN or a non-positive diagonal counts as unknown).
Change CompareMounts(const solvers::MountEstimate& now, const io::PreviousOffsets& previous);
// The same for a mount and its covariance (m, rad) that are not an estimate of their own (a
// scanner's joint mount among several, a relative transform).
Change CompareMounts(const calib::Mount& now, const Eigen::Matrix3d& covariance,
                     const io::PreviousOffsets& previous);

struct Decision {
  Verdict verdict = Verdict::kReject;
  std::vector<std::string> reasons;  // why not ACCEPT (empty for ACCEPT) or what was checked
};

// What a verdict rests on: the estimate (its usability and σ), whether it was forced or has no
// σ, the change since the previous calibration, the tolerances and the flagged residual trends.
struct DecisionInputs {
  const solvers::MountEstimate* estimate = nullptr;
  std::string why;  // why a refused estimate is refused; empty: its own message
  bool forced = false;
  bool sigma_known = true;
  const std::optional<Change>* change = nullptr;
  const pipeline::AcceptanceOptions* acceptance = nullptr;
  int flagged_trends = 0;
  // What the site's geometry leaves for a person to settle (pipeline::SiteReviews): each a
  // reason for REVIEW.
  std::vector<std::string> site_reviews;
};
Decision Decide(const DecisionInputs& in);

// The SHA-256 of each input file of the session (session.yaml, scanner, GNSS and heading logs,
// survey, options file when given, scanner preset file read, previous offsets of --compare when
// given), in that order, one entry per distinct path.
// cancel (may be null): stop early when it turns true (digests then empty).
std::vector<io::InputFileDigest> DigestInputs(const io::SessionSpec& session,
                                              const std::string& config_path,
                                              const std::string& preset_path,
                                              const std::string& compare_path,
                                              const std::atomic<bool>* cancel = nullptr);

}  // namespace wallcal::pipeline
