// The threads that trace: a TBB arena of a given size, and parallel loops over it whose every task
// runs with flush-to-zero and denormals-are-zero (core/fpenv.hpp), as Embree's threads do: each
// task sets them when it starts (one MXCSR write), so no worker runs a task without them whatever
// arena it came from. The calling thread gets the same while the scope lives and its previous
// state back afterwards. The renderer, `raybench trace` and the accuracy lab's traces all run their
// work through it.
//
// The thread count is real: TBB's default would give an arena of 64 slots only as many workers as
// the machine has hardware threads, so a scope of more threads than that also raises TBB's allowed
// parallelism to `threads` while it lives (tbb::global_control). `--threads 64` on a 2-core machine
// runs 64 threads, oversubscribed. A scope of fewer threads needs no such limit (its arena has that
// many slots, the calling thread in one of them), so scopes of different sizes can live together
// and time their loops in the same rounds: one and two threads alternating, say (while several
// raised limits live, the smallest applies).
#pragma once

#include "core/fpenv.hpp"
#include "core/par.hpp"

#include <tbb/blocked_range.h>
#include <tbb/global_control.h>
#include <tbb/info.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cstddef>
#include <optional>

namespace rb::tracer {

class ThreadScope {
 public:
  explicit ThreadScope(int threads)
      : threads_(std::max(1, threads)), arena_(threads_) {
    if (threads_ > tbb::info::default_concurrency()) limit_.emplace(tbb::global_control::max_allowed_parallelism, std::size_t(threads_));
#if RB_TSAN
    saved_concurrency_ = par::concurrency();
    par::concurrency() = threads_;
#endif
  }
  ~ThreadScope() {
#if RB_TSAN
    par::concurrency() = saved_concurrency_;
#endif
  }
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;
  int threads() const { return threads_; }
  // f() inside the arena, on the calling thread (which may then help with f's parallel loops).
  template <class Fn>
  void run(Fn&& f) {
#if RB_TSAN
    set_ftz_daz();  // the tsan preset's std::thread backend (core/par.hpp): no arena, this scope's threads
    const int outer = par::concurrency();
    par::concurrency() = threads_;
    f();
    par::concurrency() = outer;
#else
    arena_.execute([&] {
      set_ftz_daz();
      f();
    });
#endif
  }
  // f(i) for i in [0, n), `grain` at a time per task, in the arena; every task sets FTZ/DAZ first.
  template <class Fn>
  void parallel_for(std::size_t n, std::size_t grain, Fn&& f) {
    run([&] {
      par::for_range(0, n, grain, [&](std::size_t b, std::size_t e) {
        set_ftz_daz();
        for (std::size_t i = b; i != e; ++i) f(i);
      });
    });
  }

 private:
  int threads_;
  std::optional<tbb::global_control> limit_;  // only above the machine's hardware threads
  tbb::task_arena arena_;
  FtzScope ftz_;  // FTZ and DAZ on the calling thread while the scope lives, its MXCSR restored after
#if RB_TSAN
  int saved_concurrency_ = 2;
#endif
};

}  // namespace rb::tracer
