// SPDX-License-Identifier: Apache-2.0
#pragma once
// HTTP on loopback by hand, for the tests of guide --serve's server: raw sockets that send what
// a test says (however malformed) and read what comes back, each step under a time limit, so
// that a server that hangs fails the test instead of hanging it.

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <string>

namespace wallcal::testing_support {

// A free TCP port on loopback (bound and let go: the caller binds it again soon after).
inline int FreeLoopbackPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = 0;
  int port = 0;
  socklen_t length = sizeof(address);
  if (::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) == 0) {
    port = ntohs(address.sin_port);
  }
  ::close(fd);
  return port;
}

// A connected socket to 127.0.0.1:port, or -1. `receive_buffer` > 0 sets SO_RCVBUF first (a
// client that reads nothing then holds little of an answer).
inline int ConnectLoopback(int port, int receive_buffer = 0, int timeout_ms = 10000) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return -1;
  if (receive_buffer > 0) {
    ::setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &receive_buffer, sizeof(receive_buffer));
  }
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(static_cast<uint16_t>(port));
  if (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) != 0 &&
      errno != EINPROGRESS) {
    ::close(fd);
    return -1;
  }
  pollfd p{fd, POLLOUT, 0};
  int error = 0;
  socklen_t length = sizeof(error);
  if (::poll(&p, 1, timeout_ms) != 1 ||
      ::getsockopt(fd, SOL_SOCKET, SO_ERROR, &error, &length) != 0 || error != 0) {
    ::close(fd);
    return -1;
  }
  ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL) & ~O_NONBLOCK);
  return fd;
}

// Sends all of `bytes` (false when the peer closed or the time ran out).
inline bool SendAll(int fd, const std::string& bytes, int timeout_ms = 10000) {
  size_t sent = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (sent < bytes.size()) {
    pollfd p{fd, POLLOUT, 0};
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0 || ::poll(&p, 1, static_cast<int>(left)) != 1) return false;
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent,
                             MSG_NOSIGNAL | MSG_DONTWAIT);
    if (n < 0 && errno != EAGAIN && errno != EINTR) return false;
    if (n > 0) sent += static_cast<size_t>(n);
  }
  return true;
}

// Everything the peer sends until it closes (or resets), at most `timeout_ms`; *closed says
// whether it did close in that time.
inline std::string ReadUntilClosed(int fd, int timeout_ms, bool* closed = nullptr) {
  std::string in;
  char buffer[65536];
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  if (closed != nullptr) *closed = false;
  while (true) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
        deadline - std::chrono::steady_clock::now()).count();
    if (left <= 0) return in;
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, static_cast<int>(left)) != 1) continue;
    const ssize_t n = ::recv(fd, buffer, sizeof(buffer), 0);
    if (n > 0) {
      in.append(buffer, static_cast<size_t>(n));
    } else if (n == 0 || (errno != EAGAIN && errno != EINTR)) {
      if (closed != nullptr) *closed = true;
      return in;
    }
  }
}

struct HttpReply {
  int status = 0;  // 0: no answer (refused, closed, time out)
  std::string head, body;
};

inline HttpReply ParseReply(const std::string& raw) {
  HttpReply reply;
  const size_t end = raw.find("\r\n\r\n");
  if (raw.rfind("HTTP/1.1 ", 0) != 0 || end == std::string::npos) return reply;
  reply.status = std::atoi(raw.c_str() + 9);
  reply.head = raw.substr(0, end);
  reply.body = raw.substr(end + 4);
  return reply;
}

// One exchange: `request` sent as is, the answer read until the server closes.
inline HttpReply RawExchange(int port, const std::string& request, int timeout_ms = 20000) {
  const int fd = ConnectLoopback(port, 0, timeout_ms);
  if (fd < 0) return {};
  HttpReply reply;
  if (SendAll(fd, request, timeout_ms)) reply = ParseReply(ReadUntilClosed(fd, timeout_ms));
  ::close(fd);
  return reply;
}

inline HttpReply HttpGet(int port, const std::string& target, int timeout_ms = 20000) {
  return RawExchange(port, "GET " + target + " HTTP/1.1\r\nHost: 127.0.0.1\r\n\r\n", timeout_ms);
}

}  // namespace wallcal::testing_support
