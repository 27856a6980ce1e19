// inspect: the pre-flight check of a session or a log file, and CSV dumps of decoded records.
// Thin: the work and the error handling are in apps/inspect.cc (RunInspect), so tests can run
// the same code in-process.

#include <iostream>
#include <string>
#include <vector>

#include "io/output_file.h"
#include "preflight/inspect.h"

int main(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  // Names and text from the files never reach the terminal raw (control characters escaped).
  wallcal::io::ControlEscapingStreamBuf out_buffer(std::cout.rdbuf());
  wallcal::io::ControlEscapingStreamBuf err_buffer(std::cerr.rdbuf());
  std::ostream out(&out_buffer);
  std::ostream err(&err_buffer);
  const int status = wallcal::preflight::RunInspect(args, out, err);
  out.flush();
  err.flush();
  return status;
}
