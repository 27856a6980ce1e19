// SPDX-License-Identifier: Apache-2.0
#pragma once
// GNSS time from the receiver's own epoch. A logger stamps each GGA when it
// arrives: epoch + receiver/serial latency + a jitter of a few ms, on the logger's clock. The
// sentence also carries the epoch's UTC. The difference (logger stamp − UTC) is latency + the
// logger clock's offset to UTC (+ a slow clock drift); fitted robustly over the log it maps each
// epoch onto the logger clock without the jitter:
//   stamp_s = utc_epoch_s + offset_s + drift · (utc_epoch_s − reference_utc_s)
// so the fix is placed at its epoch (plus the mean latency, which the other streams' delays are
// estimated against), not at its jittered arrival.

#include <cstdint>
#include <vector>

#include "io/types.h"

namespace wallcal::calib {

enum class EpochMappingStatus {
  kMapped,         // fixes carry the mapped epoch
  kNoLoggerStamp,  // plain capture: the fixes are stamped by their UTC already
  kDisabled,       // alignment.gnss_epoch_time: false; arrival stamps kept
  kTooFew,         // fewer than kMinEpochFixes fixes with both times; arrival stamps kept
  kInconsistent,   // scatter, drift or order beyond belief; arrival stamps kept
};
const char* EpochMappingStatusName(EpochMappingStatus status);  // "mapped", ...

inline constexpr int kMinEpochFixes = 10;
// Beyond these the (logger − UTC) difference is not one latency + clock: the fit is refused.
inline constexpr double kMaxEpochJitterS = 0.1;     // robust σ of the residuals
inline constexpr double kMaxEpochDriftRatio = 1e-3;  // 1000 ppm (a PC clock is ~50 ppm)
inline constexpr double kMaxEpochOutlierShare = 0.1;  // share of fixes beyond 5 σ of the fit

struct GnssEpochMapping {
  EpochMappingStatus status = EpochMappingStatus::kNoLoggerStamp;
  int64_t fixes = 0;            // fixes with both a logger stamp and UTC
  double offset_s = io::kNaN;       // mean (logger − UTC) at reference_utc_s: latency + clock offset
  double drift = 0.0;           // logger clock rate error (s/s)
  double reference_utc_s = 0.0;
  double jitter_s = io::kNaN;       // robust σ (1.4826 MAD) of (logger − UTC) about the fit
  double max_residual_s = io::kNaN;  // largest |residual| (s)
  int64_t outliers = 0;          // residuals beyond 5 σ (left out of the fit, still mapped)
};

// Fits the mapping over the fixes that carry utc_epoch_s and, when `enabled` and the fit is
// consistent, sets each such fix's stamp_s to its mapped epoch. Other fixes, and all fixes when
// the fit is refused, keep their arrival stamps. Never throws.
GnssEpochMapping MapGnssEpochs(std::vector<io::GnssFix>* fixes, bool enabled);

}  // namespace wallcal::calib
