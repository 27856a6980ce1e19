// SPDX-License-Identifier: Apache-2.0
#pragma once
// Output files that never destroy anything but an earlier output (docs/field-guide.md,
// "Outputs").
//
// Promises of WriteFileAtomically and of the checks below:
//   - only a regular file, or a new path, is ever replaced: a FIFO, a device node, a socket or a
//     folder at the path is refused (as root, `--output /dev/null` must not replace the device);
//   - an existing symbolic link is followed: the file it points to is replaced, the link stays;
//     a link pointing nowhere is refused;
//   - the mode of a replaced file is kept (a new file is 0666 less the umask);
//   - the temporary file (beside the target) is removed on failure, and on SIGINT / SIGTERM
//     while it exists (the signal then ends the program as it would have).
// CheckOutputPath adds, before any work is done: the path is not empty, its folder exists, and
// it is not one of the run's inputs (compared by device and inode, links resolved).

#include <streambuf>
#include <string>
#include <vector>

namespace wallcal::io {

// Writes `content` to PATH.tmp-XXXXXX in the same folder, fsyncs it and renames it over `path`,
// so a reader sees the old file or the whole new one. On failure the temporary file is removed
// and InputError naming `path` is thrown; `path` is then untouched.
void WriteFileAtomically(const std::string& path, const std::string& content);

// True for "-": the output goes to standard output.
inline bool IsStdoutPath(const std::string& path) { return path == "-"; }

// Throws InputError "<option> PATH: <what is wrong>; expected ..." when PATH cannot be written
// as promised above, or is the same file as one of `inputs` (missing inputs are ignored).
// "-" passes. `option` names the command-line option ("--output").
void CheckOutputPath(const std::string& option, const std::string& path,
                     const std::vector<std::string>& inputs);

// Throws InputError unless DIR is an existing folder or a new path whose parent folder exists
// (what `--report DIR` needs). Not empty.
void CheckOutputFolder(const std::string& option, const std::string& dir);

// A stream buffer that forwards to `target` with control characters (bytes below 0x20 except
// '\n' and '\t', and 0x7F) written as \xNN: text from files (a session name with an escape
// sequence) cannot move the cursor, recolour the terminal or fake a line. Not owning `target`.
class ControlEscapingStreamBuf : public std::streambuf {
 public:
  explicit ControlEscapingStreamBuf(std::streambuf* target) : target_(target) {}

 protected:
  int_type overflow(int_type c) override;
  std::streamsize xsputn(const char* text, std::streamsize n) override;  // runs forwarded whole
  int sync() override { return target_->pubsync(); }

 private:
  std::streambuf* target_;
};

}  // namespace wallcal::io
