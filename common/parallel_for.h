// SPDX-License-Identifier: Apache-2.0
#pragma once
// Runs fn(0) .. fn(n - 1) over up to `threads` threads (the calling thread is one of them).
// Each index runs exactly once; the callers write their results into slot i, so the outcome
// does not depend on the thread count or the scheduling. fn must not throw.

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

namespace wallcal {

template <typename Fn>
void ParallelFor(int n, int threads, const Fn& fn) {
  const int workers = std::max(1, std::min(threads, n));
  if (workers <= 1) {
    for (int i = 0; i < n; ++i) fn(i);
    return;
  }
  std::atomic<int> next{0};
  auto work = [&]() {
    for (int i = next.fetch_add(1); i < n; i = next.fetch_add(1)) fn(i);
  };
  std::vector<std::thread> pool;
  pool.reserve(static_cast<size_t>(workers - 1));
  for (int t = 1; t < workers; ++t) pool.emplace_back(work);
  work();
  for (std::thread& thread : pool) thread.join();
}

}  // namespace wallcal
