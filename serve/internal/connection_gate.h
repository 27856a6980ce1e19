// SPDX-License-Identifier: Apache-2.0
#pragma once
// Every socket of the page's server, read and written on one thread by poll(): a connection is
// adopted as accepted, its request head read into a buffer of bounded size before a deadline,
// answered by a function given the head (no socket I/O there), and its answer written out before
// a second deadline. A client that sends slowly, sends too much, or never reads costs a slot and
// a bounded buffer until its deadline, never a thread; beyond `max_connections` slots a
// connection is answered 503 and closed at once. Private to serve/.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "serve/serve_limits.h"

namespace wallcal::serve::internal {

class ConnectionGate {
 public:
  // `answer(head, fd)`: the whole response (status line, headers, body) to the request `head`
  // (its request line and headers, ending with an empty line); fd only for the peer's address.
  // Called on the gate's thread; must not block.
  using Answer = std::function<std::string(const std::string& head, int fd)>;

  ConnectionGate(ServeLimits limits, Answer answer);
  ~ConnectionGate();  // Stop()
  ConnectionGate(const ConnectionGate&) = delete;
  ConnectionGate& operator=(const ConnectionGate&) = delete;

  // Starts the thread. False when the wake-up descriptor cannot be made.
  bool Start();
  // Takes the connected socket `fd` over (from any thread; it is closed by the gate in every
  // case). Never blocks.
  void Adopt(int fd);
  // Closes every connection and joins the thread. Idempotent.
  void Stop();

  ServeCounts counts() const;
  int open_connections() const { return open_.load(); }

 private:
  struct Connection;
  void Run();
  void Wake();

  const ServeLimits limits_;
  const Answer answer_;
  int wake_fd_ = -1;
  std::thread thread_;
  std::atomic<bool> stopping_{false};
  std::atomic<int> open_{0};  // adopted and not yet closed (the slots in use)

  mutable std::mutex mutex_;  // guards incoming_ and counts_
  std::vector<int> incoming_;
  ServeCounts counts_;
};

}  // namespace wallcal::serve::internal
