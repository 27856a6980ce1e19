// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: the other YAML inputs — a scanner preset, calibrate options, a simulation
// configuration and a truth.yaml — all read from the same bytes. Each must give a validated
// struct or throw io::InputError.

#include <cstdint>

#include "fuzz_util.h"
#include "io/config/session_reader.h"
#include "pipeline/calibrate_options.h"
#include "sim/simulation_config.h"

namespace {

template <class F>
void Try(F read) {
  try {
    read();
  } catch (const wallcal::io::InputError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = wallcal::fuzz::Scratch().Write("config.yaml", data, size);
  Try([&] { wallcal::io::ReadScannerPreset(path); });
  Try([&] { wallcal::pipeline::ReadCalibrateOptions(path); });
  Try([&] { wallcal::sim::ReadSimulationConfig(path); });
  Try([&] { wallcal::sim::ReadTruthYaml(path); });
  return 0;
}
