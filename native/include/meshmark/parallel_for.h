// meshmark: a static split of an index range over the machine's threads (at most `max_threads`).
#pragma once
#include <algorithm>
#include <cstdint>
#include <thread>
#include <vector>

namespace meshmark {

// Calls body(begin, end) on contiguous chunks of [0, n) from up to min(hardware threads, max_threads)
// threads; runs inline for small n. body must only write to disjoint outputs.
template <class Body>
void parallel_for(std::int64_t n, Body body, std::int64_t min_chunk = 4096, unsigned max_threads = 8) {
  unsigned hw = std::max(1u, std::min(std::thread::hardware_concurrency(), max_threads));
  const std::int64_t chunks = std::max<std::int64_t>(1, std::min<std::int64_t>(hw, n / std::max<std::int64_t>(1, min_chunk)));
  if (chunks <= 1) {
    body(std::int64_t{0}, n);
    return;
  }
  std::vector<std::thread> pool;
  const std::int64_t step = (n + chunks - 1) / chunks;
  for (std::int64_t c = 1; c < chunks; ++c) {
    const std::int64_t b = c * step, e = std::min(n, b + step);
    if (b < e) pool.emplace_back([=, &body] { body(b, e); });
  }
  body(0, std::min(n, step));
  for (auto& t : pool) t.join();
}

}  // namespace meshmark
