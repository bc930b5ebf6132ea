// Allocation counting for "no allocation in inner loops" tests. Include from ONE
// source file per test binary: it interposes the binary's malloc/calloc/realloc
// (glibc's __libc_* do the work; operator new and Eigen allocate through malloc) and
// counts calls while counting is on. Not under a sanitizer (it owns malloc) and not
// off glibc: there PLIANT_MALLOC_COUNT stays undefined and count_allocations returns -1.
#pragma once

#include <gtest/gtest.h>

#include <atomic>
#include <cstddef>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define PLIANT_NO_MALLOC_COUNT 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(memory_sanitizer) || __has_feature(thread_sanitizer)
#define PLIANT_NO_MALLOC_COUNT 1
#endif
#endif

#if !defined(PLIANT_NO_MALLOC_COUNT) && defined(__GLIBC__)
#define PLIANT_MALLOC_COUNT 1
namespace pliant::test::malloc_counter {
inline std::atomic<bool> counting{false};
inline std::atomic<long> allocations{0};
}  // namespace pliant::test::malloc_counter

extern "C" {
void* __libc_malloc(std::size_t);
void* __libc_calloc(std::size_t, std::size_t);
void* __libc_realloc(void*, std::size_t);
void* malloc(std::size_t n) {
  if (pliant::test::malloc_counter::counting.load(std::memory_order_relaxed))
    pliant::test::malloc_counter::allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_malloc(n);
}
void* calloc(std::size_t a, std::size_t b) {
  if (pliant::test::malloc_counter::counting.load(std::memory_order_relaxed))
    pliant::test::malloc_counter::allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_calloc(a, b);
}
void* realloc(void* p, std::size_t n) {
  if (pliant::test::malloc_counter::counting.load(std::memory_order_relaxed))
    pliant::test::malloc_counter::allocations.fetch_add(1, std::memory_order_relaxed);
  return __libc_realloc(p, n);
}
}
#endif

namespace pliant::test {

// Allocations made by fn(), or -1 where they cannot be counted. First checks that the
// counter sees a known allocation at all (so a broken hook cannot pass as "zero").
template <class Fn>
long count_allocations(const Fn& fn) {
#ifdef PLIANT_MALLOC_COUNT
  using namespace malloc_counter;
  allocations = 0;
  counting = true;
  auto* probe = new std::vector<double>(100);
  counting = false;
  delete probe;
  EXPECT_GE(allocations.load(), 1) << "the malloc hook does not see allocations";
  allocations = 0;
  counting = true;
  fn();
  counting = false;
  return allocations.exchange(0);
#else
  fn();
  return -1;
#endif
}

}  // namespace pliant::test
