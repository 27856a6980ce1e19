// SPDX-License-Identifier: Apache-2.0
#pragma once
// The lines of a survey file, one at a time: '\n'-separated, without the '\n', a UTF-8 byte
// order mark at the start of the text dropped. The one line splitter of the survey readers.
// Internal to io/.

#include <cstddef>
#include <string_view>

#include "io/input_file.h"

namespace wallcal::io {

class LineSplitter {
 public:
  explicit LineSplitter(std::string_view text) : text_(text) { StripUtf8Bom(&text_); }

  // The next line into *line; false after the last one.
  bool Next(std::string_view* line) {
    if (start_ >= text_.size()) return false;
    size_t end = text_.find('\n', start_);
    if (end == std::string_view::npos) end = text_.size();
    *line = text_.substr(start_, end - start_);
    start_ = end + 1;
    ++line_number_;
    return true;
  }
  // The 1-based number of the line Next gave last (0 before the first).
  int line_number() const { return line_number_; }

 private:
  std::string_view text_;
  size_t start_ = 0;
  int line_number_ = 0;
};

}  // namespace wallcal::io
