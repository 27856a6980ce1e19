// SPDX-License-Identifier: Apache-2.0
#pragma once
// cpp-httplib's server (Debian's libcpp-httplib 0.11) with the connection gate in front of its
// parser. Private to serve/.
//
// Why not cpp-httplib alone: Debian builds it as a shared library, so the CPPHTTPLIB_* limits
// (header length, thread pool) are those compiled into it and defining them before the include
// changes nothing; and 0.11.4 reads a whole header line into memory before comparing it with
// CPPHTTPLIB_HEADER_MAX_LENGTH, gives each connection a pool thread for as long as its client
// keeps sending a byte within the read timeout, queues accepted sockets without bound, and
// answers a Range header of thousands of ranges with a body of as many copies. So cpp-httplib
// accepts (its listening socket and accept loop), and every accepted socket goes to the gate
// (process_and_close_socket, the virtual it calls per connection, overridden), which reads the
// request head within its bounds; cpp-httplib then parses the request line of a complete head
// (process_request, on a stream over that line) and writes the answer, which the gate sends.
// Only the request line is passed on: the page needs no header, and none can then ask for
// ranges, compression, a body or 100-continue.

#include <functional>
#include <string>

#include <httplib.h>

#include "serve/internal/connection_gate.h"

namespace wallcal::serve::internal {

class HttpFront : public httplib::Server {
 public:
  // `gate` takes every accepted socket; it must outlive the listening.
  explicit HttpFront(ConnectionGate* gate);

  // The whole response to `head` (a request head as the gate read it), by cpp-httplib's
  // request parsing and the handlers set on this server. Never touches a socket.
  std::string Answer(const std::string& head, int fd);

  // After bind: lets `backlog` connections wait for acceptance (the library's listen() takes
  // 5; beyond, a burst of connections is lost in the kernel instead of reaching the gate,
  // which answers what it cannot take 503).
  void WidenBacklog(int backlog);

 private:
  // cpp-httplib calls this on its accepting thread for every accepted socket (through the
  // inline task queue set in the constructor): the socket goes to the gate.
  bool process_and_close_socket(socket_t sock) override;

  ConnectionGate* gate_;
};

}  // namespace wallcal::serve::internal
