// Replaces global operator new/delete to count heap allocations. Include it
// in exactly one translation unit of a program (a test or a benchmark main).
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdlib>
#include <new>

namespace sabus::test {
inline std::atomic<std::size_t> g_allocations{0};
}

// GCC cannot see that these replacements pair malloc with free.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t n) {
  ++sabus::test::g_allocations;
  if (void* p = std::malloc(n ? n : 1)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop
