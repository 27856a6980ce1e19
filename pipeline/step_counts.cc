// SPDX-License-Identifier: Apache-2.0
// The counting and the skip texts the steps share (pipeline/internal/steps.h).

#include <algorithm>
#include <filesystem>

#include "pipeline/internal/steps.h"

namespace wallcal::pipeline {

std::string FileName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

std::string DescribeSkips(const std::string& file, const io::SkipCounts& skips) {
  if (skips.Problems() == 0) return std::string();
  return FileName(file) + ": " + std::to_string(skips.Problems()) + " lines skipped (" +
         skips.ListReasons(true) + ")";
}

int64_t CountDistinct(std::vector<int>* values) {
  std::sort(values->begin(), values->end());
  return static_cast<int64_t>(std::unique(values->begin(), values->end()) - values->begin());
}

}  // namespace wallcal::pipeline
