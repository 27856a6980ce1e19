// SPDX-License-Identifier: Apache-2.0
#include "serve/guide_server.h"

#include <chrono>
#include <utility>

#include "io/types.h"
#include "serve/guide_page_data.h"  // generated from serve/guide_page.html
#include "serve/internal/connection_gate.h"
#include "serve/internal/http_front.h"

namespace wallcal::serve {
namespace {

// What every answer carries: never cached (the JSON changes twice a second), never sniffed, never
// framed, no referrer (the page's URL holds its token).
void CommonHeaders(httplib::Response& res) {
  res.set_header("Cache-Control", "no-store");
  res.set_header("X-Content-Type-Options", "nosniff");
  res.set_header("X-Frame-Options", "DENY");
  res.set_header("Referrer-Policy", "no-referrer");
}

// The page may run its own inline script and style, draw data: images, and fetch from this
// server only: nothing from elsewhere, even if a string in a report held markup.
constexpr char kPagePolicy[] =
    "default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data:; "
    "connect-src 'self'; base-uri 'none'; form-action 'none'; frame-ancestors 'none'";

// Connections waiting for acceptance (the kernel caps it at net.core.somaxconn).
constexpr int kListenBacklog = 128;

void Plain(httplib::Response& res, int status, const std::string& text) {
  res.status = status;
  res.set_content(text + "\n", "text/plain; charset=utf-8");
}

}  // namespace

GuideServer::GuideServer(const LiveBoard* board, ServeOptions options)
    : board_(board), options_(std::move(options)) {}

GuideServer::~GuideServer() { Stop(); }

void GuideServer::Start() {
  if (started_) return;
  const bool need_token = options_.token_rule == TokenRule::kAlways ||
                          !IsLoopbackHost(options_.address.host);
  token_ = need_token ? NewAccessToken() : std::string();
  // The gate answers through the front, which hands the gate its sockets: the front is made
  // before the gate's thread starts, and both live as long as the server.
  gate_ = std::make_unique<internal::ConnectionGate>(
      options_.limits,
      [this](const std::string& head, int fd) { return front_->Answer(head, fd); });
  front_ = std::make_unique<internal::HttpFront>(gate_.get());

  const LiveBoard* board = board_;
  const std::string token = token_;
  const std::shared_ptr<std::atomic<int64_t>> served = served_seq_;
  front_->set_pre_routing_handler([board, token, served](const httplib::Request& req,
                                                         httplib::Response& res) {
    CommonHeaders(res);
    if (req.method != "GET") {
      res.set_header("Allow", "GET");
      Plain(res, 405, "GET only");
    } else if (!token.empty() && !TokensEqual(req.get_param_value("token"), token)) {
      Plain(res, 403, "a token is needed: open the URL the guide printed");
    } else if (req.path == "/") {
      res.set_header("Content-Security-Policy", kPagePolicy);
      res.set_content(reinterpret_cast<const char*>(generated::kGuidePage),
                      generated::kGuidePageSize, "text/html; charset=utf-8");
    } else if (req.path == "/live.json") {
      const LiveSnapshot live = board->Live();
      res.set_content(*live.json, "application/json");
      int64_t before = served->load();
      while (before < live.seq && !served->compare_exchange_weak(before, live.seq)) {
      }
    } else if (req.path == "/report.json") {
      res.set_content(*board->ReportJson() + "\n", "application/json");
    } else {
      Plain(res, 404, "not found");
    }
    return httplib::Server::HandlerResponse::Handled;
  });
  // What cpp-httplib answers by itself (a request line it cannot parse: 400) carries the
  // headers too.
  front_->set_error_handler([](const httplib::Request&, httplib::Response& res) {
    CommonHeaders(res);
  });

  const ListenAddress& at = options_.address;
  if (at.port == 0) {
    port_ = front_->bind_to_any_port(at.host);
  } else {
    port_ = front_->bind_to_port(at.host, at.port) ? at.port : -1;
  }
  if (port_ <= 0) {
    throw io::InputError("--serve " + at.host + ":" + std::to_string(at.port) +
                         ": cannot listen there (not an address of this machine, or the port is "
                         "in use or reserved)");
  }
  front_->WidenBacklog(kListenBacklog);
  if (!gate_->Start()) throw io::InputError("--serve: cannot start the server's thread");
  listening_ = std::thread([this] { front_->listen_after_bind(); });
  // Stop() can only end the accepting loop once it runs (httplib::Server::stop does nothing
  // before): wait for it here, so that a Stop() right after Start() is never lost.
  for (int i = 0; i < 5000 && !front_->is_running(); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  started_ = true;
}

void GuideServer::Stop() {
  if (!started_) return;
  started_ = false;
  front_->stop();
  if (listening_.joinable()) listening_.join();
  gate_->Stop();
}

std::vector<std::string> GuideServer::Urls() const {
  std::vector<std::string> urls;
  for (const std::string& host : ReachableHosts(options_.address.host)) {
    urls.push_back(PageUrl(host, port_, token_));
  }
  return urls;
}

bool GuideServer::WaitUntilServed(int64_t seq, double max_s) const {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(max_s);
  while (served_seq() < seq) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  return true;
}

ServeCounts GuideServer::counts() const { return gate_ ? gate_->counts() : ServeCounts{}; }

}  // namespace wallcal::serve
