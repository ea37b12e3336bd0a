// A step run with a given OpenMP thread count, for the tests that check that
// results do not depend on it.
#pragma once

#include <omp.h>

#include <utility>

namespace femorph {
namespace testing {

/// fn() with `threads` OpenMP threads; the previous count is restored.
template <class Fn>
decltype(auto) with_threads(int threads, Fn&& fn) {
  struct Restore {
    int threads;
    ~Restore() { omp_set_num_threads(threads); }
  } restore{omp_get_max_threads()};
  omp_set_num_threads(threads);
  return std::forward<Fn>(fn)();
}

}  // namespace testing
}  // namespace femorph
