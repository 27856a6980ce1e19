// SPDX-License-Identifier: Apache-2.0
#pragma once
// A real browser for the tests and benchmarks of guide --serve's page: Debian's Chromium run
// headless by its chromedriver, driven through the W3C WebDriver HTTP API (new session, go to a
// URL, run a script, take a screenshot) on loopback. Nothing is downloaded: chromedriver and the
// browser come from the packages chromium and chromium-driver (scripts/install-deps.sh browser).
// Chromium is started with background networking, component updates, sync and QUIC off, so
// that it makes no request but the page's on a closed network, in a profile folder of its own.

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <memory>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include <httplib.h>

#include "common/json_text.h"
#include "test/support/json_value.h"
#include "test/support/raw_http.h"

namespace wallcal::testing_support {

inline constexpr char kChromium[] = "/usr/bin/chromium";
inline constexpr char kChromedriver[] = "/usr/bin/chromedriver";

// Empty when Chromium and chromedriver are installed; else why not, for a skip message.
inline std::string BrowserMissing() {
  for (const char* path : {kChromium, kChromedriver}) {
    if (::access(path, X_OK) != 0) {
      return std::string(path) +
             " is missing: the page is tested in a real browser, which `bash "
             "scripts/install-deps.sh browser` installs (packages chromium chromium-driver)";
    }
  }
  return "";
}

// A JSON string literal for a request body (common/json_text.h's escaping).
inline std::string JsonQuote(const std::string& text) { return JsonString(text); }

// Headless Chromium at a window size, one session, until destroyed (chromedriver killed).
class Browser {
 public:
  // Starts chromedriver and a session; ok() false (and error() says why) when either fails.
  Browser(const std::filesystem::path& profile_dir, int width, int height) {
    port_ = FreeLoopbackPort();
    driver_ = ::fork();
    if (driver_ == 0) {
      ::setpgid(0, 0);
      const std::string port = "--port=" + std::to_string(port_);
      ::execl(kChromedriver, kChromedriver, port.c_str(), "--silent", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    if (driver_ < 0) {
      error_ = "cannot start chromedriver";
      return;
    }
    client_ = std::make_unique<httplib::Client>("127.0.0.1", port_);
    client_->set_connection_timeout(5);
    client_->set_read_timeout(120);
    bool ready = false;
    for (int i = 0; i < 300 && !ready; ++i) {
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      auto res = client_->Get("/status");
      ready = res && res->status == 200 && res->body.find("\"ready\":true") != std::string::npos;
    }
    if (!ready) {
      error_ = "chromedriver did not become ready on port " + std::to_string(port_);
      return;
    }
    const std::vector<std::string> args = {
        "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
        "--disable-background-networking", "--disable-component-update", "--disable-sync",
        "--disable-dev-shm-usage", "--hide-scrollbars",
        "--user-data-dir=" + profile_dir.string(),
        "--window-size=" + std::to_string(width) + "," + std::to_string(height)};
    std::string list;
    for (const std::string& a : args) list += (list.empty() ? "" : ", ") + JsonQuote(a);
    const std::string body =
        "{\"capabilities\": {\"alwaysMatch\": {\"browserName\": \"chrome\", "
        "\"goog:chromeOptions\": {\"binary\": " + JsonQuote(kChromium) + ", \"args\": [" + list +
        "]}}}}";
    Json reply;
    if (!Call("POST", "/session", body, &reply)) return;
    session_ = reply["value"]["sessionId"].text;
    if (session_.empty()) {
      error_ = "no session id in chromedriver's reply";
      return;
    }
    // --window-size is the window's: the page gets it less the browser's own bars. Grown by
    // those, so that the page itself is width × height (a screenshot is the page).
    Json bars;
    if (!Execute("return [window.outerWidth - window.innerWidth, window.outerHeight - window.innerHeight];",
                 &bars) ||
        bars.items.size() != 2) {
      return;
    }
    const int w = width + static_cast<int>(bars.items[0].number);
    const int h = height + static_cast<int>(bars.items[1].number);
    Call("POST", "/session/" + session_ + "/window/rect",
         "{\"width\": " + std::to_string(w) + ", \"height\": " + std::to_string(h) + "}", &reply);
  }
  ~Browser() {
    if (!session_.empty()) client_->Delete(("/session/" + session_).c_str());
    if (driver_ > 0) {
      ::kill(-driver_, SIGTERM);
      ::kill(driver_, SIGTERM);
      int status = 0;
      for (int i = 0; i < 50; ++i) {
        if (::waitpid(driver_, &status, WNOHANG) == driver_) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
      ::kill(-driver_, SIGKILL);
      ::waitpid(driver_, &status, 0);
    }
  }
  Browser(const Browser&) = delete;
  Browser& operator=(const Browser&) = delete;

  bool ok() const { return error_.empty(); }
  const std::string& error() const { return error_; }

  bool Navigate(const std::string& url) {
    Json reply;
    return Call("POST", "/session/" + session_ + "/url", "{\"url\": " + JsonQuote(url) + "}",
                &reply);
  }
  // Runs `script` (a function body: `return …;`) in the page; its result as JSON.
  bool Execute(const std::string& script, Json* value) {
    Json reply;
    if (!Call("POST", "/session/" + session_ + "/execute/sync",
              "{\"script\": " + JsonQuote(script) + ", \"args\": []}", &reply)) {
      return false;
    }
    *value = reply["value"];
    return true;
  }
  // The window as a PNG (base64, as WebDriver gives it).
  bool Screenshot(std::string* png_base64) {
    Json reply;
    if (!Call("GET", "/session/" + session_ + "/screenshot", "", &reply)) return false;
    *png_base64 = reply["value"].text;
    return true;
  }

 private:
  bool Call(const std::string& method, const std::string& path, const std::string& body,
            Json* reply) {
    httplib::Result res = method == "GET" ? client_->Get(path.c_str())
                                          : client_->Post(path.c_str(), body, "application/json");
    if (!res) {
      error_ = method + " " + path + ": no answer from chromedriver";
      return false;
    }
    Json parsed;
    if (res->status != 200 || !JsonParser(res->body).Parse(&parsed)) {
      error_ = method + " " + path + ": " + std::to_string(res->status) + " " + res->body.substr(0, 400);
      return false;
    }
    *reply = std::move(parsed);
    return true;
  }

  int port_ = 0;
  pid_t driver_ = -1;
  std::unique_ptr<httplib::Client> client_;
  std::string session_;
  std::string error_;
};

}  // namespace wallcal::testing_support
