#include "core/counted.hpp"

#include <algorithm>
#include <sstream>

namespace rb {

std::string OpCounts::str() const {
  std::ostringstream s;
  s << add << "\u00b1 " << mul << "*";
  if (div) s << ' ' << div << "/";
  if (sqrt) s << ' ' << sqrt << "sqrt";
  if (cmp) s << ' ' << cmp << "cmp";
  if (minmax) s << ' ' << minmax << "minmax";
  if (select) s << ' ' << select << "sel";
  if (fma) s << ' ' << fma << "fma";
  return s.str();
}

namespace ops {
namespace {
struct Registry {
  std::mutex m;
  std::vector<ThreadCounters*> live;
  OpCounts retired;
};
Registry& registry() {
  static Registry* r = new Registry;  // never destroyed: threads may exit after static teardown
  return *r;
}
}  // namespace

ThreadCounters::ThreadCounters() {
  auto& r = registry();
  std::lock_guard lk(r.m);
  r.live.push_back(this);
}
ThreadCounters::~ThreadCounters() {
  auto& r = registry();
  std::lock_guard lk(r.m);
  r.retired += snapshot();
  r.live.erase(std::remove(r.live.begin(), r.live.end(), this), r.live.end());
}
OpCounts ThreadCounters::snapshot() const {
  OpCounts o;
  std::uint64_t* f[8] = {&o.add, &o.mul, &o.div, &o.sqrt, &o.cmp, &o.minmax, &o.select, &o.fma};
  for (int k = 0; k < 8; ++k) *f[k] = c[k].load(std::memory_order_relaxed);
  return o;
}
void ThreadCounters::clear() {
  for (auto& x : c) x.store(0, std::memory_order_relaxed);
}

OpCounts current() { return local().snapshot(); }
void reset() { local().clear(); }
OpCounts total() {
  auto& r = registry();
  std::lock_guard lk(r.m);
  OpCounts o = r.retired;
  for (auto* t : r.live) o += t->snapshot();
  return o;
}
void reset_all() {
  auto& r = registry();
  std::lock_guard lk(r.m);
  r.retired = {};
  for (auto* t : r.live) t->clear();
}
}  // namespace ops
}  // namespace rb
