// SPDX-License-Identifier: Apache-2.0
#pragma once
// Reading input files with bounded resources (docs/session-format.md, "Limits").
//
// Every input (session.yaml, options, presets, logs, survey files, recordings) must be a regular
// file, or a symbolic link to one: a FIFO, a device (/dev/zero, /dev/urandom), a socket or a
// folder is refused before anything is read, so a log is never read from something that can
// block forever or never end. Sizes are bounded by a byte budget per file and per line (after
// decompression); the budgets are generous and can be changed with environment variables:
//   WALLCAL_MAX_FILE_BYTES  largest input file, and largest uncompressed gzip content
//                           (default 64 GiB: far above a day of logging)
//   WALLCAL_MAX_LINE_BYTES  longest line of a text log (default 256 MiB: a CARMEN scan of
//                           100000 beams is under 2 MiB)
//   WALLCAL_MAX_YAML_BYTES  largest YAML file (session.yaml, options, presets; default 16 MiB)
// A budget variable that is not a positive integer is ignored (the default holds).

#include <cstdint>
#include <istream>
#include <string>
#include <string_view>

namespace wallcal::io {

inline constexpr int64_t kDefaultMaxFileBytes = int64_t{64} << 30;
inline constexpr int64_t kDefaultMaxLineBytes = int64_t{256} << 20;
inline constexpr int64_t kDefaultMaxYamlBytes = int64_t{16} << 20;
// Deepest nesting of maps and lists accepted in a YAML file: our files use at most 4 levels.
inline constexpr int kMaxYamlDepth = 32;

struct InputLimits {
  int64_t max_file_bytes = kDefaultMaxFileBytes;
  int64_t max_line_bytes = kDefaultMaxLineBytes;
  int64_t max_yaml_bytes = kDefaultMaxYamlBytes;
};

// The budgets in force: the defaults, overridden by the environment variables above.
InputLimits CurrentInputLimits();

// Throws InputError "PATH: <what> is a FIFO (named pipe); expected a regular file" (or "a
// folder", "a character device", "missing", "larger than N bytes", ...) unless PATH names a
// regular file (links followed) of at most `max_bytes` bytes (0: CurrentInputLimits().
// max_file_bytes). `what` is the file's role in words ("the scan log").
void CheckInputFile(const std::string& path, const std::string& what, int64_t max_bytes = 0);

// Reads PATH whole after CheckInputFile(path, what, max_bytes). Throws InputError when it
// cannot be read.
std::string ReadInputFile(const std::string& path, const std::string& what, int64_t max_bytes);

// How ReadLineBounded ended.
enum class LineRead { kLine, kLastLineWithoutNewline, kEnd, kTooLong };

// Reads one line (without its end: LF, CRLF or a CR alone) into *line, keeping at most
// max_bytes bytes: kTooLong when
// the line is longer (the stream is then left inside the line; callers stop reading). NUL
// bytes are kept (the caller decides). Never allocates more than max_bytes for the line.
LineRead ReadLineBounded(std::istream& in, std::string* line, int64_t max_bytes);

// `text` with every line end as LF: CRLF becomes LF and a CR alone (old Mac, some instrument
// downloads) becomes LF, so each line keeps its number.
std::string NormaliseLineEnds(std::string text);

// Removes a UTF-8 byte-order mark (EF BB BF) from the start of `text`; true when there was one.
bool StripUtf8Bom(std::string* text);
bool StripUtf8Bom(std::string_view* text);

// Text safe to print or to put in a one-line message: control characters (bytes < 0x20 except
// '\n' when keep_newlines, and 0x7F), and bytes that are not valid UTF-8, become \xNN; valid
// UTF-8 is kept as it is.
std::string EscapeControl(std::string_view text, bool keep_newlines = false);

// Length in bytes of the valid UTF-8 sequence starting at text[i] (1 for ASCII), 0 when the
// bytes there are not valid UTF-8 (overlong forms and surrogates included).
size_t Utf8SequenceLength(std::string_view text, size_t i);

// A line described in words, never quoted, for messages about a file that may not be meant for
// us (a password file named by mistake): "a line of 31 bytes, 1 word, text", "... binary bytes".
std::string DescribeLine(std::string_view line);

// True when `text` is valid UTF-8 without control characters (tab allowed).
bool IsPrintableUtf8(std::string_view text);

}  // namespace wallcal::io
