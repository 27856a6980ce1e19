// SPDX-License-Identifier: Apache-2.0
#include "io/output_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <optional>

#include "io/types.h"
#include "io/output_file.h"
#include "io/internal/file_kind.h"

namespace wallcal::io {
namespace {

namespace fs = std::filesystem;

// The temporary file being written, for the signal handler: a fixed buffer (no allocation in
// the handler) guarded by an atomic flag. One write at a time per process is all wallcal does.
char g_temp_path[4096];
std::atomic<bool> g_temp_live{false};

extern "C" void RemoveTempAndReraise(int signal_number) {
  if (g_temp_live.load()) ::unlink(g_temp_path);
  // SA_RESETHAND restored the default action: end the program as the signal meant to.
  ::raise(signal_number);
}

void InstallSignalCleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
      struct sigaction current {};
      if (::sigaction(signal_number, nullptr, &current) != 0) continue;
      if (current.sa_handler != SIG_DFL) continue;  // ignored or handled by someone else
      struct sigaction action {};
      action.sa_handler = RemoveTempAndReraise;
      sigemptyset(&action.sa_mask);
      action.sa_flags = SA_RESETHAND;
      ::sigaction(signal_number, &action, nullptr);
    }
  });
}

class TempRegistration {
 public:
  explicit TempRegistration(const std::string& temp) {
    if (temp.size() < sizeof(g_temp_path)) {
      std::memcpy(g_temp_path, temp.c_str(), temp.size() + 1);
      g_temp_live.store(true);
    }
  }
  ~TempRegistration() { g_temp_live.store(false); }
  TempRegistration(const TempRegistration&) = delete;
  TempRegistration& operator=(const TempRegistration&) = delete;
};

// The file a write to `path` replaces: `path` itself, or what its symbolic link(s) point to.
// Throws when a link leads nowhere or something other than a regular file is there.
std::string ResolveTarget(const std::string& path, struct stat* existing, bool* exists) {
  struct stat link_info {};
  *exists = false;
  if (::lstat(path.c_str(), &link_info) != 0) {
    if (errno == ENOENT) return path;
    throw InputError(Where(path, 0, std::string("cannot look at the output: ") + std::strerror(errno)));
  }
  std::string target = path;
  if (S_ISLNK(link_info.st_mode)) {
    std::error_code ec;
    const fs::path resolved = fs::canonical(path, ec);
    if (ec) {
      throw InputError(Where(path, 0,
                             "is a symbolic link to a missing file; expected a regular file or a "
                             "new path (remove the link, or point it at a file)"));
    }
    target = resolved.string();
  }
  if (::stat(target.c_str(), existing) != 0) {
    throw InputError(Where(path, 0, std::string("cannot look at the output: ") + std::strerror(errno)));
  }
  if (!S_ISREG(existing->st_mode)) {
    throw InputError(Where(path, 0,
                           std::string("the output is ") + KindOf(existing->st_mode) +
                               "; only a regular file or a new path is ever replaced"));
  }
  *exists = true;
  return target;
}

}  // namespace

void CheckOutputPath(const std::string& option, const std::string& path,
                     const std::vector<std::string>& inputs) {
  if (path.empty()) {
    throw InputError(option + ": empty file name; expected a path (or - for standard output)");
  }
  if (IsStdoutPath(path)) return;
  struct stat existing {};
  bool exists = false;
  const std::string target = ResolveTarget(path, &existing, &exists);
  if (exists) {
    for (const std::string& input : inputs) {
      struct stat info {};
      if (input.empty() || ::stat(input.c_str(), &info) != 0) continue;
      if (info.st_dev == existing.st_dev && info.st_ino == existing.st_ino) {
        throw InputError(Where(path, 0,
                               option + " names an input of this run (" + input +
                                   "); expected a new file, e.g. offsets.yaml"));
      }
    }
  }
  std::string dir = fs::path(target).parent_path().string();
  if (dir.empty()) dir = ".";
  struct stat dir_info {};
  if (::stat(dir.c_str(), &dir_info) != 0 || !S_ISDIR(dir_info.st_mode)) {
    throw InputError(Where(path, 0, option + ": the folder " + dir +
                                        " does not exist; expected an existing folder"));
  }
  if (::access(dir.c_str(), W_OK | X_OK) != 0) {
    throw InputError(Where(path, 0, option + ": cannot write in the folder " + dir + ": " +
                                        std::strerror(errno)));
  }
}

void CheckOutputFolder(const std::string& option, const std::string& dir) {
  if (dir.empty()) throw InputError(option + ": empty folder name; expected a folder");
  struct stat info {};
  if (::stat(dir.c_str(), &info) == 0) {
    if (!S_ISDIR(info.st_mode)) {
      throw InputError(Where(dir, 0, option + ": this is " + KindOf(info.st_mode) +
                                         ", not a folder; expected a folder (new or existing)"));
    }
    return;
  }
  std::string parent = fs::path(dir).lexically_normal().parent_path().string();
  if (parent.empty()) parent = ".";
  struct stat parent_info {};
  if (::stat(parent.c_str(), &parent_info) != 0 || !S_ISDIR(parent_info.st_mode)) {
    throw InputError(Where(dir, 0, option + ": the folder " + parent +
                                       " does not exist; expected an existing parent folder"));
  }
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  if (path.empty()) throw InputError("cannot write a file with an empty name");
  struct stat existing {};
  bool exists = false;
  const std::string target = ResolveTarget(path, &existing, &exists);
  auto fail = [&path](const std::string& what, int error) {
    throw InputError(Where(path, 0, what + ": " + std::strerror(error)));
  };
  InstallSignalCleanup();
  std::string temp = target + ".tmp-XXXXXX";
  // Block the cleanup signals while the name is registered, so the handler never sees a half
  // registration; they are delivered (and the file removed) as soon as they are unblocked.
  sigset_t cleanup_signals, previous;
  sigemptyset(&cleanup_signals);
  sigaddset(&cleanup_signals, SIGINT);
  sigaddset(&cleanup_signals, SIGTERM);
  sigaddset(&cleanup_signals, SIGHUP);
  ::sigprocmask(SIG_BLOCK, &cleanup_signals, &previous);
  const int fd = ::mkstemp(temp.data());
  const int create_error = errno;
  std::optional<TempRegistration> registration;
  if (fd >= 0) registration.emplace(temp);
  ::sigprocmask(SIG_SETMASK, &previous, nullptr);
  if (fd < 0) fail("cannot create a temporary file next to it", create_error);
  // From here on, every failure removes the temporary file: `path` stays as it was.
  auto abandon = [&](const std::string& what) {
    const int error = errno;
    ::close(fd);
    ::unlink(temp.c_str());
    fail(what, error);
  };
  size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR) continue;
      abandon("cannot write");
    }
    written += static_cast<size_t>(n);
  }
  // mkstemp makes the file 0600: keep the mode of the file replaced, else what a new file
  // would get (0666 less the umask).
  mode_t mode = existing.st_mode & 07777;
  if (!exists) {
    const mode_t mask = ::umask(0);
    ::umask(mask);
    mode = 0666 & ~mask;
  }
  if (::fchmod(fd, mode) != 0) abandon("cannot set permissions");
  if (::fsync(fd) != 0) abandon("cannot flush to disk");
  if (::close(fd) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    fail("cannot close", error);
  }
  if (std::rename(temp.c_str(), target.c_str()) != 0) {
    const int error = errno;
    ::unlink(temp.c_str());
    fail("cannot rename the temporary file over it", error);
  }
  registration.reset();
  // Make the rename itself durable; failing here does not undo a complete file.
  std::string dir = fs::path(target).parent_path().string();
  if (dir.empty()) dir = ".";
  const int dir_fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
  if (dir_fd >= 0) {
    ::fsync(dir_fd);
    ::close(dir_fd);
  }
}

ControlEscapingStreamBuf::int_type ControlEscapingStreamBuf::overflow(int_type c) {
  if (traits_type::eq_int_type(c, traits_type::eof())) return traits_type::not_eof(c);
  const unsigned char u = static_cast<unsigned char>(traits_type::to_char_type(c));
  if ((u < 0x20 && u != '\n' && u != '\t') || u == 0x7F) {
    static const char kHex[] = "0123456789ABCDEF";
    const char escaped[4] = {'\\', 'x', kHex[u >> 4], kHex[u & 0xF]};
    return target_->sputn(escaped, 4) == 4 ? c : traits_type::eof();
  }
  return traits_type::eq_int_type(target_->sputc(static_cast<char>(u)), traits_type::eof())
             ? traits_type::eof()
             : c;
}

std::streamsize ControlEscapingStreamBuf::xsputn(const char* text, std::streamsize n) {
  std::streamsize done = 0;
  while (done < n) {
    std::streamsize run = done;
    while (run < n) {
      const unsigned char u = static_cast<unsigned char>(text[run]);
      if ((u < 0x20 && u != '\n' && u != '\t') || u == 0x7F) break;
      ++run;
    }
    if (run > done && target_->sputn(text + done, run - done) != run - done) return done;
    done = run;
    if (done < n) {
      if (traits_type::eq_int_type(overflow(traits_type::to_int_type(text[done])),
                                   traits_type::eof())) {
        return done;
      }
      ++done;
    }
  }
  return done;
}

}  // namespace wallcal::io
