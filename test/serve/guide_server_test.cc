// SPDX-License-Identifier: Apache-2.0
// guide --serve's server against clients that do what they should not: no token or a wrong one,
// paths that climb out ("..", "%2e%2e"), a header of a megabyte, 200 connections at once, a
// client that sends a byte at a time, clients that never read a large answer, methods other
// than GET. Each is refused or dropped; meanwhile a thread publishes a report every 50 ms, as
// the guide's refreshes do, and a well-behaved client must still get the newest one (polled
// until it does, within a generous bound: no timing is asserted), and the process's memory
// must stay within a generous bound (VmRSS before and after).

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "guide/guide.h"
#include "guide/guide_text.h"
#include "io/types.h"
#include "serve/guide_server.h"
#include "serve/listen_address.h"
#include "serve/live_board.h"
#include "test/support/json_value.h"
#include "test/support/raw_http.h"

namespace wallcal {
namespace {

using testing_support::HttpGet;
using testing_support::HttpReply;
using testing_support::RawExchange;

// The process's resident memory (kB).
long ResidentKb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::stol(line.substr(6));
  }
  return 0;
}

// A report with `stations` stations (its JSON about 300 bytes a station).
guide::GuideReport Report(int stations, double logged_s) {
  guide::GuideReport report;
  report.session_name = "hostile";
  report.wall_ids = {"A"};
  calib::WallGeometry wall;
  wall.id = "A";
  wall.end_a_local = Eigen::Vector2d(0.0, -5.0);
  wall.end_b_local = Eigen::Vector2d(0.0, 5.0);
  report.walls = {wall};
  for (int i = 0; i < stations; ++i) {
    guide::StationSummary s;
    s.start_s = i;
    s.end_s = i + 0.5;
    s.pose.antenna_local_m = Eigen::Vector2d(-8.0, 0.01 * i);
    report.stations.push_back(s);
  }
  report.logged_s = logged_s;
  return report;
}

class GuideServerTest : public ::testing::Test {
 protected:
  void Start(serve::TokenRule rule = serve::TokenRule::kUnlessLoopback, int max_connections = 32,
             double head_timeout_s = 1.0) {
    board_ = std::make_unique<serve::LiveBoard>();
    board_->PublishReport(Report(3, 0.0));
    serve::ServeOptions options;
    options.address.host = "127.0.0.1";
    options.address.port = 0;
    options.token_rule = rule;
    // Short deadlines, so that a test waits seconds, not minutes, for the server to let go.
    options.limits.max_connections = max_connections;
    options.limits.head_timeout_s = head_timeout_s;
    options.limits.answer_timeout_s = 2.0;
    server_ = std::make_unique<serve::GuideServer>(board_.get(), options);
    server_->Start();
    port_ = server_->port();
    ASSERT_GT(port_, 0);
    rss_before_kb_ = ResidentKb();
  }

  // Publishes a growing report every 50 ms until the test ends, as the guide's refreshes do.
  void Publish(int stations = 3) {
    publisher_ = std::thread([this, stations] {
      for (int i = 1; !stop_.load(); ++i) {
        board_->PublishReport(Report(stations, i));
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    });
  }

  void TearDown() override {
    stop_ = true;
    if (publisher_.joinable()) publisher_.join();
    if (server_) server_->Stop();
  }

  std::string Token() const { return server_->token().empty() ? "" : "?token=" + server_->token(); }

  // A well-behaved client gets a document at least as new as the newest published when it
  // asked, within `within_s` (retrying what a busy server turns away).
  void ExpectNewest(double within_s = 60.0) {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(within_s);
    std::string last;
    while (std::chrono::steady_clock::now() < deadline) {
      const int64_t newest = board_->seq();
      ++good_requests_;
      const HttpReply reply = HttpGet(port_, "/live.json" + Token(), 10000);
      testing_support::Json doc;
      if (reply.status == 200 && testing_support::JsonParser(reply.body).Parse(&doc) &&
          doc["seq"].number >= static_cast<double>(newest)) {
        return;
      }
      last = std::to_string(reply.status) + " " + reply.body.substr(0, 80);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
    ADD_FAILURE() << "no newest report within " << within_s << " s; last answer: " << last;
  }

  void ExpectMemoryBounded() {
#if defined(__SANITIZE_ADDRESS__)
    // AddressSanitizer keeps freed memory in quarantine (256 MB by default): VmRSS says
    // nothing of the server's own there.
#else
    const long growth_kb = ResidentKb() - rss_before_kb_;
    EXPECT_LT(growth_kb, 64 * 1024) << "VmRSS grew by " << growth_kb << " kB";
#endif
  }

  std::unique_ptr<serve::LiveBoard> board_;
  std::unique_ptr<serve::GuideServer> server_;
  int port_ = 0;
  long rss_before_kb_ = 0;
  std::atomic<bool> stop_{false};
  std::thread publisher_;
  int64_t good_requests_ = 0;  // the well-behaved client's (ExpectNewest)
};

TEST_F(GuideServerTest, ServesThePageAndItsJsonOnLoopbackWithoutAToken) {
  Start();
  EXPECT_TRUE(server_->token().empty());
  const HttpReply page = HttpGet(port_, "/");
  ASSERT_EQ(page.status, 200);
  EXPECT_NE(page.head.find("Content-Type: text/html"), std::string::npos) << page.head;
  EXPECT_NE(page.head.find("Content-Security-Policy: default-src 'none'"), std::string::npos);
  EXPECT_NE(page.body.find("<title>wallcal guide</title>"), std::string::npos);
  EXPECT_EQ(page.body.find("src=\"http"), std::string::npos) << "the page loads nothing";

  const guide::GuideReport report = Report(4, 12.0);
  board_->PublishReport(report, 12345);
  const HttpReply live = HttpGet(port_, "/live.json");
  ASSERT_EQ(live.status, 200);
  testing_support::Json doc;
  ASSERT_TRUE(testing_support::JsonParser(live.body).Parse(&doc)) << live.body;
  EXPECT_EQ(doc["seq"].number, static_cast<double>(board_->seq()));
  EXPECT_EQ(doc["scan_log_bytes"].number, 12345);
  EXPECT_EQ(doc["report"]["stations"].number, 4);
  EXPECT_EQ(doc["history"].items.size(), 2u);
  // /report.json is guide --json's line for the same report, byte for byte.
  EXPECT_EQ(HttpGet(port_, "/report.json").body, guide::GuideJson(report));
}

TEST_F(GuideServerTest, RefusesRequestsWithoutItsTokenAwayFromLoopback) {
  Start(serve::TokenRule::kAlways);
  const std::string token = server_->token();
  ASSERT_EQ(token.size(), 32u);
  EXPECT_EQ(token.find_first_not_of("0123456789abcdef"), std::string::npos);
  ASSERT_FALSE(server_->Urls().empty());
  EXPECT_NE(server_->Urls().front().find("?token=" + token), std::string::npos);
  Publish();
  for (const std::string& target :
       {std::string("/"), std::string("/live.json"), std::string("/report.json"),
        std::string("/?token="), "/?token=" + token.substr(0, 31),
        "/?token=" + token + "0", "/live.json?token=" + std::string(32, '0'),
        "/live.json?tok=" + token}) {
    const HttpReply reply = HttpGet(port_, target);
    EXPECT_EQ(reply.status, 403) << target;
    EXPECT_EQ(reply.body.find("hostile"), std::string::npos) << target;
  }
  EXPECT_EQ(HttpGet(port_, "/?token=" + token).status, 200);
  EXPECT_EQ(HttpGet(port_, "/live.json?token=" + token).status, 200);
  ExpectNewest();
}

TEST(GuideServerAddressTest, NeedsItsTokenOnEveryAddressWhenNotBoundToLoopback) {
  // Bound to every address (as for a tablet), so asked through loopback too: the token rule
  // follows the address bound, not the one a request comes in on.
  serve::LiveBoard board;
  serve::ServeOptions options;
  options.address.host = "0.0.0.0";
  serve::GuideServer server(&board, options);
  try {
    server.Start();
  } catch (const io::InputError& e) {
    GTEST_SKIP() << "cannot bind 0.0.0.0 here: " << e.what();
  }
  ASSERT_EQ(server.token().size(), 32u);
  EXPECT_EQ(HttpGet(server.port(), "/").status, 403);
  EXPECT_EQ(HttpGet(server.port(), "/live.json").status, 403);
  EXPECT_EQ(HttpGet(server.port(), "/?token=" + server.token()).status, 200);
  for (const std::string& url : server.Urls()) {
    EXPECT_NE(url.find("?token=" + server.token()), std::string::npos) << url;
  }
}

TEST_F(GuideServerTest, ServesItsFixedPathsOnlyAndNothingFromTheFileSystem) {
  Start();
  Publish();
  for (const char* target :
       {"/..", "/../../../../etc/passwd", "/%2e%2e/%2e%2e/%2e%2e/etc/passwd",
        "/%2E%2E%2F%2E%2E%2Fetc%2Fpasswd", "/..%2f..%2f..%2fetc%2fpasswd", "//etc/passwd",
        "/live.json/../../../etc/passwd", "/./live.json/..", "/guide_page.html",
        "/serve/guide_page.html", "/CMakeLists.txt", "/index.html", "/live.json%00",
        "/%00", "/favicon.ico", "/report.json/x", "/.%2e/.%2e/etc/passwd"}) {
    const HttpReply reply = HttpGet(port_, target);
    EXPECT_TRUE(reply.status == 404 || reply.status == 400) << target << ": " << reply.status;
    EXPECT_EQ(reply.body.find("root:"), std::string::npos) << target;
    EXPECT_EQ(reply.body.find("<html"), std::string::npos) << target;
  }
  ExpectNewest();
  ExpectMemoryBounded();
}

TEST_F(GuideServerTest, AnswersGetOnly) {
  Start();
  Publish();
  for (const char* method : {"POST", "PUT", "DELETE", "PATCH", "OPTIONS", "HEAD"}) {
    const HttpReply reply = RawExchange(
        port_, std::string(method) + " /live.json HTTP/1.1\r\nHost: x\r\nContent-Length: 5\r\n\r\nhello");
    EXPECT_EQ(reply.status, 405) << method;
    EXPECT_NE(reply.head.find("Allow: GET"), std::string::npos) << method;
  }
  // A body announced that never comes, and one far too long: the answer does not wait for it.
  EXPECT_EQ(RawExchange(port_, "POST / HTTP/1.1\r\nContent-Length: 100000000\r\n\r\n").status, 405);
  EXPECT_EQ(RawExchange(port_, "PUT / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\nffffffff\r\n")
                .status,
            405);
  EXPECT_EQ(RawExchange(port_, "BREW /pot HTTP/1.1\r\n\r\n").status, 400);
  EXPECT_EQ(RawExchange(port_, "GET\r\n\r\n").status, 400);
  ExpectNewest();
  ExpectMemoryBounded();
}

TEST_F(GuideServerTest, DropsAHeaderOfAMegabyte) {
  Start();
  Publish();
  for (int round = 0; round < 5; ++round) {
    const std::string huge = "GET / HTTP/1.1\r\nX-Big: " + std::string(1 << 20, 'a') + "\r\n\r\n";
    const int fd = testing_support::ConnectLoopback(port_);
    ASSERT_GE(fd, 0);
    testing_support::SendAll(fd, huge, 20000);  // the server may close before it is all sent
    bool closed = false;
    const HttpReply reply = testing_support::ParseReply(testing_support::ReadUntilClosed(fd, 30000, &closed));
    ::close(fd);
    EXPECT_TRUE(closed);
    EXPECT_TRUE(reply.status == 0 || reply.status == 431) << reply.status;
  }
  // A long line without an end at all, and a request line of a megabyte.
  EXPECT_NE(RawExchange(port_, std::string(1 << 20, 'G')).status, 200);
  EXPECT_NE(RawExchange(port_, "GET /" + std::string(1 << 20, 'a') + " HTTP/1.1\r\n\r\n").status, 200);
  EXPECT_GE(server_->counts().head_too_long, 5);
  ExpectNewest();
  ExpectMemoryBounded();
}

// `count` connections to 127.0.0.1:port opened at once (non-blocking connects, then waited for
// together): those that connected.
std::vector<int> ConnectAtOnce(int port, int count) {
  std::vector<int> fds;
  for (int i = 0; i < count; ++i) {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(static_cast<uint16_t>(port));
    if (fd >= 0 && (::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof(address)) == 0 ||
                    errno == EINPROGRESS)) {
      fds.push_back(fd);
    } else if (fd >= 0) {
      ::close(fd);
    }
  }
  std::vector<int> connected;
  std::vector<pollfd> waiting;
  for (int fd : fds) waiting.push_back(pollfd{fd, POLLOUT, 0});
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!waiting.empty() && std::chrono::steady_clock::now() < deadline) {
    if (::poll(waiting.data(), waiting.size(), 1000) <= 0) continue;
    std::vector<pollfd> still;
    for (const pollfd& p : waiting) {
      if (p.revents == 0) {
        still.push_back(p);
        continue;
      }
      int error = 0;
      socklen_t length = sizeof(error);
      if (::getsockopt(p.fd, SOL_SOCKET, SO_ERROR, &error, &length) == 0 && error == 0) {
        ::fcntl(p.fd, F_SETFL, ::fcntl(p.fd, F_GETFL) & ~O_NONBLOCK);
        connected.push_back(p.fd);
      } else {
        ::close(p.fd);
      }
    }
    waiting = std::move(still);
  }
  for (const pollfd& p : waiting) ::close(p.fd);
  return connected;
}

TEST_F(GuideServerTest, TurnsAwayConnectionsBeyondItsLimitAndKeepsServing) {
  // The silent connections held 5 s: long enough that the 200 are all open at once.
  Start(serve::TokenRule::kUnlessLoopback, /*max_connections=*/32, /*head_timeout_s=*/5.0);
  Publish();
  std::vector<int> idle = ConnectAtOnce(port_, 200);
  EXPECT_EQ(idle.size(), 200u);
  // More than max_connections (32) at once: the rest answered 503 and closed at once; the
  // 32 silent ones closed at their head's deadline; and the newest report still comes.
  ExpectNewest();
  const serve::ServeCounts counts = server_->counts();
  EXPECT_GE(counts.refused_busy, 1);
  EXPECT_GE(counts.timed_out, 1);
  // Every connection the server took (answered 503, or silent to its deadline) is let go. (A
  // connection the kernel's accept queue dropped never reached the server: its client is left
  // waiting, as with any server.)
  // Whether the peer has closed: what is there read and dropped, until EOF (closed), a reset
  // (closed) or nothing more yet (open).
  const auto peer_closed = [](int fd) {
    char buffer[4096];
    while (true) {
      const ssize_t n = ::recv(fd, buffer, sizeof(buffer), MSG_DONTWAIT);
      if (n > 0) continue;
      return n == 0 || (errno != EAGAIN && errno != EWOULDBLOCK && errno != EINTR);
    }
  };
  std::vector<pollfd> open;
  for (int fd : idle) open.push_back(pollfd{fd, POLLIN, 0});
  int64_t closed = 0;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (!open.empty() && std::chrono::steady_clock::now() < deadline) {
    const serve::ServeCounts now = server_->counts();
    // The silent ones the server took: all it took or refused but the well-behaved client's.
    if (closed >= now.adopted + now.refused_busy - good_requests_) break;
    if (::poll(open.data(), open.size(), 500) <= 0) continue;
    std::vector<pollfd> still;
    for (const pollfd& p : open) {
      if (p.revents != 0 && peer_closed(p.fd)) {
        ++closed;
      } else {
        still.push_back(pollfd{p.fd, POLLIN, 0});
      }
    }
    open = std::move(still);
  }
  const serve::ServeCounts final_counts = server_->counts();
  EXPECT_GE(closed, final_counts.adopted + final_counts.refused_busy - good_requests_)
      << "connections the server took and never let go";
  for (int fd : idle) ::close(fd);
  ExpectMemoryBounded();
}

TEST_F(GuideServerTest, CutsAClientThatSendsAByteAtATimeAtItsDeadline) {
  Start();
  Publish();
  const int fd = testing_support::ConnectLoopback(port_);
  ASSERT_GE(fd, 0);
  const std::string drip = "GET / HTTP/1.1\r\nX-Slow: " + std::string(10000, 's');
  bool sent_all = true;
  size_t i = 0;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  for (; i < drip.size() && std::chrono::steady_clock::now() < give_up; ++i) {
    if (::send(fd, &drip[i], 1, MSG_NOSIGNAL) != 1) {
      sent_all = false;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  EXPECT_FALSE(sent_all) << "the server took " << i << " bytes at a trickle without closing";
  ::close(fd);
  EXPECT_GE(server_->counts().timed_out, 1);
  ExpectNewest();
}

TEST_F(GuideServerTest, ClientsThatNeverReadHoldNoMoreThanTheirAnswers) {
  Start(serve::TokenRule::kUnlessLoopback, /*max_connections=*/16);
  const guide::GuideReport big = Report(6000, 1.0);
  board_->PublishReport(big);
  ASSERT_GT(guide::GuideJson(big).size(), 800000u);  // far beyond the socket buffers
  Publish(6000);
  std::vector<int> stuck;
  for (int i = 0; i < 40; ++i) {
    // A tiny receive buffer: the answer stays mostly unsent.
    const int fd = testing_support::ConnectLoopback(port_, 4096, 30000);
    if (fd < 0) continue;
    testing_support::SendAll(fd, i % 2 ? "GET /report.json HTTP/1.1\r\n\r\n" : "GET / HTTP/1.1\r\n\r\n");
    stuck.push_back(fd);
  }
  ExpectNewest();
  EXPECT_GE(server_->counts().timed_out, 1);
  ExpectMemoryBounded();
  for (int fd : stuck) ::close(fd);
}

TEST(ListenAddressTest, ParsesPortsAndAddresses) {
  serve::ListenAddress address;
  std::string message;
  EXPECT_EQ(serve::ParseListenAddress("8080", &address, &message), serve::AddressError::kNone);
  EXPECT_EQ(address.host, "127.0.0.1");
  EXPECT_EQ(address.port, 8080);
  EXPECT_EQ(serve::ParseListenAddress("0.0.0.0:0", &address, &message), serve::AddressError::kNone);
  EXPECT_EQ(address.host, "0.0.0.0");
  EXPECT_EQ(address.port, 0);
  EXPECT_EQ(serve::ParseListenAddress("[::1]:9", &address, &message), serve::AddressError::kNone);
  EXPECT_EQ(address.host, "::1");
  EXPECT_EQ(serve::ParseListenAddress("", &address, &message), serve::AddressError::kEmpty);
  EXPECT_EQ(serve::ParseListenAddress("65536", &address, &message), serve::AddressError::kBadPort);
  EXPECT_EQ(serve::ParseListenAddress("1:-1", &address, &message), serve::AddressError::kBadPort);
  EXPECT_EQ(serve::ParseListenAddress("x", &address, &message), serve::AddressError::kBadPort);
  EXPECT_EQ(serve::ParseListenAddress("example.com:80", &address, &message),
            serve::AddressError::kBadHost);
  EXPECT_EQ(serve::ParseListenAddress("::1:80", &address, &message), serve::AddressError::kBadHost);
  EXPECT_FALSE(message.empty());
}

TEST(ListenAddressTest, TellsLoopbackFromTheNetworkAndMakesFreshTokens) {
  EXPECT_TRUE(serve::IsLoopbackHost("127.0.0.1"));
  EXPECT_TRUE(serve::IsLoopbackHost("127.1.2.3"));
  EXPECT_TRUE(serve::IsLoopbackHost("::1"));
  EXPECT_TRUE(serve::IsLoopbackHost("localhost"));
  EXPECT_FALSE(serve::IsLoopbackHost("0.0.0.0"));
  EXPECT_FALSE(serve::IsLoopbackHost("192.168.1.20"));
  EXPECT_FALSE(serve::IsLoopbackHost("::"));
  const std::string a = serve::NewAccessToken(), b = serve::NewAccessToken();
  EXPECT_EQ(a.size(), 32u);
  EXPECT_NE(a, b);
  EXPECT_TRUE(serve::TokensEqual(a, a));
  EXPECT_FALSE(serve::TokensEqual(a, b));
  EXPECT_FALSE(serve::TokensEqual("", ""));
  EXPECT_FALSE(serve::TokensEqual(a.substr(0, 31), a));
  EXPECT_EQ(serve::PageUrl("::1", 80, "ab"), "http://[::1]:80/?token=ab");
}

}  // namespace
}  // namespace wallcal
