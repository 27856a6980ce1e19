// SPDX-License-Identifier: Apache-2.0
#pragma once
// characterise: the scanner itself measured on a wall session. A surveyed wall seen from known
// poses is the motion table of Ye & Borenstein 2002 and Okubo, Ye & Borenstein 2009: every beam
// that hits the wall has a true range, so the logged range z can be fitted to the papers' model
//   z = n·true + c + drift(t) + ξ,  ξ ~ N(0, σ),  logged as Int(z) (the range quantum),
// and turned into the presets' correction ŷ = k·z + b (k = 1/n, b = −c/n).
//
// Flow: pipeline::RunCalibration loads the session, ties the survey, interpolates the poses and
// finds the wall in every scan (and, without --mount, estimates the mount); beam_returns.cc then
// re-reads the scans and pairs each beam with its true range; range_fit.cc fits the model with
// the errors every beam of a station shares (GNSS position, heading, the surveyed wall, the
// mount) as parameters with their priors, so the σ of k and b includes them; scanner_stats.cc
// measures the quantum, the noise's growth, the incidence limit and the mixed pixels.
//
// Units: metres, radians, seconds inside; degrees only in printed text and the preset file.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "io/types.h"
#include "pipeline/calibration.h"

namespace wallcal::characterise {

struct CharacteriseRequest {
  std::string session_path;  // session.yaml or its folder
  std::string config_path;   // calibrate options (YAML); empty: defaults
  std::string mount_path;    // an earlier offsets.yaml; empty: the mount is estimated jointly
  int threads = 0;           // as calibrate's --threads
  std::string preset_name;   // the measured preset's name; empty: "<model>_measured"
  std::string scanner_id;    // a session with scanners: the scanner to characterise
  std::vector<std::string> command_line;
};

// Why a parameter (or the whole run) is not determined. A message says what to collect.
enum class Undetermined {
  kNone,
  kCalibrationFailed,  // the session gave no wall observations / no mount (calibrate's reason)
  kNoStations,         // no stop-and-go stations (characterise uses standing scans only)
  kTooFewRanges,       // fewer than kMinWallReturns wall returns
  kScaleK,             // σ(k) above kMaxSigmaK: station distances span too little
  kOffsetB,            // σ(b) above kMaxSigmaB: incidences / headings span too little
};

inline constexpr int kMinWallReturns = 2000;
inline constexpr int kMinStations = 4;
// σ(k) is judged by the range error it leaves at the scanner's working range
// (min(max range, 20 m)): at most 2 cm (0.1 % for an LMS at 20 m, 0.5 % for a 4 m URG).
inline constexpr double kMaxScaleErrorM = 0.02;
inline constexpr double kMaxWorkingRangeM = 20.0;
inline constexpr double kMaxSigmaB = 0.005;   // m

// An estimate and its 1σ; sigma < 0 when not determined.
struct Value {
  double value = 0.0;
  double sigma = -1.0;
  bool known() const { return sigma >= 0.0; }
};

// The range model and what is fitted with it (range_fit.h).
struct RangeModel {
  Value n, c_m;           // z = n·true + c (c: the session-mean offset, drift included)
  Value k, b_m;           // ŷ = k·z + b, the presets' range_correction
  Value sigma_m;          // beam noise ξ, the quantum's share (q²/12) removed (Sheppard)
  double residual_rms_m = 0.0;  // of the fitted beams, quantum included
  double corr_k_b = 0.0;
  // Mount used or estimated (vehicle frame) and its σ after the fit; corr of b with mount x.
  Value mount_x_m, mount_y_m, mount_yaw_rad;
  double corr_b_mount_x = 0.0;
  bool mount_given = false;       // from --mount (a prior), else estimated here
  bool mount_sigma_given = false; // --mount had a covariance
  // Drift: offset relative to the first scan at knot times (s since the first used scan).
  bool drift_fitted = false;
  std::vector<double> drift_knots_s;
  std::vector<Value> drift_at_knots_m;
  Value drift_first_hour_m;  // drift(min(1 h, session)) − drift(0)
  double drift_span_s = 0.0; // the time that drift figure covers
  int beams_used = 0, beams_rejected = 0, stations = 0;
};

// Noise growth: least-squares slope of the squared residual against a quantity, as dσ/dx.
struct NoiseTrend {
  Value slope;        // m per m (range) or m per rad (incidence)
  bool grows = false; // significant (> 4σ) and positive
};

struct ScannerStats {
  double quantum_m = 0.0;     // 0.01 (cm mode), 0.001 (mm mode) or 0: finer / not a grid
  double quantum_share = 0.0; // share of the wall returns on that grid
  NoiseTrend noise_vs_range, noise_vs_incidence;
  // Incidence beyond which fewer than half the beams that should hit the wall return a range
  // near it (5° bins). Not reached: limit_reached false, limit = the largest incidence seen.
  bool incidence_limit_reached = false;
  Value incidence_limit_rad;
  std::vector<double> incidence_bin_deg, return_share;  // the curve, bins of 5°
  // Beams whose footprint straddles a wall end: share returning neither the wall (within 4σ)
  // nor nothing; binomial σ.
  Value mixed_pixel_rate;
  int edge_beams = 0;
};

// One fitted beam, for the plots (range error = z − (n·true + c + drift) + (n − 1)·true + c:
// the error of the raw reading against the true range).
struct PlotPoint {
  double true_range_m, incidence_rad, time_s, error_m;
};

struct Characterisation {
  pipeline::CalibrationResult calibration;  // the session as calibrate saw it
  RangeModel model;
  ScannerStats stats;
  io::ScannerPreset preset;  // the measured preset (written by io::FormatScannerPreset)
  Undetermined undetermined = Undetermined::kNone;
  std::string reason;  // for people: the parameter and what to collect
  std::vector<std::string> notes;     // what the data fix and what they cannot separate
  std::vector<std::string> warnings;
  std::vector<PlotPoint> plot;        // a subsample of the fitted beams (≤ 4000)
  double session_span_s = 0.0;
  double distance_min_m = 0.0, distance_max_m = 0.0;    // stations' scanner-to-wall distances
  double incidence_min_rad = 0.0, incidence_max_rad = 0.0;  // of the fitted beams
  bool ok() const { return undetermined == Undetermined::kNone; }
};

// Runs the whole characterisation. Throws io::InputError for bad input (session, --mount file);
// a session that cannot determine the scanner comes back with undetermined != kNone.
Characterisation Characterise(const CharacteriseRequest& request);

// The lines of the stdout summary.
std::string Summary(const Characterisation& result);

// SVG plots (range error against true range, incidence and time) as (file name, content).
std::vector<std::pair<std::string, std::string>> Plots(const Characterisation& result);

}  // namespace wallcal::characterise
