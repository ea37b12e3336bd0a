// A step run with a given thread count, for the tests that check that
// results do not depend on it.
#pragma once

#include "common/parallel.h"

#include <omp.h>

#include <utility>

namespace femorph {
namespace testing {

/// fn() with `threads` threads (the pool of common/parallel.h, and OpenMP for
/// the loops still on it); the previous counts are restored.
template <class Fn>
decltype(auto) with_threads(int threads, Fn&& fn) {
  struct Restore {
    int pool, omp;
    ~Restore() {
      set_parallel_threads(pool);
      omp_set_num_threads(omp);
    }
  } restore{parallel_threads(), omp_get_max_threads()};
  set_parallel_threads(threads);
  omp_set_num_threads(threads);
  return std::forward<Fn>(fn)();
}

}  // namespace testing
}  // namespace femorph
