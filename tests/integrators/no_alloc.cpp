// The kernels do not allocate per sample: this executable replaces the global operator new with
// a counting one, and the number of allocations made by one propagation must not depend on the
// window length (100 vs 2000 samples). It is in fact zero for valid input, through the kernels
// and through the plugins (whose operator new resolves to this executable's).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "integrator_cases.h"

namespace {
std::atomic<long> g_allocations{0};

void* CountedAlloc(std::size_t n, std::size_t align) {
  ++g_allocations;
  if (n == 0) n = 1;
  void* p = align > alignof(std::max_align_t)
                ? std::aligned_alloc(align, (n + align - 1) / align * align)
                : std::malloc(n);
  if (!p) throw std::bad_alloc();
  return p;
}
}  // namespace

void* operator new(std::size_t n) { return CountedAlloc(n, 0); }
void* operator new[](std::size_t n) { return CountedAlloc(n, 0); }
void* operator new(std::size_t n, std::align_val_t a) {
  return CountedAlloc(n, static_cast<std::size_t>(a));
}
void* operator new[](std::size_t n, std::align_val_t a) {
  return CountedAlloc(n, static_cast<std::size_t>(a));
}
void* operator new(std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return CountedAlloc(n, 0);
  } catch (...) {
    return nullptr;
  }
}
void* operator new[](std::size_t n, const std::nothrow_t&) noexcept {
  try {
    return CountedAlloc(n, 0);
  } catch (...) {
    return nullptr;
  }
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
void operator delete(void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::align_val_t) noexcept { std::free(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { std::free(p); }

namespace {

using namespace imuconv;
using namespace imuconv::test;

template <typename F>
long AllocationsDuring(F&& f) {
  const long before = g_allocations.load();
  f();
  return g_allocations.load() - before;
}

TEST(IntegratorNoAllocation, CounterWorks) {
  // Guards the test itself: a replaced operator new that is not called would prove nothing.
  static std::vector<int>* volatile sink = nullptr;  // escapes, so new/delete cannot be elided
  const long n = AllocationsDuring([] {
    sink = new std::vector<int>(100);
    delete sink;
  });
  EXPECT_GE(n, 2);
}

TEST(IntegratorNoAllocation, KernelsDoNotAllocatePerSample) {
  const ImuCase c = LoadCase("smooth-0");
  const PropagationInput short_in = MakeInput(c, c.samples[0].t, c.samples[100].t);
  const PropagationInput long_in = MakeInput(c, c.samples[0].t, c.samples[2000].t);
  ASSERT_EQ(short_in.window.size(), 101u);
  ASSERT_EQ(long_in.window.size(), 2001u);
  for (Integrator i : kIntegrators) {
    PropagationResult r;
    bool ok_short = false, ok_long = false;  // checked outside the counted calls
    const long n_short =
        AllocationsDuring([&] { ok_short = PropagateKernel(i, short_in, r).ok(); });
    const long n_long = AllocationsDuring([&] { ok_long = PropagateKernel(i, long_in, r).ok(); });
    EXPECT_TRUE(ok_short && ok_long) << Name(i);
    EXPECT_EQ(n_short, n_long) << Name(i);
    EXPECT_EQ(n_long, 0) << Name(i);
  }
  PropagationResult r;
  bool ok = false;
  EXPECT_EQ(AllocationsDuring([&] { ok = kernels::PropagateRk4(long_in, r, 3).ok(); }),
            0);  // with substeps
  EXPECT_TRUE(ok);
}

TEST(IntegratorNoAllocation, PluginsDoNotAllocatePerSample) {
  const ImuCase c = LoadCase("smooth-0");
  const PropagationInput short_in = MakeInput(c, c.samples[0].t, c.samples[100].t);
  const PropagationInput long_in = MakeInput(c, c.samples[0].t, c.samples[2000].t);
  for (Integrator i : kIntegrators) {
    const auto prop = Plugins().propagator(Name(i));  // loading allocates; the calls below must not
    PropagationResult r;
    bool ok_short = false, ok_long = false;
    const long n_short = AllocationsDuring([&] { ok_short = prop->propagate(short_in, r).ok(); });
    const long n_long = AllocationsDuring([&] { ok_long = prop->propagate(long_in, r).ok(); });
    EXPECT_TRUE(ok_short && ok_long) << Name(i);
    EXPECT_EQ(n_short, n_long) << Name(i);
    EXPECT_EQ(n_long, 0) << Name(i);
  }
}

}  // namespace
