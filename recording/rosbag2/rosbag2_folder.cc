// SPDX-License-Identifier: Apache-2.0
#include "recording/rosbag2/internal/rosbag2_folder.h"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "io/types.h"

namespace wallcal::recording {
namespace {

namespace fs = std::filesystem;

bool IsStorageFile(const fs::directory_entry& entry) {
  std::error_code ec;
  const std::string ext = entry.path().extension().string();
  return (ext == ".db3" || ext == ".mcap") && entry.is_regular_file(ec);
}

// The digits of a run without its leading zeros ("007" -> "7").
std::string_view Number(std::string_view digits) {
  const size_t first = digits.find_first_not_of('0');
  return first == std::string_view::npos ? std::string_view() : digits.substr(first);
}

}  // namespace

bool IsRosbag2Folder(const std::string& folder) {
  std::error_code ec;
  if (fs::is_regular_file(fs::path(folder) / "metadata.yaml", ec)) return true;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder, ec)) {
    if (IsStorageFile(entry)) return true;
  }
  return false;
}

bool SplitOrderLess(const std::string& a, const std::string& b) {
  const auto digit = [](char c) { return std::isdigit(static_cast<unsigned char>(c)) != 0; };
  size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (digit(a[i]) && digit(b[j])) {
      size_t ei = i, ej = j;
      while (ei < a.size() && digit(a[ei])) ++ei;
      while (ej < b.size() && digit(b[ej])) ++ej;
      const std::string_view na = Number(std::string_view(a).substr(i, ei - i));
      const std::string_view nb = Number(std::string_view(b).substr(j, ej - j));
      if (na.size() != nb.size()) return na.size() < nb.size();
      if (na != nb) return na < nb;
      i = ei;
      j = ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

Rosbag2Files FindRosbag2Files(const std::string& folder) {
  const fs::path dir(folder);
  const fs::path meta_path = dir / "metadata.yaml";
  Rosbag2Files files;
  std::error_code ec;
  std::set<fs::path> listed;
  if (fs::is_regular_file(meta_path, ec)) {
    files.has_metadata = true;
    files.metadata = io::ReadRosbag2Metadata(meta_path.string());
    const io::Rosbag2Metadata& meta = files.metadata;
    if (!meta.compression_format.empty() || !meta.compression_mode.empty()) {
      throw io::InputError(
          io::Where(meta_path.string(), 0,
                    "compressed rosbag2 (compression_format '" + meta.compression_format +
                        "', mode '" + meta.compression_mode +
                        "') is not read; expected an uncompressed bag (ros2 bag convert)"));
    }
    for (const std::string& rel : meta.relative_file_paths) {
      fs::path file = dir / rel;
      // Early rosbag2 wrote paths relative to the bag's parent folder ("bag/bag_0.db3").
      const fs::path alt = dir.parent_path() / rel;
      if (!fs::exists(file, ec) && fs::exists(alt, ec)) file = alt;
      if (!fs::is_regular_file(file, ec)) {
        throw io::InputError(io::Where(
            meta_path.string(), 0, "lists storage file " + rel + ", which is not in the folder"));
      }
      files.paths.push_back(file.string());
      listed.insert(fs::weakly_canonical(file, ec));
    }
    files.listed = static_cast<int>(files.paths.size());
  }
  std::vector<std::string> more;
  for (const fs::directory_entry& entry : fs::directory_iterator(dir, ec)) {
    if (!IsStorageFile(entry) || listed.count(fs::weakly_canonical(entry.path(), ec)) > 0) {
      continue;
    }
    more.push_back(entry.path().filename().string());
  }
  std::sort(more.begin(), more.end(), SplitOrderLess);
  for (const std::string& name : more) files.paths.push_back((dir / name).string());
  return files;
}

}  // namespace wallcal::recording
