// A step run with a given thread count, for the tests that check that
// results do not depend on it.
#pragma once

#include "common/parallel.h"

#include <utility>

namespace femorph {
namespace testing {

/// fn() with `threads` threads (common/parallel.h); the previous count is
/// restored.
template <class Fn>
decltype(auto) with_threads(int threads, Fn&& fn) {
  struct Restore {
    int threads;
    ~Restore() { set_parallel_threads(threads); }
  } restore{parallel_threads()};
  set_parallel_threads(threads);
  return std::forward<Fn>(fn)();
}

}  // namespace testing
}  // namespace femorph
