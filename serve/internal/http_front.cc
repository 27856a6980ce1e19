// SPDX-License-Identifier: Apache-2.0
#include "serve/internal/http_front.h"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>

#include <algorithm>
#include <cstring>

namespace wallcal::serve::internal {
namespace {

// Runs each task at once on the thread that enqueues it: cpp-httplib's accepting thread, whose
// only task per connection is handing the socket to the gate (never blocks).
class InlineQueue : public httplib::TaskQueue {
 public:
  void enqueue(std::function<void()> fn) override { fn(); }
  void shutdown() override {}
};

// A request head for cpp-httplib's parser to read, and a bounded buffer for what it writes.
class HeadStream : public httplib::Stream {
 public:
  HeadStream(std::string head, int fd) : head_(std::move(head)), fd_(fd) {}
  bool is_readable() const override { return read_ < head_.size(); }
  bool is_writable() const override { return true; }
  ssize_t read(char* ptr, size_t size) override {
    const size_t n = std::min(size, head_.size() - read_);
    std::memcpy(ptr, head_.data() + read_, n);
    read_ += n;
    return static_cast<ssize_t>(n);
  }
  ssize_t write(const char* ptr, size_t size) override {
    if (written_.size() + size > kMaxWritten) return -1;
    written_.append(ptr, size);
    return static_cast<ssize_t>(size);
  }
  void get_remote_ip_and_port(std::string& ip, int& port) const override {
    Address(::getpeername, ip, port);
  }
  void get_local_ip_and_port(std::string& ip, int& port) const override {
    Address(::getsockname, ip, port);
  }
  // No socket for cpp-httplib to select() on: the gate polls it (and an fd past FD_SETSIZE
  // would otherwise be answered 500).
  socket_t socket() const override { return INVALID_SOCKET; }

  std::string& written() { return written_; }

 private:
  static constexpr size_t kMaxWritten = 16 << 20;

  template <class Query>
  void Address(Query query, std::string& ip, int& port) const {
    sockaddr_storage address{};
    socklen_t length = sizeof(address);
    ip.clear();
    port = 0;
    if (query(fd_, reinterpret_cast<sockaddr*>(&address), &length) != 0) return;
    char text[INET6_ADDRSTRLEN] = {};
    if (address.ss_family == AF_INET) {
      const auto* v4 = reinterpret_cast<const sockaddr_in*>(&address);
      if (inet_ntop(AF_INET, &v4->sin_addr, text, sizeof(text)) != nullptr) ip = text;
      port = ntohs(v4->sin_port);
    } else if (address.ss_family == AF_INET6) {
      const auto* v6 = reinterpret_cast<const sockaddr_in6*>(&address);
      if (inet_ntop(AF_INET6, &v6->sin6_addr, text, sizeof(text)) != nullptr) ip = text;
      port = ntohs(v6->sin6_port);
    }
  }

  std::string head_;
  size_t read_ = 0;
  int fd_;
  std::string written_;
};

// The request line of `head` followed by the empty line that ends a head; CRLF whatever the
// client used.
std::string RequestLineOnly(const std::string& head) {
  size_t end = head.find('\n');
  if (end == std::string::npos) end = head.size();
  if (end > 0 && head[end - 1] == '\r') --end;
  return head.substr(0, end) + "\r\n\r\n";
}

}  // namespace

HttpFront::HttpFront(ConnectionGate* gate) : gate_(gate) {
  new_task_queue = [] { return new InlineQueue; };
  // SO_REUSEADDR only: cpp-httplib's default also sets SO_REUSEPORT, which would let a second
  // server bind the same port beside this one instead of failing.
  set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
}

void HttpFront::WidenBacklog(int backlog) {
  // listen() again on a listening socket sets its backlog anew (Linux).
  if (svr_sock_ != INVALID_SOCKET) ::listen(svr_sock_, backlog);
}

bool HttpFront::process_and_close_socket(socket_t sock) {
  gate_->Adopt(sock);
  return true;
}

std::string HttpFront::Answer(const std::string& head, int fd) {
  HeadStream stream(RequestLineOnly(head), fd);
  bool connection_closed = false;
  process_request(stream, /*close_connection=*/true, connection_closed, nullptr);
  return std::move(stream.written());
}

}  // namespace wallcal::serve::internal
