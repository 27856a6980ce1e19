// SPDX-License-Identifier: Apache-2.0
#pragma once
// The top of the report: the decision section (verdict with its reasons, the error budget, the
// change since the previous calibration, the error against truth.yaml when known). Internal to
// outputs/report.cc; renders the result only.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "pipeline/calibration.h"
#include "pipeline/multi_scanner.h"

namespace wallcal::outputs {

// What a page shows as the calibration's outcome: a run's own estimate, verdict and change, or
// for a scanner of several its joint mount, σ, clock offset, verdict and change. Everything
// else on the page (residuals, error budget, repeatability, counts) is the run's own.
struct PageOutcome {
  const pipeline::CalibrationResult* run = nullptr;
  bool joint = false;
  calib::Mount mount;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  double clock_offset_s = 0.0;
  const pipeline::Decision* decision = nullptr;
  const std::optional<pipeline::Change>* change = nullptr;
  const pipeline::ReportData* report = nullptr;  // the drawings around `mount`
};
PageOutcome OwnOutcome(const pipeline::CalibrationResult& run);
PageOutcome JointOutcome(const pipeline::CalibrationResult& own,
                         const pipeline::JointScannerResult& joint);

// <section id="decision">...</section>
std::string DecisionSectionHtml(const PageOutcome& outcome);

}  // namespace wallcal::outputs
