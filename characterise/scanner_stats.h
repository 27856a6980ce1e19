// SPDX-License-Identifier: Apache-2.0
#pragma once
// What the wall returns say about the scanner beyond its range model: the range quantum, the
// noise's growth with range and incidence, the incidence limit and the mixed pixels at the
// wall's ends. Internal to characterise/.

#include "characterise/beam_returns.h"
#include "characterise/characterisation.h"
#include "characterise/range_fit.h"

namespace wallcal::characterise {

// The grid the raw wall readings lie on: 0.01 m (cm mode) when at least 98 % of them are within
// 0.2 mm of a centimetre, else 0.001 m likewise, else 0 (finer, or no grid).
double RangeQuantum(const BeamSet& set, double* share);

// The statistics after the fit (`fit` for the same `set`).
ScannerStats MeasureStats(const BeamSet& set, const FitOutput& fit, double quantum_m,
                          double quantum_share);

}  // namespace wallcal::characterise
