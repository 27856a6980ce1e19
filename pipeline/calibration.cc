// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibration.h"

#include <filesystem>

#include "pipeline/session.h"

namespace wallcal::pipeline {

Warnings CalibrationResult::AllWarnings() const {
  Warnings all;
  for (const Warnings* step : {&survey.warnings, &poses.warnings, &site.warnings, &detection.warnings,
                               &solve.warnings, &finish.warnings}) {
    all.insert(all.end(), step->begin(), step->end());
  }
  return all;
}

std::map<calib::ScanSkip, int64_t> CalibrationResult::ScansSkipped() const {
  std::map<calib::ScanSkip, int64_t> all = detection.scans_skipped;
  for (const auto& [reason, count] : solve.scans_skipped) all[reason] += count;
  return all;
}

const std::string& CalibrationResult::Why() const {
  return finish.refusal_advice ? *finish.refusal_advice : solve.estimate.message;
}

solvers::SolverOptions CalibrationResult::SolverInUse() const {
  solvers::SolverOptions solver = loaded.options.solver;
  if (poses.interpolator == nullptr) return solver;  // no poses yet: the configured noise
  solver.gnss_white_sigma_m = poses.white_noise.gnss_white_sigma_m;
  solver.heading_sigma_rad = poses.white_noise.heading_sigma_rad;
  return solver;
}

const char* NoiseSourceName(NoiseSource source) {
  switch (source) {
    case NoiseSource::kConfigured:
      return "configured";
    case NoiseSource::kMeasuredAtStops:
      return "measured at the stops";
    case NoiseSource::kMeasuredOnDrives:
      return "measured on the drives";
  }
  return "?";
}

const char* SiteTermName(SiteTermKind kind) {
  switch (kind) {
    case SiteTermKind::kVehicleAttitude: return "vehicle attitude";
    case SiteTermKind::kLeverArmHeight: return "lever arm height";
    case SiteTermKind::kScannerTilt: return "scanner tilt";
    case SiteTermKind::kWallLean: return "wall lean";
  }
  return "?";
}

const char* SiteTermKey(SiteTermKind kind) {
  switch (kind) {
    case SiteTermKind::kVehicleAttitude: return "vehicle_attitude";
    case SiteTermKind::kLeverArmHeight: return "lever_arm_height";
    case SiteTermKind::kScannerTilt: return "scanner_tilt";
    case SiteTermKind::kWallLean: return "wall_lean";
  }
  return "?";
}

CalibrationResult RunCalibration(const CalibrateRequest& request, const ProgressFn& progress) {
  return CalibrationSession(request, progress).Run();
}

std::string DefaultOutputPath(const io::SessionSpec& session) {
  return (std::filesystem::path(session.dir) / "offsets.yaml").string();
}

}  // namespace wallcal::pipeline
