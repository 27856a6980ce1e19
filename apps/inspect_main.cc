// inspect: the pre-flight check of a session or a log file, and CSV dumps of decoded records.
// Thin: the work and the error handling are in apps/inspect.cc (RunInspect), so tests can run
// the same code in-process.

#include <iostream>
#include <string>
#include <vector>

#include "preflight/inspect.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  return wallcal::preflight::RunInspect(args, std::cout, std::cerr);
}
