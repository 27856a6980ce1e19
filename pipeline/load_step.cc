// SPDX-License-Identifier: Apache-2.0
// The load step of a calibration run (pipeline/internal/steps.h): session.yaml, the options,
// the scanner preset and the --compare file; the inputs' digests started beside the work.

#include <algorithm>
#include <future>
#include <memory>
#include <thread>

#include "io/config/offsets_reader.h"
#include "io/config/session_reader.h"
#include "pipeline/config_dirs.h"
#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {

void Say(const ProgressFn& progress, Stage stage, const std::string& text) {
  if (progress) progress(Progress{stage, text, 0, 0, false});
}

LoadResult Load(const CalibrateRequest& request, RunState* state) {
  LoadResult loaded;
  loaded.session = io::ReadSession(request.session_path);
  if (request.scanner_index >= 0) {
    loaded.session = io::SessionForScanner(loaded.session, request.scanner_index);
  } else if (!request.scanner_id.empty()) {
    loaded.session = io::SessionForScannerId(loaded.session, request.scanner_id);
  } else if (!loaded.session.scanners.empty()) {
    throw io::InputError(io::Where(
        loaded.session.file, loaded.session.scanners.front().line,
        "scanners: lists several scanners; expected --scanner ID for this command (ID one of " +
            io::ScannerIds(loaded.session) + "), or wallcal calibrate, which takes them all"));
  }
  if (!request.config_path.empty()) loaded.options = ReadCalibrateOptions(request.config_path);
  loaded.options.Validate();
  loaded.options.solver.num_threads =
      request.threads > 0 ? request.threads
                          : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  // A measured preset beside the session (characterise writes <session>/scanners/NAME.yaml)
  // is found first, then the shipped ones (config_dirs.h).
  loaded.preset = LoadSessionPreset(loaded.session.scanner_model, loaded.session.dir);
  // The previous calibration is read now: a bad --compare file fails before the work.
  if (!request.compare_path.empty()) {
    state->previous = io::ReadPreviousOffsets(request.compare_path);
  }
  return loaded;
}

void StartDigests(const CalibrateRequest& request, const LoadResult& loaded, RunState* state) {
  const io::SessionSpec session = loaded.session;
  const std::string config_path = request.config_path;
  const std::string preset_path = loaded.preset.file;  // the file actually read
  const std::string compare_path = request.compare_path;
  const auto policy =
      loaded.options.solver.num_threads > 1 ? std::launch::async : std::launch::deferred;
  const std::shared_ptr<std::atomic<bool>> cancel = state->cancel_digests.flag;
  state->digests =
      std::async(policy, [session, config_path, preset_path, compare_path, cancel]() {
        return DigestInputs(session, config_path, preset_path, compare_path, cancel.get());
      }).share();
}

}  // namespace wallcal::pipeline
