// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a path is when it is not a regular file, for the messages of io/input_file.cc and
// io/output_file.cc. Internal to io/.

#include <sys/stat.h>

namespace wallcal::io {

// "a folder", "a FIFO (named pipe)", ... for a stat mode that is not a regular file.
inline const char* KindOf(mode_t mode) {
  if (S_ISDIR(mode)) return "a folder";
  if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
  if (S_ISCHR(mode)) return "a character device";
  if (S_ISBLK(mode)) return "a block device";
  if (S_ISSOCK(mode)) return "a socket";
  return "not a regular file";
}

}  // namespace wallcal::io
