// SPDX-License-Identifier: Apache-2.0
#include "pipeline/verdict.h"

#include <cmath>
#include <limits>
#include <set>

#include "common/angles.h"
#include "common/enum_text.h"
#include "common/format.h"
#include "common/sha256.h"

namespace wallcal::pipeline {
namespace {

double SigmaOf(double variance) {
  return std::isfinite(variance) && variance > 0.0 ? std::sqrt(variance) : std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

const char* VerdictName(Verdict verdict) {
  static const EnumText<Verdict> kTexts[] = {
      {Verdict::kAccept, "ACCEPT"}, {Verdict::kReview, "REVIEW"}, {Verdict::kReject, "REJECT"}};
  return TextOf(kTexts, verdict, "REJECT");
}

Change CompareMounts(const solvers::MountEstimate& now, const io::PreviousOffsets& previous) {
  return CompareMounts(now.mount, now.covariance, previous);
}

Change CompareMounts(const calib::Mount& now, const Eigen::Matrix3d& covariance,
                     const io::PreviousOffsets& previous) {
  Change change;
  change.previous_file = previous.file;
  change.previous_created_utc = previous.created_utc;
  change.dx_m = now.x_m - previous.x_m;
  change.dy_m = now.y_m - previous.y_m;
  change.dyaw_rad = WrapAngle(now.yaw_rad - previous.yaw_rad);
  const double deltas[3] = {change.dx_m, change.dy_m, change.dyaw_rad};
  double* sigmas[3] = {&change.x_sigmas, &change.y_sigmas, &change.yaw_sigmas};
  for (int k = 0; k < 3; ++k) {
    const double now_sigma = SigmaOf(covariance(k, k));
    const double previous_sigma =
        previous.sigma_known ? SigmaOf(previous.covariance[4 * k]) : std::numeric_limits<double>::quiet_NaN();
    *sigmas[k] = std::abs(deltas[k]) / std::hypot(now_sigma, previous_sigma);
  }
  return change;
}

Decision Decide(const DecisionInputs& in) {
  Decision d;
  const solvers::MountEstimate& e = *in.estimate;
  const pipeline::AcceptanceOptions& a = *in.acceptance;
  auto reject = [&d](const std::string& why) {
    d.verdict = Verdict::kReject;
    d.reasons.push_back(why);
  };
  auto review = [&d](const std::string& why) {
    if (d.verdict == Verdict::kAccept) d.verdict = Verdict::kReview;
    d.reasons.push_back(why);
  };
  if (!e.usable) {
    d.verdict = Verdict::kReject;
    d.reasons.push_back("mount not determined: " + (in.why.empty() ? e.message : in.why));
    return d;
  }
  d.verdict = Verdict::kAccept;
  if (in.forced) reject("forced: written although a check refused it (see the warnings)");
  if (!in.sigma_known) {
    review("no σ: the method does not give one; run the adjustment (--method ceres)");
  } else {
    const double sx = SigmaOf(e.covariance(0, 0)), sy = SigmaOf(e.covariance(1, 1));
    const double syaw = SigmaOf(e.covariance(2, 2));
    if (!(std::max(sx, sy) <= a.max_sigma_xy_m)) {
      reject(Format("σ x %.1f mm, y %.1f mm: beyond acceptance.max_sigma_xy_m %.1f mm", sx * 1e3,
                    sy * 1e3, a.max_sigma_xy_m * 1e3));
    }
    if (!(syaw <= a.max_sigma_yaw_rad)) {
      reject(Format("σ yaw %.3f°: beyond acceptance.max_sigma_yaw_deg %.3f°", syaw * kRadToDeg,
                    a.max_sigma_yaw_rad * kRadToDeg));
    }
  }
  if (in.change && in.change->has_value()) {
    const Change& c = **in.change;
    if (std::max(std::abs(c.dx_m), std::abs(c.dy_m)) > a.max_change_xy_m) {
      review(Format("moved x %+.1f mm, y %+.1f mm since %s: beyond acceptance.max_change_xy_m "
                    "%.1f mm (was the scanner moved or bumped?)",
                    c.dx_m * 1e3, c.dy_m * 1e3, c.previous_file.c_str(), a.max_change_xy_m * 1e3));
    }
    if (std::abs(c.dyaw_rad) > a.max_change_yaw_rad) {
      review(Format("turned %+.3f° since %s: beyond acceptance.max_change_yaw_deg %.3f°",
                    c.dyaw_rad * kRadToDeg, c.previous_file.c_str(),
                    a.max_change_yaw_rad * kRadToDeg));
    }
    const double largest = std::max({c.x_sigmas, c.y_sigmas, c.yaw_sigmas});
    if (largest > a.max_change_sigmas) {
      review(Format("the change is %.1f combined σ: more than the two calibrations' errors "
                    "explain (acceptance.max_change_sigmas %.1f)",
                    largest, a.max_change_sigmas));
    }
  }
  for (const std::string& why : in.site_reviews) review(why);
  if (in.flagged_trends > 0) {
    review(std::to_string(in.flagged_trends) +
           " residual trend(s) flagged: a model error (range scale, timing, wall shape) may "
           "bias the mount (see the report's diagnostics)");
  }
  return d;
}

std::vector<io::InputFileDigest> DigestInputs(const io::SessionSpec& session,
                                              const std::string& config_path,
                                              const std::string& preset_path,
                                              const std::string& compare_path,
                                              const std::atomic<bool>* cancel) {
  std::vector<io::InputFileDigest> out;
  std::set<std::string> seen;
  auto add = [&](const std::string& role, const std::string& path) {
    if (path.empty() || !seen.insert(path).second) return;
    out.push_back(io::InputFileDigest{role, path, Sha256OfFile(path, cancel)});
  };
  add("session", session.file);
  add("scanner_log", session.scanner_log);
  add("gnss_log", session.gnss_log);
  add("heading_log", session.heading_log);
  add("survey", session.survey_points);
  add("options", config_path);
  add("scanner_preset", preset_path);
  add("previous_offsets", compare_path);
  return out;
}

}  // namespace wallcal::pipeline
