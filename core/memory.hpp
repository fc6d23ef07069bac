// Storage for large arrays (the BVH build's working arrays, the 8-wide nodes, primitive batches and
// their scene indices, ray sets).
//
// A fresh allocation costs a page fault per 4 KiB page when it is first written (kernel page
// faults were a fifth of the samples of a `raybench trace` run on the 202k-triangle dragon). Blocks
// of 2 MiB and more are therefore aligned to 2 MiB and marked with madvise(MADV_HUGEPAGE), so that
// a kernel with transparent huge pages in `madvise` mode (Debian's default) backs them with 2 MiB
// pages: one fault per 2 MiB. The traversal gains too: a random ray's nodes and leaves lie megabytes
// apart, and on 4 KiB pages nearly each of them is a TLB miss (on a virtual machine, a walk of two
// page tables). Elsewhere the advice is ignored and nothing changes. The
// environment variable RAYBENCH_NO_HUGE_PAGES (any value) turns the advice off, to measure what it
// buys.
//
// BigAllocator<T, Align> is a standard allocator: vectors with it behave as any std::vector
// (value-initialised by resize). uninit_array<T> is storage for trivially copyable T that is
// never initialised, for arrays written once by index (the builder's node pool).
#pragma once

#include <cstddef>
#include <cstdlib>
#include <memory>
#include <new>
#include <type_traits>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rb {

inline constexpr std::size_t kHugePage = std::size_t(2) << 20;

inline bool huge_pages_wanted() {
  static const bool wanted = std::getenv("RAYBENCH_NO_HUGE_PAGES") == nullptr;
  return wanted;
}

// Raw storage of `bytes` bytes aligned to `align` (a power of two); huge-page advice from 2 MiB.
// Throws std::bad_alloc (also for a size that rounding up would overflow).
inline void* big_alloc(std::size_t bytes, std::size_t align) {
  if (bytes == 0) bytes = 1;
  if (bytes > std::size_t(-1) - kHugePage) throw std::bad_alloc();
  void* p = nullptr;
  if (bytes >= kHugePage && huge_pages_wanted()) {
    const std::size_t size = (bytes + kHugePage - 1) / kHugePage * kHugePage;
    p = std::aligned_alloc(kHugePage, size);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    madvise(p, size, MADV_HUGEPAGE);  // advice only: a kernel without THP leaves 4 KiB pages
#endif
    return p;
  }
  align = align < alignof(std::max_align_t) ? alignof(std::max_align_t) : align;
  p = std::aligned_alloc(align, (bytes + align - 1) / align * align);
  if (!p) throw std::bad_alloc();
  return p;
}
inline void big_free(void* p) { std::free(p); }

template <class T, std::size_t Align = alignof(T)>
struct BigAllocator {
  using value_type = T;
  template <class U>
  struct rebind {
    using other = BigAllocator<U, Align>;
  };
  BigAllocator() noexcept = default;
  template <class U>
  BigAllocator(const BigAllocator<U, Align>&) noexcept {}
  T* allocate(std::size_t n) {
    if (n > std::size_t(-1) / sizeof(T)) throw std::bad_array_new_length();
    return static_cast<T*>(big_alloc(n * sizeof(T), Align > alignof(T) ? Align : alignof(T)));
  }
  void deallocate(T* p, std::size_t) noexcept { big_free(p); }
  template <class U>
  bool operator==(const BigAllocator<U, Align>&) const noexcept { return true; }
};

template <class T>
using big_vector = std::vector<T, BigAllocator<T>>;

// A BigAllocator whose vectors default-initialise instead of value-initialising: resize() of a
// trivially constructible T leaves the new elements unwritten, so a vector can be sized to an
// upper bound, filled by index (in parallel) and shrunk, touching only the pages it fills.
template <class T>
struct DefaultInitAllocator : BigAllocator<T> {
  template <class U>
  struct rebind {
    using other = DefaultInitAllocator<U>;
  };
  DefaultInitAllocator() noexcept = default;
  template <class U>
  DefaultInitAllocator(const DefaultInitAllocator<U>&) noexcept {}
  template <class U, class... Args>
  void construct(U* p, Args&&... args) {
    if constexpr (sizeof...(Args) == 0) ::new (static_cast<void*>(p)) U;
    else ::new (static_cast<void*>(p)) U(std::forward<Args>(args)...);
  }
};

// `n` uninitialised elements of a trivially copyable T (aligned to Align), for arrays whose every
// used element is written before it is read.
template <class T, std::size_t Align = alignof(T)>
class uninit_array {
  static_assert(std::is_trivially_copyable_v<T> && std::is_trivially_destructible_v<T>);
  struct Free {
    void operator()(T* p) const noexcept { big_free(p); }
  };
  std::unique_ptr<T[], Free> p_;

 public:
  uninit_array() = default;
  explicit uninit_array(std::size_t n) : p_(BigAllocator<T, Align>().allocate(n)) {}
  T& operator[](std::size_t i) { return p_[i]; }
  T* data() { return p_.get(); }
  const T* data() const { return p_.get(); }
};

}  // namespace rb
