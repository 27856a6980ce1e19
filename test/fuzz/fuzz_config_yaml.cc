// libFuzzer target: the other YAML inputs — a scanner preset, calibrate options, a simulation
// configuration and a truth.yaml — all read from the same bytes. Each must give a validated
// struct or throw io::InputError.

#include <cstdint>

#include "fuzz_util.h"
#include "io/session_reader.h"

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
  Try([&] { wallcal::io::ReadCalibrateOptions(path); });
  Try([&] { wallcal::io::ReadSimulationConfig(path); });
  Try([&] { wallcal::io::ReadTruthYaml(path); });
  return 0;
}
