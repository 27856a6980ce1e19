// SPDX-License-Identifier: Apache-2.0
#include "io/input_file.h"

#include <sys/stat.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>

#include "io/types.h"
#include "io/internal/file_kind.h"

namespace wallcal::io {
namespace {

int64_t FromEnvironment(const char* name, int64_t fallback) {
  const char* text = std::getenv(name);
  if (text == nullptr || *text == '\0') return fallback;
  char* end = nullptr;
  errno = 0;
  const long long value = std::strtoll(text, &end, 10);
  if (errno != 0 || end == text || *end != '\0' || value <= 0) return fallback;
  return static_cast<int64_t>(value);
}

size_t Utf8LengthImpl(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<unsigned char>(text[k]); };
  const unsigned char c = byte(i);
  size_t n = 0;
  unsigned min = 0;
  unsigned code = 0;
  if (c < 0x80) return 1;
  if (c >= 0xC2 && c <= 0xDF) {
    n = 2, min = 0x80, code = c & 0x1F;
  } else if (c >= 0xE0 && c <= 0xEF) {
    n = 3, min = 0x800, code = c & 0x0F;
  } else if (c >= 0xF0 && c <= 0xF4) {
    n = 4, min = 0x10000, code = c & 0x07;
  } else {
    return 0;
  }
  if (i + n > text.size()) return 0;
  for (size_t k = 1; k < n; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < min || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return n;
}

size_t Utf8Length(std::string_view text, size_t i) { return Utf8LengthImpl(text, i); }

bool IsControl(unsigned char c) { return c < 0x20 || c == 0x7F; }

}  // namespace

size_t Utf8SequenceLength(std::string_view text, size_t i) { return Utf8Length(text, i); }

InputLimits CurrentInputLimits() {
  InputLimits limits;
  limits.max_file_bytes = FromEnvironment("WALLCAL_MAX_FILE_BYTES", limits.max_file_bytes);
  limits.max_line_bytes = FromEnvironment("WALLCAL_MAX_LINE_BYTES", limits.max_line_bytes);
  limits.max_yaml_bytes = FromEnvironment("WALLCAL_MAX_YAML_BYTES", limits.max_yaml_bytes);
  return limits;
}

void CheckInputFile(const std::string& path, const std::string& what, int64_t max_bytes) {
  if (path.empty()) throw InputError(what + ": empty path; expected a file name");
  struct stat info {};
  if (::stat(path.c_str(), &info) != 0) {
    throw InputError(Where(path, 0, "cannot open " + what + ": " + std::strerror(errno)));
  }
  if (!S_ISREG(info.st_mode)) {
    throw InputError(Where(path, 0,
                           what + " is " + KindOf(info.st_mode) + "; expected a regular file"));
  }
  const int64_t budget = max_bytes > 0 ? max_bytes : CurrentInputLimits().max_file_bytes;
  if (static_cast<int64_t>(info.st_size) > budget) {
    throw InputError(Where(path, 0,
                           what + " has " + std::to_string(info.st_size) +
                               " bytes; expected at most " + std::to_string(budget) +
                               " (WALLCAL_MAX_FILE_BYTES / WALLCAL_MAX_YAML_BYTES raise it)"));
  }
}

std::string ReadInputFile(const std::string& path, const std::string& what, int64_t max_bytes) {
  CheckInputFile(path, what, max_bytes);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(Where(path, 0, "cannot open " + what + ": " + std::strerror(errno)));
  std::string text;
  char buffer[1 << 16];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) {
    text.append(buffer, static_cast<size_t>(in.gcount()));
    // The file may have grown since it was checked: the budget holds for what is read.
    if (static_cast<int64_t>(text.size()) > max_bytes && max_bytes > 0) {
      throw InputError(Where(path, 0, what + " is larger than " + std::to_string(max_bytes) +
                                          " bytes; expected at most that"));
    }
  }
  if (in.bad()) throw InputError(Where(path, 0, "cannot read " + what));
  return text;
}

LineRead ReadLineBounded(std::istream& in, std::string* line, int64_t max_bytes) {
  line->clear();
  std::streambuf* buffer = in.rdbuf();
  if (buffer == nullptr) return LineRead::kEnd;
  while (true) {
    const int c = buffer->sbumpc();
    if (c == std::char_traits<char>::eof()) {
      in.setstate(std::ios::eofbit);
      return line->empty() ? LineRead::kEnd : LineRead::kLastLineWithoutNewline;
    }
    if (c == '\n') return LineRead::kLine;
    if (c == '\r') {
      // CRLF is one line end; a CR alone ends the line too (old Mac and instrument downloads).
      if (buffer->sgetc() == '\n') buffer->sbumpc();
      return LineRead::kLine;
    }
    if (static_cast<int64_t>(line->size()) >= max_bytes) return LineRead::kTooLong;
    line->push_back(static_cast<char>(c));
  }
}

std::string NormaliseLineEnds(std::string text) {
  if (text.find('\r') == std::string::npos) return text;
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] != '\r') {
      out += text[i];
    } else if (i + 1 >= text.size() || text[i + 1] != '\n') {
      out += '\n';
    }
  }
  return out;
}

bool StripUtf8Bom(std::string* text) {
  if (text->compare(0, 3, "\xEF\xBB\xBF") != 0) return false;
  text->erase(0, 3);
  return true;
}

bool StripUtf8Bom(std::string_view* text) {
  if (text->substr(0, 3) != "\xEF\xBB\xBF") return false;
  text->remove_prefix(3);
  return true;
}

std::string EscapeControl(std::string_view text, bool keep_newlines) {
  static const char kHex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size();) {
    const unsigned char c = static_cast<unsigned char>(text[i]);
    const size_t n = Utf8Length(text, i);
    if (n == 0 || (n == 1 && IsControl(c) && !(keep_newlines && c == '\n'))) {
      out += "\\x";
      out += kHex[c >> 4];
      out += kHex[c & 0xF];
      ++i;
      continue;
    }
    out.append(text.data() + i, n);
    i += n;
  }
  return out;
}

std::string DescribeLine(std::string_view line) {
  size_t words = 0;
  bool in_word = false;
  for (const char c : line) {
    const bool space = c == ' ' || c == '\t' || c == '\r';
    if (!space && !in_word) ++words;
    in_word = !space;
  }
  std::string text = "a line of " + std::to_string(line.size()) + " bytes, " +
                     std::to_string(words) + (words == 1 ? " word, " : " words, ");
  text += IsPrintableUtf8(line) ? "text" : "binary bytes";
  return text;
}

bool IsPrintableUtf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t n = Utf8Length(text, i);
    if (n == 0) return false;
    if (n == 1 && IsControl(static_cast<unsigned char>(text[i])) && text[i] != '\t') return false;
    i += n;
  }
  return true;
}

}  // namespace wallcal::io
