// SPDX-License-Identifier: Apache-2.0
#include "sim/session_cut.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/types.h"

namespace wallcal::sim {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ReadLines(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw io::InputError(path.string() + ":0: cannot be read; expected a session file");
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

void WriteLines(const fs::path& path, const std::vector<std::string>& lines) {
  std::ofstream out(path, std::ios::trunc);
  for (const std::string& line : lines) out << line << '\n';
  if (!out) throw io::InputError(path.string() + ":0: cannot be written");
}

// A CARMEN line's ipc timestamp: the third field from the end.
double CarmenStamp(const std::string& line) {
  std::istringstream in(line);
  std::vector<std::string> fields;
  for (std::string f; in >> f;) fields.push_back(f);
  return fields.size() >= 3 ? std::strtod(fields[fields.size() - 3].c_str(), nullptr) : 0.0;
}

}  // namespace

void CutTextSession(const std::string& from_dir, const std::string& to_dir, double scan_fraction) {
  fs::create_directories(to_dir);
  for (const fs::directory_entry& entry : fs::directory_iterator(from_dir)) {
    if (entry.is_regular_file()) {
      fs::copy_file(entry.path(), fs::path(to_dir) / entry.path().filename(),
                    fs::copy_options::overwrite_existing);
    }
  }
  const std::vector<std::string> scans = ReadLines(fs::path(from_dir) / "scans.clf");
  size_t scan_lines = 0;
  for (const std::string& line : scans) scan_lines += (!line.empty() && line[0] != '#') ? 1 : 0;
  const size_t keep = static_cast<size_t>(std::ceil(scan_fraction * scan_lines));
  std::vector<std::string> kept;
  size_t seen = 0;
  double last_s = -1e300;
  for (const std::string& line : scans) {
    const bool scan = !line.empty() && line[0] != '#';
    if (scan && seen >= keep) break;
    kept.push_back(line);
    if (scan) {
      ++seen;
      last_s = CarmenStamp(line);
    }
  }
  WriteLines(fs::path(to_dir) / "scans.clf", kept);
  for (const char* name : {"gnss.nmea", "heading.nmea"}) {
    std::vector<std::string> lines;
    for (const std::string& line : ReadLines(fs::path(from_dir) / name)) {
      if (std::strtod(line.c_str(), nullptr) > last_s) break;
      lines.push_back(line);
    }
    WriteLines(fs::path(to_dir) / name, lines);
  }
}

}  // namespace wallcal::sim
