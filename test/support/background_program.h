// SPDX-License-Identifier: Apache-2.0
#pragma once
// A program left running while a test works beside it (wallcal guide --follow --serve while the
// test grows the logs and looks at the page): its stdout and stderr go to files the test can
// read as they grow; it runs in a process group of its own, killed when the object goes.

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

namespace wallcal::testing_support {

class BackgroundProgram {
 public:
  // Starts argv (argv[0] a path) with stdout to out_path and stderr to err_path.
  BackgroundProgram(const std::vector<std::string>& argv, std::filesystem::path out_path,
                    std::filesystem::path err_path)
      : out_path_(std::move(out_path)), err_path_(std::move(err_path)) {
    pid_ = ::fork();
    if (pid_ == 0) {
      ::setpgid(0, 0);
      const int null_in = ::open("/dev/null", O_RDONLY);
      const int out = ::open(out_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = ::open(err_path_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (null_in < 0 || out < 0 || err < 0) ::_exit(127);
      ::dup2(null_in, STDIN_FILENO);
      ::dup2(out, STDOUT_FILENO);
      ::dup2(err, STDERR_FILENO);
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      ::execv(args[0], args.data());
      ::_exit(127);
    }
    if (pid_ > 0) ::setpgid(pid_, pid_);
  }
  ~BackgroundProgram() { Kill(); }
  BackgroundProgram(const BackgroundProgram&) = delete;
  BackgroundProgram& operator=(const BackgroundProgram&) = delete;

  bool started() const { return pid_ > 0; }

  std::string Out() const { return Read(out_path_); }
  std::string Err() const { return Read(err_path_); }

  // The first line of stderr that contains `text`, waiting up to timeout_s; empty when none
  // (or the program ended first).
  std::string WaitForErrLine(const std::string& text, double timeout_s) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      std::istringstream in(Err());
      for (std::string line; std::getline(in, line);) {
        if (line.find(text) != std::string::npos) return line;
      }
      if (Exited(nullptr)) return "";
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return "";
  }

  // Waits up to timeout_s for the program to exit: true with its exit status in *status.
  bool Wait(double timeout_s, int* status) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
    while (std::chrono::steady_clock::now() < deadline) {
      if (Exited(status)) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    return false;
  }

  void Kill() {
    if (pid_ <= 0 || reaped_) return;
    ::kill(-pid_, SIGKILL);
    int status = 0;
    ::waitpid(pid_, &status, 0);
    reaped_ = true;
  }

 private:
  bool Exited(int* status) {
    if (reaped_) {
      if (status != nullptr) *status = exit_status_;
      return true;
    }
    int raw = 0;
    if (pid_ <= 0 || ::waitpid(pid_, &raw, WNOHANG) != pid_) return false;
    reaped_ = true;
    exit_status_ = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    if (status != nullptr) *status = exit_status_;
    return true;
  }
  static std::string Read(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::filesystem::path out_path_, err_path_;
  pid_t pid_ = -1;
  bool reaped_ = false;
  int exit_status_ = -1;
};

}  // namespace wallcal::testing_support
