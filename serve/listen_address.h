// SPDX-License-Identifier: Apache-2.0
#pragma once
// Where the guide's page is served and who may read it: `--serve [ADDR:]PORT` parsed, whether
// an address is this machine's loopback (the page needs no token there), the access token
// required everywhere else, and the URLs to print.

#include <string>
#include <vector>

namespace wallcal::serve {

struct ListenAddress {
  std::string host = "127.0.0.1";  // a numeric IPv4 or IPv6 address, or "localhost"
  int port = 0;                    // 1..65535; 0: any free port
};

// Why `--serve` text is not an address (typed; ParseListenAddress's message says it).
enum class AddressError { kNone, kEmpty, kBadPort, kBadHost };

// "8080", "127.0.0.1:8080", "0.0.0.0:8080", "[::1]:8080", "localhost:8080" (PORT 0: any free
// port). *message says what is wrong for people when the result is not kNone.
AddressError ParseListenAddress(const std::string& text, ListenAddress* address,
                                std::string* message);

// True for 127.0.0.0/8, ::1, ::ffff:127.x.y.z and "localhost": only this machine can connect.
bool IsLoopbackHost(const std::string& host);

// 128 random bits from the system's entropy (std::random_device, /dev/urandom on Linux), as 32
// lower-case hex digits.
std::string NewAccessToken();

// Compares a request's token with the expected one in a time that does not depend on where they
// differ. False when either is empty.
bool TokensEqual(const std::string& given, const std::string& expected);

// The hosts a browser can reach the page at: `host` itself, or for a wildcard address (0.0.0.0,
// ::) each address of this machine's interfaces that are up, loopback last.
std::vector<std::string> ReachableHosts(const std::string& host);

// "http://HOST:PORT/" with "?token=TOKEN" when the token is not empty; an IPv6 host in brackets.
std::string PageUrl(const std::string& host, int port, const std::string& token);

}  // namespace wallcal::serve
