// Counted<T>: a number that tallies the operations performed on it, per thread, by kind.
//
// T is any type num<T> describes (float, double, the SIMD batches). A kernel instantiated with
// Counted<float> reports scalar operation counts (with its early exits); with Counted<f8> it
// reports what one SIMD instance executes, which is the per-lane count (SIMD code cannot exit
// early on a lane it shares with a hit).
//
// What is counted, one each:    + - (binary)            -> add
//                               *                       -> mul
//                               /                       -> div
//                               vsqrt                   -> sqrt
//                               < <= > >= == !=         -> cmp
//                               vmin vmax               -> minmax (vclamp counts 2)
//                               vselect                 -> select
//                               vfma                    -> fma (reports also show it as 1 mul + 1 add)
//                               vsin vcos vacos vatan2 vcbrt -> a separate per-thread tally,
//                                 ops::trans_current() (OpCounts keeps its eight kinds)
// What is free, by convention:  unary minus and vabs, vcopysign (sign-bit operations), vrounded
//                               (a compiler barrier, no instruction), mask
//                               logic (& | ~), loads, stores, broadcasts of constants, conversion,
//                               any_of/all_of/none_of (movemask and a branch).
//
// Counters are thread_local and visible to other threads: counting works inside TBB workers.
// ops::total() sums every thread (including threads that have ended).
#pragma once

#include "core/num.hpp"

#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>
#include <vector>

namespace rb {

struct OpCounts {
  std::uint64_t add = 0, mul = 0, div = 0, sqrt = 0, cmp = 0, minmax = 0, select = 0, fma = 0;
  OpCounts& operator+=(const OpCounts& o) {
    add += o.add; mul += o.mul; div += o.div; sqrt += o.sqrt;
    cmp += o.cmp; minmax += o.minmax; select += o.select; fma += o.fma;
    return *this;
  }
  OpCounts operator-(const OpCounts& o) const {
    OpCounts r;
    r.add = add - o.add; r.mul = mul - o.mul; r.div = div - o.div; r.sqrt = sqrt - o.sqrt;
    r.cmp = cmp - o.cmp; r.minmax = minmax - o.minmax; r.select = select - o.select; r.fma = fma - o.fma;
    return r;
  }
  bool operator==(const OpCounts&) const = default;
  // Arithmetic total with each FMA as one mul plus one add.
  std::uint64_t flops() const { return add + mul + div + sqrt + 2 * fma; }
  std::uint64_t total() const { return add + mul + div + sqrt + cmp + minmax + select + fma; }
  std::string str() const;
};

namespace ops {

// One thread's counters. Only the owning thread writes; the relaxed atomics make reads from
// other threads (ops::total) well defined without a locked instruction per operation.
struct ThreadCounters {
  std::atomic<std::uint64_t> c[8] = {};
  ThreadCounters();
  ~ThreadCounters();
  RB_INLINE void bump(int k, std::uint64_t n = 1) {
    c[k].store(c[k].load(std::memory_order_relaxed) + n, std::memory_order_relaxed);
  }
  OpCounts snapshot() const;
  void clear();
};

enum Kind : int { kAdd = 0, kMul, kDiv, kSqrt, kCmp, kMinMax, kSelect, kFma };

inline ThreadCounters& local() {
  thread_local ThreadCounters t;
  return t;
}

OpCounts current();   // this thread
void reset();         // this thread
OpCounts total();     // every thread, live and ended
void reset_all();     // every thread

// Transcendental calls (vsin, vcos, vacos, vatan2, vcbrt) on Counted numbers, this thread.
inline std::uint64_t& trans_local() {
  thread_local std::uint64_t n = 0;
  return n;
}
inline std::uint64_t trans_current() { return trans_local(); }

// RAII measurement on this thread: counts since construction.
struct Scope {
  OpCounts start = current();
  OpCounts elapsed() const { return current() - start; }
};

}  // namespace ops

template <class T>
struct Counted {
  T v{};
  using base = num<T>;
  Counted() = default;
  RB_INLINE explicit Counted(const T& x) : v(x) {}
  template <class S>
    requires(std::is_arithmetic_v<S> && !std::is_same_v<S, T>)
  RB_INLINE explicit Counted(S s) : v(T(static_cast<typename base::scalar>(s))) {}

  friend RB_INLINE Counted operator+(const Counted& a, const Counted& b) { ops::local().bump(ops::kAdd); return Counted(a.v + b.v); }
  friend RB_INLINE Counted operator-(const Counted& a, const Counted& b) { ops::local().bump(ops::kAdd); return Counted(a.v - b.v); }
  friend RB_INLINE Counted operator*(const Counted& a, const Counted& b) { ops::local().bump(ops::kMul); return Counted(a.v * b.v); }
  friend RB_INLINE Counted operator/(const Counted& a, const Counted& b) { ops::local().bump(ops::kDiv); return Counted(a.v / b.v); }
  friend RB_INLINE Counted operator-(const Counted& a) { return Counted(-a.v); }
  RB_INLINE Counted& operator+=(const Counted& b) { return *this = *this + b; }
  RB_INLINE Counted& operator-=(const Counted& b) { return *this = *this - b; }
  RB_INLINE Counted& operator*=(const Counted& b) { return *this = *this * b; }
  RB_INLINE Counted& operator/=(const Counted& b) { return *this = *this / b; }

  using M = typename base::mask;
  friend RB_INLINE M operator<(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v < b.v; }
  friend RB_INLINE M operator<=(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v <= b.v; }
  friend RB_INLINE M operator>(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v > b.v; }
  friend RB_INLINE M operator>=(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v >= b.v; }
  friend RB_INLINE M operator==(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v == b.v; }
  friend RB_INLINE M operator!=(const Counted& a, const Counted& b) { ops::local().bump(ops::kCmp); return a.v != b.v; }
};

template <class T>
struct num<Counted<T>> {
  using type = Counted<T>;
  using base = num<T>;
  using scalar = typename base::scalar;
  using mask = typename base::mask;
  static constexpr int lanes = base::lanes;
  static constexpr const char* name = base::name;
  static RB_INLINE type min(const type& a, const type& b) { ops::local().bump(ops::kMinMax); return type(base::min(a.v, b.v)); }
  static RB_INLINE type max(const type& a, const type& b) { ops::local().bump(ops::kMinMax); return type(base::max(a.v, b.v)); }
  static RB_INLINE type select(const mask& m, const type& a, const type& b) { ops::local().bump(ops::kSelect); return type(base::select(m, a.v, b.v)); }
  static RB_INLINE type sqrt(const type& a) { ops::local().bump(ops::kSqrt); return type(base::sqrt(a.v)); }
  static RB_INLINE type abs(const type& a) { return type(base::abs(a.v)); }
  static RB_INLINE type fma(const type& a, const type& b, const type& c) { ops::local().bump(ops::kFma); return type(base::fma(a.v, b.v, c.v)); }
  static RB_INLINE type copysign(const type& a, const type& b) { return type(base::copysign(a.v, b.v)); }
  static RB_INLINE type rounded(const type& a) { return type(base::rounded(a.v)); }
  static RB_INLINE type sin(const type& a) { ++ops::trans_local(); return type(base::sin(a.v)); }
  static RB_INLINE type cos(const type& a) { ++ops::trans_local(); return type(base::cos(a.v)); }
  static RB_INLINE type acos(const type& a) { ++ops::trans_local(); return type(base::acos(a.v)); }
  static RB_INLINE type atan2(const type& a, const type& b) { ++ops::trans_local(); return type(base::atan2(a.v, b.v)); }
  static RB_INLINE type cbrt(const type& a) { ++ops::trans_local(); return type(base::cbrt(a.v)); }
  static RB_INLINE bool any(const mask& m) { return base::any(m); }
  static RB_INLINE bool all(const mask& m) { return base::all(m); }
  static RB_INLINE mask mnot(const mask& m) { return base::mnot(m); }
  static RB_INLINE mask mconst(bool b) { return base::mconst(b); }
  static RB_INLINE bool lane_mask(const mask& m, int i) { return base::lane_mask(m, i); }
  static RB_INLINE int count(const mask& m) { return base::count(m); }
  static RB_INLINE scalar lane(const type& v, int i) { return base::lane(v.v, i); }
  template <class S> static RB_INLINE type load(const S* p) { return type(base::load(p)); }
  template <class S> static RB_INLINE void store(S* p, const type& v) { base::store(p, v.v); }
};

using cfloat = Counted<float>;
using cdouble = Counted<double>;
using cf8 = Counted<f8>;
using cd4 = Counted<d4>;

}  // namespace rb
