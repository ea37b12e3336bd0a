// Parallel loops on a pool of threads that sleep when idle (no busy-waiting),
// so that a loop never hurts on a machine whose cores are busy elsewhere.
//
// A loop over [0, n) is cut into chunks; the calling thread and the pool's
// threads take chunks from an atomic counter, so a thread on a loaded core
// simply takes fewer. The caller starts on its chunks at once and waits
// (blocked, not spinning) only for the chunks other threads have taken.
// When that wait shows a pool thread was held up (its core taken by another
// process), the next loops run on the caller alone for a while (back-off).
// Results are made deterministic by the callers: per-item outputs, or
// per-chunk results combined in chunk order (parallel_reduce).
//
// Nested loops (a loop started inside another's body) and loops started while
// another thread's loop holds the pool run serially on the calling thread.
// An exception thrown by a body stops the remaining chunks from starting;
// the first one caught is rethrown on the calling thread once every thread
// has left the loop.
#pragma once

#include "common/types.h"

#include <algorithm>
#include <limits>
#include <utility>
#include <vector>

namespace femorph {

/// Threads a parallel loop may use (>= 1): set_parallel_threads(), else the
/// first number of OMP_NUM_THREADS, else the processors this process may
/// run on.
int parallel_threads();

/// Sets the thread count of later loops; n <= 0 restores the default. Waits
/// for a loop another thread runs; not to be called from a loop's body.
void set_parallel_threads(int n);

/// True on a thread running a chunk of a parallel loop (not in a loop run
/// serially because it was too small or one thread is set).
bool in_parallel();

namespace detail {

/// A non-owning reference to a callable void(long chunk, int worker).
struct ChunkBody {
  void* object;
  void (*call)(void* object, long chunk, int worker);
};

/// Runs body for chunks 0 .. num_chunks - 1 on the pool (worker ids
/// 0 .. parallel_threads() - 1, 0 being the caller), or serially when
/// `parallel` is false, one thread is set or the pool is taken.
void run_chunks(long num_chunks, bool parallel, ChunkBody body);

/// Chunk size for n items when the caller gives none.
inline long auto_chunk(long n) { return std::max(1L, n / (8L * parallel_threads())); }

}  // namespace detail

/// body(begin, end, worker) over the chunks [begin, end) of [0, n), each of
/// `chunk` items (<= 0: automatic); worker in [0, parallel_threads()) names
/// the thread, for per-thread scratch. Serial (worker 0, or the enclosing
/// loop's worker when nested) when n < min_items.
template <class Body>
void parallel_for_chunks(long n, Body&& body, long min_items = kParallelMinItems, long chunk = 0) {
  if (n <= 0) return;
  if (chunk <= 0) chunk = detail::auto_chunk(n);
  const long num_chunks = (n + chunk - 1) / chunk;
  auto run = [&](long c, int worker) { body(c * chunk, std::min(n, (c + 1) * chunk), worker); };
  using Run = decltype(run);
  detail::run_chunks(num_chunks, n >= min_items && num_chunks > 1,
                     {&run, [](void* o, long c, int w) { (*static_cast<Run*>(o))(c, w); }});
}

/// The min_items of a loop that runs in parallel exactly when `parallel`.
inline long parallel_when(bool parallel) { return parallel ? 0 : std::numeric_limits<long>::max(); }

/// Adds v to x atomically (relaxed: the loop's end orders it before the
/// caller's next read) and returns x's old value: for counters shared by a
/// loop's threads, e.g. the fill positions of a bucket sort.
template <class T>
T fetch_add(T& x, T v) {
  return __atomic_fetch_add(&x, v, __ATOMIC_RELAXED);
}

/// a followed by b: the combine of parallel_reduce for lists made per chunk.
template <class T>
std::vector<T> append(std::vector<T> a, std::vector<T> b) {
  if (a.empty()) return b;
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

/// f(i) for every i in [0, n), in parallel when n >= min_items.
template <class F>
void parallel_for(long n, F&& f, long min_items = kParallelMinItems, long chunk = 0) {
  parallel_for_chunks(
      n,
      [&](long begin, long end, int) {
        for (long i = begin; i < end; ++i) f(i);
      },
      min_items, chunk);
}

/// f(i, worker) for every i in [0, n): parallel_for with the thread's id.
template <class F>
void parallel_for_worker(long n, F&& f, long min_items = kParallelMinItems, long chunk = 0) {
  parallel_for_chunks(
      n,
      [&](long begin, long end, int worker) {
        for (long i = begin; i < end; ++i) f(i, worker);
      },
      min_items, chunk);
}

/// The chunk results body(begin, end, worker) -> T of [0, n), folded in
/// chunk order: combine(...combine(combine(init, r0), r1)..., rk). The chunk
/// boundaries depend on the thread count unless `chunk` is given, so
/// combine must be associative (sums of integers, min, max, concatenation)
/// for the result not to depend on it.
template <class T, class Body, class Combine>
T parallel_reduce(long n, T init, Body&& body, Combine&& combine, long min_items = kParallelMinItems, long chunk = 0) {
  if (n <= 0) return init;
  if (n < min_items || chunk <= 0) chunk = n < min_items ? n : detail::auto_chunk(n);  // serial: one chunk
  const long num_chunks = (n + chunk - 1) / chunk;
  std::vector<T> partial(static_cast<std::size_t>(num_chunks));
  parallel_for_chunks(
      n,
      [&](long begin, long end, int worker) {
        partial[static_cast<std::size_t>(begin / chunk)] = body(begin, end, worker);
      },
      min_items, chunk);
  for (T& p : partial) init = combine(std::move(init), std::move(p));
  return init;
}

}  // namespace femorph
