// SPDX-License-Identifier: Apache-2.0
#pragma once
// The guide's page over HTTP (`wallcal guide --serve [ADDR:]PORT`): one self-contained page and
// the JSON it polls, read from a LiveBoard the guide publishes to. Fixed paths only, GET only,
// nothing read from the file system:
//   /             the page (HTML, CSS, JavaScript and SVG in one document, built in)
//   /live.json    LiveBoard::Live(): the report, what the guide waits for, the σ history
//   /report.json  the newest report exactly as guide --json prints it
// Anything else is 404, a method other than GET 405. Away from loopback every request needs
// ?token=TOKEN (403 without it; the page passes its own on to its requests).
//
// The server runs on threads of its own (cpp-httplib's accepting thread and one thread that
// does all socket I/O with poll(), see internal/http_front.h) and only reads the board's
// snapshots: the guide's refreshes never wait on a client.

#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "serve/serve_limits.h"
#include "serve/listen_address.h"
#include "serve/live_board.h"

namespace wallcal::serve {

namespace internal {
class ConnectionGate;
class HttpFront;
}  // namespace internal

// After the guide ends (enough, --max-seconds), the page is served until it has fetched the
// last report, at most this long (s): it polls twice a second.
inline constexpr double kLastReportLingerS = 10.0;

enum class TokenRule {
  kUnlessLoopback,  // a token is needed unless the address is a loopback one (the default)
  kAlways,          // always (the tests' loopback server in the token's mode)
};

struct ServeOptions {
  ListenAddress address;
  TokenRule token_rule = TokenRule::kUnlessLoopback;
  ServeLimits limits;
};

class GuideServer {
 public:
  // `board` must outlive the server. Nothing is bound yet.
  GuideServer(const LiveBoard* board, ServeOptions options);
  ~GuideServer();  // Stop()
  GuideServer(const GuideServer&) = delete;
  GuideServer& operator=(const GuideServer&) = delete;

  // Binds and starts serving. Throws io::InputError when it cannot listen at the address (not
  // an address of this machine, the port in use or reserved).
  void Start();
  // Stops listening, closes every connection and joins the threads. Idempotent.
  void Stop();

  int port() const { return port_; }
  // The access token (32 hex digits), empty when none is needed.
  const std::string& token() const { return token_; }
  // The page's URLs, one per address a browser can reach (ReachableHosts), token included.
  std::vector<std::string> Urls() const;
  ServeCounts counts() const;
  // The newest LiveSnapshot::seq /live.json has answered with (0: none yet).
  int64_t served_seq() const { return served_seq_->load(); }
  // Waits until /live.json has answered with `seq` or later, at most max_s; true if it has.
  bool WaitUntilServed(int64_t seq, double max_s) const;

 private:
  const LiveBoard* board_;
  ServeOptions options_;
  std::string token_;
  int port_ = 0;
  std::unique_ptr<internal::ConnectionGate> gate_;
  std::unique_ptr<internal::HttpFront> front_;
  std::thread listening_;
  bool started_ = false;
  // Shared with the request handler (which may outlive no server, but is a copyable lambda).
  std::shared_ptr<std::atomic<int64_t>> served_seq_ = std::make_shared<std::atomic<int64_t>>(0);
};

}  // namespace wallcal::serve
