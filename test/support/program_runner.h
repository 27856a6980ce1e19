// SPDX-License-Identifier: Apache-2.0
#pragma once
// Runs a program as a user would and captures what it did: its exit status (or the signal that
// ended it), stdout and stderr, under a time limit. Every test that runs `wallcal` goes through
// here. The program runs in a process group of its own with stdin from /dev/null; at the time
// limit the whole group is killed (SIGKILL) and the run says it timed out (a hang).
//
// WALLCAL_PROGRAMS_DIR, when set, runs the same tests against the wallcal of another build
// (e.g. an older main, to see a test fail there).

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

namespace wallcal::testing_support {

struct ProgramRun {
  int exit_code = -1;      // the exit status when the program exited, else -1
  int signal = 0;          // the signal that ended it, else 0
  bool timed_out = false;  // killed at the time limit
  std::string out, err;    // everything written to stdout and stderr
  bool exited() const { return exit_code >= 0; }
};

struct RunOptions {
  std::string cwd;               // the working folder (empty: the test's own)
  std::vector<std::string> env;  // "NAME=value" set for the program
  bool merge_stderr = false;     // stderr into `out` as well (as 2>&1), interleaved
  int timeout_s = 300;
};

// Runs argv[0] (found on PATH when it has no '/') with the arguments argv[1..].
inline ProgramRun RunProgram(const std::vector<std::string>& argv, const RunOptions& options = {}) {
  ProgramRun run;
  int out_pipe[2], err_pipe[2];
  if (argv.empty() || ::pipe2(out_pipe, O_CLOEXEC) != 0) return run;
  if (::pipe2(err_pipe, O_CLOEXEC) != 0) {
    ::close(out_pipe[0]);
    ::close(out_pipe[1]);
    return run;
  }
  const pid_t child = ::fork();
  if (child == 0) {
    ::setpgid(0, 0);
    const int null_in = ::open("/dev/null", O_RDONLY);
    if (null_in >= 0) ::dup2(null_in, STDIN_FILENO);
    ::dup2(out_pipe[1], STDOUT_FILENO);
    ::dup2(options.merge_stderr ? out_pipe[1] : err_pipe[1], STDERR_FILENO);
    if (!options.cwd.empty() && ::chdir(options.cwd.c_str()) != 0) ::_exit(127);
    for (const std::string& setting : options.env) {
      const size_t eq = setting.find('=');
      if (eq != std::string::npos) {
        ::setenv(setting.substr(0, eq).c_str(), setting.substr(eq + 1).c_str(), 1);
      }
    }
    std::vector<char*> args;
    for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    ::execvp(args[0], args.data());
    ::_exit(127);
  }
  ::close(out_pipe[1]);
  ::close(err_pipe[1]);
  if (child < 0) {
    ::close(out_pipe[0]);
    ::close(err_pipe[0]);
    return run;
  }
  ::setpgid(child, child);  // also here: no race with the child's own call
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(options.timeout_s);
  pollfd fds[2] = {{out_pipe[0], POLLIN, 0}, {err_pipe[0], POLLIN, 0}};
  std::string* sinks[2] = {&run.out, &run.err};
  int open_pipes = 2;
  char buffer[65536];
  while (open_pipes > 0) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now());
    if (left.count() <= 0) {
      run.timed_out = true;
      ::kill(-child, SIGKILL);
      break;
    }
    const int ready = ::poll(fds, 2, static_cast<int>(left.count()));
    if (ready < 0 && errno != EINTR) break;
    for (int i = 0; i < 2 && ready > 0; ++i) {
      if (fds[i].fd < 0 || fds[i].revents == 0) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof(buffer));
      if (n > 0) {
        sinks[i]->append(buffer, static_cast<size_t>(n));
      } else if (n == 0 || errno != EINTR) {
        ::close(fds[i].fd);
        fds[i].fd = -1;
        --open_pipes;
      }
    }
  }
  for (pollfd& fd : fds) {
    if (fd.fd >= 0) ::close(fd.fd);
  }
  int status = 0;
  while (::waitpid(child, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFEXITED(status)) run.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) run.signal = WTERMSIG(status);
  return run;
}

// Quotes a word for sh: 'it'\''s'.
inline std::string ShellQuote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// `sh -c COMMAND`, for a test that needs the shell (several programs at once, a pipe).
inline ProgramRun RunShell(const std::string& command, const RunOptions& options = {}) {
  return RunProgram({"/bin/sh", "-c", command}, options);
}

// The wallcal program under test.
inline std::string WallcalPath() {
  const char* dir = std::getenv("WALLCAL_PROGRAMS_DIR");
  return std::string(dir != nullptr && *dir != '\0' ? dir : WALLCAL_BINARY_DIR) + "/wallcal";
}

// `wallcal ARGS...`, e.g. RunWallcal({"calibrate", session, "--output", path}).
inline ProgramRun RunWallcal(std::vector<std::string> args, const RunOptions& options = {}) {
  args.insert(args.begin(), WallcalPath());
  return RunProgram(args, options);
}

// `wallcal COMMAND` followed by ARGS as a shell would split them (ARGS already shell-quoted
// where needed): for tests that write their arguments as one line.
inline ProgramRun RunWallcalLine(const std::string& command, const std::string& args,
                                 const RunOptions& options = {}) {
  return RunShell("exec " + ShellQuote(WallcalPath()) + " " + command + " " + args, options);
}

// `wallcal COMMAND`, quoted for the shell: the start of a command line for RunCommand.
inline std::string WallcalCommand(const std::string& command) {
  return ShellQuote(WallcalPath()) + " " + command;
}

// What a command line did, stderr merged into stdout.
struct CommandRun {
  int status = -1;  // the exit status; -1 when it did not exit
  std::string out;
};

// Runs a shell command line with stderr merged into out.
inline CommandRun RunCommand(const std::string& command) {
  RunOptions options;
  options.merge_stderr = true;
  const ProgramRun run = RunShell(command, options);
  return {run.exit_code, run.out};
}

}  // namespace wallcal::testing_support
