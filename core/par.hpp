// The engine's parallel primitives, one place for both backends:
//   for_range(begin, end, grain, f)          f(b, e) over chunks of [begin, end)
//   reduce(begin, end, grain, init, body, join)  body(b, e, acc) -> acc per chunk, join(a, b) -> a
//   invoke(a, b)                             a() and b() side by side
//
// Normally these are oneTBB's parallel_for, parallel_reduce and task_group. In the `tsan` preset
// (RB_TSAN) they run on std::threads instead: Debian's libtbb.so is not instrumented, so
// ThreadSanitizer cannot see the happens-before edges of its task spawning, stealing and joining
// (measured: about 100 reports per run of the threaded tests on TBB, every one between a task's
// creation and its execution on another thread). On std::threads every edge is visible, so a
// report is a race in our code. What TSan then does not check is TBB's scheduler itself. The
// chunks are those of TBB's blocked ranges; the engine's reductions are exact (box minima and
// maxima, counts), so results do not depend on the backend. The thread count is that of the
// innermost tracer::ThreadScope (`concurrency()`), so `--threads 64` runs 64 threads there too.
#pragma once

#include <algorithm>
#include <cstddef>
#include <utility>

#if RB_TSAN
#include <atomic>
#include <thread>
#include <vector>
#else
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>
#include <tbb/task_group.h>
#endif

namespace rb::par {

#if RB_TSAN
// Threads of the innermost ThreadScope on this thread (set by tracer::ThreadScope); 2 outside one.
inline int& concurrency() {
  thread_local int n = 2;
  return n;
}

template <class F>
void for_range(std::size_t begin, std::size_t end, std::size_t grain, F&& f) {
  if (end <= begin) return;
  grain = std::max<std::size_t>(1, grain);
  const std::size_t chunks = (end - begin + grain - 1) / grain;
  const int threads = int(std::min<std::size_t>(chunks, std::size_t(std::max(1, concurrency()))));
  std::atomic<std::size_t> next{0};
  const int inherit = concurrency();
  auto work = [&] {
    concurrency() = inherit;
    for (std::size_t c; (c = next.fetch_add(1)) < chunks;) {
      const std::size_t b = begin + c * grain;
      f(b, std::min(end, b + grain));
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(work);
  work();
  for (auto& t : pool) t.join();
}

template <class T, class Body, class Join>
T reduce(std::size_t begin, std::size_t end, std::size_t grain, T init, Body&& body, Join&& join) {
  if (end <= begin) return init;
  grain = std::max<std::size_t>(1, grain);
  const std::size_t chunks = (end - begin + grain - 1) / grain;
  std::vector<T> part(chunks, init);
  for_range(0, chunks, 1, [&](std::size_t c0, std::size_t c1) {
    for (std::size_t c = c0; c < c1; ++c) {
      const std::size_t b = begin + c * grain;
      part[c] = body(b, std::min(end, b + grain), part[c]);
    }
  });
  T acc = init;
  for (std::size_t c = 0; c < chunks; ++c) acc = join(acc, part[c]);
  return acc;
}

template <class A, class B>
void invoke(A&& a, B&& b) {
  const int inherit = concurrency();
  std::thread t([&] {
    concurrency() = inherit;
    a();
  });
  b();
  t.join();
}
#else
template <class F>
void for_range(std::size_t begin, std::size_t end, std::size_t grain, F&& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(begin, end, std::max<std::size_t>(1, grain)),
                    [&](const tbb::blocked_range<std::size_t>& r) { f(r.begin(), r.end()); });
}

template <class T, class Body, class Join>
T reduce(std::size_t begin, std::size_t end, std::size_t grain, T init, Body&& body, Join&& join) {
  return tbb::parallel_reduce(
      tbb::blocked_range<std::size_t>(begin, end, std::max<std::size_t>(1, grain)), init,
      [&](const tbb::blocked_range<std::size_t>& r, T acc) { return body(r.begin(), r.end(), acc); }, join);
}

template <class A, class B>
void invoke(A&& a, B&& b) {
  tbb::task_group g;
  g.run(std::forward<A>(a));
  b();
  g.wait();
}
#endif

}  // namespace rb::par
