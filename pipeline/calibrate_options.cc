// SPDX-License-Identifier: Apache-2.0
#include "pipeline/calibrate_options.h"

namespace wallcal::pipeline {

namespace {

// The top-level keys beside the modules' sections.
template <class V>
void VisitRunOptions(V& v, CalibrateOptions& o) {
  v.Integer("first_pass_max_scans", o.first_pass_max_scans, io::AtLeast(1));
}

}  // namespace

void AcceptanceOptions::Validate() const {
  io::CheckOptions("acceptance.", *this, VisitAcceptanceOptions<io::OptionChecker>);
}

void CalibrateOptions::Validate() const {
  detector.Validate();
  alignment.Validate();
  solver.Validate();
  acceptance.Validate();
  io::CheckOptions("", *this, VisitRunOptions<io::OptionChecker>);
}

CalibrateOptions ReadCalibrateOptions(const std::string& file) {
  CalibrateOptions options;
  io::ReadOptionsFile(
      file,
      [&options](io::OptionsMap& top) {
        top.Section("detector",
                    [&](io::OptionsMap& m) { calib::VisitDetectorOptions(m, options.detector); });
        top.Section("alignment",
                    [&](io::OptionsMap& m) { calib::VisitAlignmentOptions(m, options.alignment); });
        top.Section("solver",
                    [&](io::OptionsMap& m) { solvers::VisitSolverOptions(m, options.solver); });
        top.Section("acceptance",
                    [&](io::OptionsMap& m) { VisitAcceptanceOptions(m, options.acceptance); });
        VisitRunOptions(top, options);
      },
      [&options] { options.Validate(); });
  return options;
}

}  // namespace wallcal::pipeline
