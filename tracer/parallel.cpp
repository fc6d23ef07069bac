#include "tracer/parallel.hpp"

#include "core/fpenv.hpp"

#include <tbb/task_arena.h>
#include <tbb/task_scheduler_observer.h>

#include <algorithm>

namespace rb::tracer {

namespace {
struct FtzObserver : tbb::task_scheduler_observer {
  explicit FtzObserver(tbb::task_arena& a) : tbb::task_scheduler_observer(a) { observe(true); }
  ~FtzObserver() override { observe(false); }
  void on_scheduler_entry(bool) override { set_ftz_daz(); }
};
}  // namespace

struct ThreadScope::Impl {
  tbb::task_arena arena;
  std::unique_ptr<FtzObserver> obs;
  explicit Impl(int threads) : arena(threads) {
    arena.initialize();
    obs = std::make_unique<FtzObserver>(arena);
  }
};

ThreadScope::ThreadScope(int threads) : threads_(std::max(1, threads)) {
  impl_ = std::make_unique<Impl>(threads_);
  saved_csr_ = _mm_getcsr();
  set_ftz_daz();
}
ThreadScope::~ThreadScope() {
  impl_.reset();
  _mm_setcsr(saved_csr_);
}
void ThreadScope::run_fn(const std::function<void()>& f) {
  impl_->arena.execute([&] {
    set_ftz_daz();
    f();
  });
}

}  // namespace rb::tracer
