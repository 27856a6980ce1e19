// SPDX-License-Identifier: Apache-2.0
#include "serve/internal/connection_gate.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <exception>
#include <memory>
#include <utility>

namespace wallcal::serve::internal {
namespace {

using Clock = std::chrono::steady_clock;

Clock::time_point After(double seconds) {
  return Clock::now() + std::chrono::duration_cast<Clock::duration>(
                            std::chrono::duration<double>(seconds));
}

const char kBusy[] =
    "HTTP/1.1 503 Service Unavailable\r\nContent-Length: 0\r\nConnection: close\r\n"
    "Retry-After: 1\r\n\r\n";
const char kTooLong[] =
    "HTTP/1.1 431 Request Header Fields Too Large\r\nContent-Length: 0\r\n"
    "Connection: close\r\n\r\n";
const char kFailed[] =
    "HTTP/1.1 500 Internal Server Error\r\nContent-Length: 0\r\nConnection: close\r\n\r\n";

// Where the head ends (just past its empty line), or npos. Bare LF line ends are taken too.
size_t HeadEnd(const std::string& in, size_t from) {
  from = from > 3 ? from - 3 : 0;
  const size_t crlf = in.find("\r\n\r\n", from);
  const size_t lf = in.find("\n\n", from);
  if (crlf == std::string::npos && lf == std::string::npos) return std::string::npos;
  if (crlf != std::string::npos && (lf == std::string::npos || crlf + 2 <= lf)) return crlf + 4;
  return lf + 2;
}

}  // namespace

struct ConnectionGate::Connection {
  enum class Phase { kReading, kWriting, kClosing };
  int fd = -1;
  Phase phase = Phase::kReading;
  Clock::time_point deadline;
  std::string in;
  std::string out;
  size_t sent = 0;
};

ConnectionGate::ConnectionGate(ServeLimits limits, Answer answer)
    : limits_(limits), answer_(std::move(answer)) {}

ConnectionGate::~ConnectionGate() { Stop(); }

bool ConnectionGate::Start() {
  wake_fd_ = eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  if (wake_fd_ < 0) return false;
  thread_ = std::thread([this] { Run(); });
  return true;
}

void ConnectionGate::Wake() {
  if (wake_fd_ < 0) return;
  const uint64_t one = 1;
  // A full counter (never in practice) still leaves the descriptor readable: the loop wakes.
  [[maybe_unused]] const ssize_t written = ::write(wake_fd_, &one, sizeof(one));
}

void ConnectionGate::Adopt(int fd) {
  if (fd < 0) return;
  // A slot is taken here, on the accepting thread, so that a flood is turned away before it
  // costs the gate anything but this check.
  bool refuse = stopping_.load();
  if (!refuse && open_.fetch_add(1) >= limits_.max_connections) {
    open_.fetch_sub(1);
    refuse = true;
  }
  if (refuse) {
    ::send(fd, kBusy, sizeof(kBusy) - 1, MSG_NOSIGNAL | MSG_DONTWAIT);
    ::close(fd);
    std::lock_guard<std::mutex> lock(mutex_);
    ++counts_.refused_busy;
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    incoming_.push_back(fd);
    ++counts_.adopted;
  }
  Wake();
}

void ConnectionGate::Stop() {
  if (stopping_.exchange(true)) {
    if (thread_.joinable()) thread_.join();
    return;
  }
  Wake();
  if (thread_.joinable()) thread_.join();
  std::lock_guard<std::mutex> lock(mutex_);
  for (int fd : incoming_) ::close(fd);
  incoming_.clear();
  if (wake_fd_ >= 0) ::close(wake_fd_);
  wake_fd_ = -1;
}

ServeCounts ConnectionGate::counts() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return counts_;
}

void ConnectionGate::Run() {
  std::vector<std::unique_ptr<Connection>> connections;
  std::vector<pollfd> fds;
  std::vector<char> buffer(16384);
  const auto close_connection = [this](Connection* c) {
    ::close(c->fd);
    c->fd = -1;
    open_.fetch_sub(1);
  };
  while (!stopping_.load()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      for (int fd : incoming_) {
        auto c = std::make_unique<Connection>();
        c->fd = fd;
        ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) | O_NONBLOCK);
        // A fixed send buffer: the kernel holds at most this of an answer a client does not
        // read (its autotuning would grow it to megabytes), the gate the rest until the deadline.
        if (limits_.send_buffer_bytes > 0) {
          ::setsockopt(fd, SOL_SOCKET, SO_SNDBUF, &limits_.send_buffer_bytes,
                       sizeof(limits_.send_buffer_bytes));
        }
        c->deadline = After(limits_.head_timeout_s);
        connections.push_back(std::move(c));
      }
      incoming_.clear();
    }
    fds.assign(1, pollfd{wake_fd_, POLLIN, 0});
    auto next_deadline = Clock::now() + std::chrono::seconds(1);
    for (const auto& c : connections) {
      const short events = c->phase == Connection::Phase::kWriting ? POLLOUT : POLLIN;
      fds.push_back(pollfd{c->fd, events, 0});
      next_deadline = std::min(next_deadline, c->deadline);
    }
    const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_deadline - Clock::now());
    const int timeout_ms = static_cast<int>(std::clamp<int64_t>(wait.count() + 1, 0, 1000));
    const int ready = ::poll(fds.data(), fds.size(), timeout_ms);
    if (ready < 0 && errno != EINTR) break;
    if (fds[0].revents != 0) {
      uint64_t count = 0;
      [[maybe_unused]] const ssize_t n = ::read(wake_fd_, &count, sizeof(count));
    }
    const auto now = Clock::now();
    ServeCounts counted;
    for (size_t i = 0; i < connections.size(); ++i) {
      Connection* c = connections[i].get();
      const short revents = ready > 0 ? fds[i + 1].revents : 0;
      if (c->phase == Connection::Phase::kReading && (revents & (POLLIN | POLLHUP | POLLERR))) {
        const size_t room = limits_.max_head_bytes + 1 - std::min(c->in.size(), limits_.max_head_bytes);
        const ssize_t n = ::recv(c->fd, buffer.data(), std::min(room, buffer.size()), 0);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
          close_connection(c);
          continue;
        }
        if (n > 0) {
          const size_t before = c->in.size();
          c->in.append(buffer.data(), static_cast<size_t>(n));
          const size_t end = HeadEnd(c->in, before);
          if (end != std::string::npos && end <= limits_.max_head_bytes) {
            try {
              c->out = answer_(c->in.substr(0, end), c->fd);
            } catch (const std::exception&) {
              c->out = kFailed;  // a 500: the answer could not be made
            }
            if (c->out.size() > limits_.max_answer_bytes) c->out = kFailed;
          } else if (c->in.size() > limits_.max_head_bytes) {
            c->out = kTooLong;
            ++counted.head_too_long;
          }
          if (!c->out.empty()) {
            c->in.clear();
            c->in.shrink_to_fit();
            c->phase = Connection::Phase::kWriting;
            c->deadline = After(limits_.answer_timeout_s);
          }
        }
      } else if (c->phase == Connection::Phase::kWriting && (revents & (POLLOUT | POLLHUP | POLLERR))) {
        const ssize_t n = ::send(c->fd, c->out.data() + c->sent, c->out.size() - c->sent,
                                 MSG_NOSIGNAL | MSG_DONTWAIT);
        if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR) {
          close_connection(c);
          continue;
        }
        if (n > 0) c->sent += static_cast<size_t>(n);
        if (c->sent == c->out.size()) {
          ++counted.answered;
          c->out.clear();
          c->out.shrink_to_fit();
          // Half-close and read what the client still sends until it closes: closing with
          // unread input would reset the connection and could lose the answer on its way.
          ::shutdown(c->fd, SHUT_WR);
          c->phase = Connection::Phase::kClosing;
        }
      } else if (c->phase == Connection::Phase::kClosing && (revents & (POLLIN | POLLHUP | POLLERR))) {
        const ssize_t n = ::recv(c->fd, buffer.data(), buffer.size(), 0);
        if (n == 0 || (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR)) {
          close_connection(c);
          continue;
        }
      }
      if (c->fd >= 0 && now >= c->deadline) {
        if (c->phase != Connection::Phase::kClosing) ++counted.timed_out;
        close_connection(c);
      }
    }
    connections.erase(std::remove_if(connections.begin(), connections.end(),
                                     [](const std::unique_ptr<Connection>& c) { return c->fd < 0; }),
                      connections.end());
    if (counted.head_too_long + counted.timed_out + counted.answered > 0) {
      std::lock_guard<std::mutex> lock(mutex_);
      counts_.head_too_long += counted.head_too_long;
      counts_.timed_out += counted.timed_out;
      counts_.answered += counted.answered;
    }
  }
  for (auto& c : connections) {
    if (c->fd >= 0) close_connection(c.get());
  }
}

}  // namespace wallcal::serve::internal
