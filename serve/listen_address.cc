// SPDX-License-Identifier: Apache-2.0
#include "serve/listen_address.h"

#include <arpa/inet.h>
#include <ifaddrs.h>
#include <net/if.h>
#include <netinet/in.h>

#include <cstdint>
#include <cstdlib>
#include <random>

namespace wallcal::serve {
namespace {

bool IsIpv4(const std::string& host, in_addr* address) {
  return inet_pton(AF_INET, host.c_str(), address) == 1;
}

bool IsIpv6(const std::string& host, in6_addr* address) {
  return inet_pton(AF_INET6, host.c_str(), address) == 1;
}

}  // namespace

AddressError ParseListenAddress(const std::string& text, ListenAddress* address,
                                std::string* message) {
  if (text.empty()) {
    *message = "an empty address; expected [ADDR:]PORT (8080, 0.0.0.0:8080, [::1]:8080)";
    return AddressError::kEmpty;
  }
  ListenAddress parsed;
  std::string port_text = text;
  if (text.front() == '[') {
    const size_t close = text.find("]:");
    if (close == std::string::npos) {
      *message = "'" + text + "': an IPv6 address is written [ADDR]:PORT";
      return AddressError::kBadHost;
    }
    parsed.host = text.substr(1, close - 1);
    port_text = text.substr(close + 2);
  } else if (const size_t colon = text.rfind(':'); colon != std::string::npos) {
    parsed.host = text.substr(0, colon);
    port_text = text.substr(colon + 1);
    if (parsed.host.find(':') != std::string::npos) {
      *message = "'" + text + "': an IPv6 address is written [ADDR]:PORT";
      return AddressError::kBadHost;
    }
  }
  char* end = nullptr;
  const long port = std::strtol(port_text.c_str(), &end, 10);
  if (port_text.empty() || port_text.size() > 5 || *end != '\0' || port < 0 || port > 65535 ||
      port_text.find_first_not_of("0123456789") != std::string::npos) {
    *message = "'" + text + "': the port is not a number from 0 to 65535";
    return AddressError::kBadPort;
  }
  parsed.port = static_cast<int>(port);
  in_addr v4;
  in6_addr v6;
  if (parsed.host != "localhost" && !IsIpv4(parsed.host, &v4) && !IsIpv6(parsed.host, &v6)) {
    *message = "'" + text + "': '" + parsed.host +
               "' is not a numeric IPv4 or IPv6 address (or localhost)";
    return AddressError::kBadHost;
  }
  *address = parsed;
  message->clear();
  return AddressError::kNone;
}

bool IsLoopbackHost(const std::string& host) {
  if (host == "localhost") return true;
  in_addr v4;
  if (IsIpv4(host, &v4)) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6;
  if (IsIpv6(host, &v6)) {
    if (IN6_IS_ADDR_LOOPBACK(&v6)) return true;
    return IN6_IS_ADDR_V4MAPPED(&v6) && v6.s6_addr[12] == 127;
  }
  return false;
}

std::string NewAccessToken() {
  std::random_device entropy;  // libstdc++ on Linux: getrandom() or /dev/urandom
  static const char kHex[] = "0123456789abcdef";
  std::string token;
  for (int word = 0; word < 4; ++word) {
    uint32_t bits = entropy();
    for (int nibble = 0; nibble < 8; ++nibble) {
      token += kHex[bits & 0xf];
      bits >>= 4;
    }
  }
  return token;
}

bool TokensEqual(const std::string& given, const std::string& expected) {
  if (given.empty() || expected.empty()) return false;
  unsigned difference = given.size() == expected.size() ? 0u : 1u;
  for (size_t i = 0; i < expected.size(); ++i) {
    const char g = i < given.size() ? given[i] : '\0';
    difference |= static_cast<unsigned char>(g ^ expected[i]);
  }
  return difference == 0;
}

std::vector<std::string> ReachableHosts(const std::string& host) {
  if (host != "0.0.0.0" && host != "::") return {host};
  std::vector<std::string> hosts, loopback;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) == 0) {
    for (const ifaddrs* i = list; i != nullptr; i = i->ifa_next) {
      if (i->ifa_addr == nullptr || (i->ifa_flags & IFF_UP) == 0) continue;
      const int family = i->ifa_addr->sa_family;
      if (family != AF_INET && !(family == AF_INET6 && host == "::")) continue;
      char text[INET6_ADDRSTRLEN] = {};
      const void* bytes =
          family == AF_INET
              ? static_cast<const void*>(&reinterpret_cast<const sockaddr_in*>(i->ifa_addr)->sin_addr)
              : static_cast<const void*>(&reinterpret_cast<const sockaddr_in6*>(i->ifa_addr)->sin6_addr);
      if (inet_ntop(family, bytes, text, sizeof(text)) == nullptr) continue;
      const std::string name = text;
      if (family == AF_INET6 && name.rfind("fe80:", 0) == 0) continue;  // needs a zone id
      (IsLoopbackHost(name) ? loopback : hosts).push_back(name);
    }
    freeifaddrs(list);
  }
  hosts.insert(hosts.end(), loopback.begin(), loopback.end());
  if (hosts.empty()) hosts.push_back(host == "::" ? "::1" : "127.0.0.1");
  return hosts;
}

std::string PageUrl(const std::string& host, int port, const std::string& token) {
  const std::string shown = host.find(':') != std::string::npos ? "[" + host + "]" : host;
  return "http://" + shown + ":" + std::to_string(port) + "/" +
         (token.empty() ? "" : "?token=" + token);
}

}  // namespace wallcal::serve
