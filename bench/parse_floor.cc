// SPDX-License-Identifier: Apache-2.0
// The floor of the speed benchmark (bench/speed_bench.sh): the least any program must spend to
// read a CARMEN scan log, measured on the same file in the same run as calibrate. One thread,
// the C library only: getline for each line, strtod for every whitespace-separated field that
// is a number (the hostname is passed over). Prints the line and number counts and their sum,
// so that no work can be optimised away.
//
// usage: parse_floor LOG

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: parse_floor LOG\n");
    return 2;
  }
  std::FILE* file = std::fopen(argv[1], "r");
  if (file == nullptr) {
    std::perror(argv[1]);
    return 2;
  }
  char* line = nullptr;
  size_t capacity = 0;
  long lines = 0, numbers = 0;
  double sum = 0.0;
  while (getline(&line, &capacity, file) > 0) {
    ++lines;
    char* p = line;
    while (*p != '\0') {
      while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
      if (*p == '\0') break;
      char* end = nullptr;
      const double value = std::strtod(p, &end);
      if (end == p) {  // not a number: a keyword or the hostname
        while (*p != '\0' && *p != ' ' && *p != '\t' && *p != '\n') ++p;
        continue;
      }
      sum += value;
      ++numbers;
      p = end;
    }
  }
  std::free(line);
  std::fclose(file);
  std::printf("%ld lines, %ld numbers, sum %.6g\n", lines, numbers, sum);
  return 0;
}
