// SPDX-License-Identifier: Apache-2.0
#pragma once
// What one client may cost the page's server, and how the connections ended.

#include <cstddef>
#include <cstdint>

namespace wallcal::serve {

struct ServeLimits {
  int max_connections = 32;           // open at once; more are answered 503 and closed at once
  size_t max_head_bytes = 8192;       // the request line and headers; more: 431, closed
  double head_timeout_s = 5.0;        // from acceptance to the end of the request's head
  double answer_timeout_s = 10.0;     // to write the answer, then to see the client close
  size_t max_answer_bytes = 8 << 20;  // an answer longer than this is not sent (500)
  int send_buffer_bytes = 262144;     // the kernel's send buffer per connection (SO_SNDBUF)
};

// How many connections ended which way (for the tests and for people).
struct ServeCounts {
  int64_t adopted = 0;        // taken in (a slot free)
  int64_t refused_busy = 0;   // more than max_connections open: 503
  int64_t head_too_long = 0;  // 431
  int64_t timed_out = 0;      // head or answer not done before its deadline
  int64_t answered = 0;       // the whole answer written
};

}  // namespace wallcal::serve
