// The threads that trace: a TBB arena of a given size whose every worker runs with flush-to-zero and
// denormals-are-zero (core/fpenv.hpp), as Embree's threads do, set when a worker enters the arena;
// the calling thread gets the same while the scope lives and its previous state back afterwards.
// The renderer, `raybench trace` and the accuracy lab's traces all run their work through it.
#pragma once

#include <functional>
#include <memory>

namespace rb::tracer {

class ThreadScope {
 public:
  explicit ThreadScope(int threads);  // threads < 1: one
  ~ThreadScope();
  ThreadScope(const ThreadScope&) = delete;
  ThreadScope& operator=(const ThreadScope&) = delete;
  int threads() const { return threads_; }
  template <class Fn>
  void run(Fn&& f) { run_fn(std::function<void()>(std::forward<Fn>(f))); }  // f inside the arena

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  int threads_ = 1;
  unsigned saved_csr_ = 0;
  void run_fn(const std::function<void()>& f);
};

}  // namespace rb::tracer
