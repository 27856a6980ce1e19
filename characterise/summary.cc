// SPDX-License-Identifier: Apache-2.0
// The stdout summary of a characterisation (characterise/characterisation.h).

#include <sstream>

#include "characterise/characterisation.h"
#include "common/angles.h"
#include "common/format.h"

namespace wallcal::characterise {
namespace {

// "1.000812 +- 0.000120" (or "not determined").
std::string Pm(const Value& v, const char* format, double scale = 1.0) {
  if (!v.known()) return Format(format, scale * v.value) + " (not determined)";
  return Format(format, scale * v.value) + " +- " + Format(format, scale * v.sigma);
}

}  // namespace

std::string Summary(const Characterisation& r) {
  std::ostringstream out;
  const RangeModel& m = r.model;
  const ScannerStats& s = r.stats;
  out << "characterise: session '" << r.calibration.loaded.session.name << "', scanner preset '"
      << r.calibration.loaded.preset.name << "'\n";
  out << Format("  wall returns: %d fitted, %d rejected (> 4 sigma), %d stations, %.1f-%.1f m, "
                "%.0f-%.0f deg incidence, %.0f s\n",
                m.beams_used, m.beams_rejected, m.stations, r.distance_min_m, r.distance_max_m,
                r.incidence_min_rad * kRadToDeg, r.incidence_max_rad * kRadToDeg,
                r.session_span_s);
  if (r.undetermined == Undetermined::kCalibrationFailed ||
      r.undetermined == Undetermined::kNoStations) {
    out << "NOT DETERMINED: " << r.reason << "\n";
    return out.str();
  }
  out << "  range correction (y = k*z + b):\n";
  out << "k = " << Pm(m.k, "%.7f") << "\n";
  out << "b_mm = " << Pm(m.b_m, "%.3f", 1e3) << Format("   (corr(k, b) %.2f)\n", m.corr_k_b);
  out << "  simulation model (z = n*true + c):\n";
  out << "n = " << Pm(m.n, "%.6f") << "\n";
  out << "c_mm = " << Pm(m.c_m, "%.3f", 1e3) << "\n";
  out << "sigma_mm = " << Pm(m.sigma_m, "%.4f", 1e3)
      << Format("   (residual RMS %.3f mm, quantum included)\n", 1e3 * m.residual_rms_m);
  out << "  noise growth: "
      << Pm(s.noise_vs_range.slope, "%.3f", 1e3) << " mm/m with range"
      << (s.noise_vs_range.grows ? " (grows)" : "") << "; "
      << Pm(s.noise_vs_incidence.slope, "%.3f", 1e3 / kRadToDeg) << " mm/deg with incidence"
      << (s.noise_vs_incidence.grows ? " (grows)" : "") << "\n";
  out << "  range quantum: "
      << (s.quantum_m >= 0.01   ? "10 mm (cm mode)"
          : s.quantum_m > 0.0 ? "1 mm (mm mode)"
                              : "finer than 1 mm or none")
      << Format(" (%.1f %% of the readings on it)\n", 100.0 * s.quantum_share);
  if (s.incidence_limit_reached) {
    out << "  incidence limit: " << Pm(s.incidence_limit_rad, "%.1f", kRadToDeg)
        << " deg (returns below half beyond)\n";
  } else {
    out << Format("  incidence limit: not reached (returns up to %.1f deg, the largest seen)\n",
                  s.incidence_limit_rad.value * kRadToDeg);
  }
  out << "  mixed pixels at the wall's ends: "
      << (s.mixed_pixel_rate.known()
              ? Pm(s.mixed_pixel_rate, "%.1f", 100.0) + Format(" %% of %d edge beams", s.edge_beams)
              : Format("not measured (%d edge beams)", s.edge_beams))
      << "\n";
  if (m.drift_fitted) {
    out << "drift_mm = " << Pm(m.drift_first_hour_m, "%.2f", 1e3)
        << Format("   (over the first %.0f min)\n", m.drift_span_s / 60.0);
  }
  out << "  mount " << (m.mount_given ? "(from --mount)" : "(estimated jointly)") << ": x "
      << Pm(m.mount_x_m, "%.4f") << " m, y " << Pm(m.mount_y_m, "%.4f") << " m, yaw "
      << Pm(m.mount_yaw_rad, "%.3f", kRadToDeg) << " deg\n";
  for (const std::string& note : r.notes) out << "  note: " << note << "\n";
  for (const std::string& warning : r.warnings) out << "  warning: " << warning << "\n";
  if (!r.ok()) out << "NOT DETERMINED: " << r.reason << "\n";
  return out.str();
}

}  // namespace wallcal::characterise
