// The thread pool of common/parallel.h: every index once, results in chunk
// order, nested and concurrent loops, exceptions, one thread, the back-off
// from a held-up loop, and no CPU spent while idle.
#include "common/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <ctime>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

namespace femorph {
namespace {

/// Runs the test body with `n` threads, restoring the default after.
struct Threads {
  explicit Threads(int n) { set_parallel_threads(n); }
  ~Threads() { set_parallel_threads(0); }
};

TEST(Parallel, EveryIndexExactlyOnce) {
  for (const int threads : {1, 2, 3, 8}) {
    Threads t(threads);
    EXPECT_EQ(parallel_threads(), threads);
    for (const long n : {0L, 1L, 7L, 9999L, 100000L}) {
      for (const long chunk : {0L, 1L, 13L, 4096L}) {
        std::vector<std::atomic<int>> hits(static_cast<std::size_t>(n));
        parallel_for(
            n, [&](long i) { hits[static_cast<std::size_t>(i)].fetch_add(1); }, 0, chunk);
        for (long i = 0; i < n; ++i) ASSERT_EQ(hits[static_cast<std::size_t>(i)].load(), 1) << threads << " " << n;
      }
    }
  }
}

TEST(Parallel, ChunksAreContiguousAndWorkersInRange) {
  Threads t(4);
  const long n = 100003, chunk = 1000;
  std::vector<int> worker_of(static_cast<std::size_t>(n), -1);
  parallel_for_chunks(
      n,
      [&](long begin, long end, int worker) {
        EXPECT_EQ(begin % chunk, 0);
        EXPECT_EQ(end, std::min(n, begin + chunk));
        EXPECT_GE(worker, 0);
        EXPECT_LT(worker, 4);
        for (long i = begin; i < end; ++i) worker_of[static_cast<std::size_t>(i)] = worker;
      },
      0, chunk);
  for (const int w : worker_of) EXPECT_GE(w, 0);
}

TEST(Parallel, ReduceCombinesInChunkOrder) {
  const long n = 250000;
  std::vector<long> expected(static_cast<std::size_t>(n));
  std::iota(expected.begin(), expected.end(), 0L);
  // A floating sum is order-dependent: with a fixed chunk size it must be
  // the same for every thread count.
  double sum_one = 0;
  for (const int threads : {1, 2, 3, 5}) {
    Threads t(threads);
    const std::vector<long> joined = parallel_reduce(
        n, std::vector<long>(),
        [](long begin, long end, int) {
          std::vector<long> part;
          for (long i = begin; i < end; ++i) part.push_back(i);
          return part;
        },
        append<long>, 0);
    EXPECT_EQ(joined, expected) << threads;
    const double sum = parallel_reduce(
        n, 0.0,
        [](long begin, long end, int) {
          double s = 0;
          for (long i = begin; i < end; ++i) s += 1.0 / (1.0 + static_cast<double>(i));
          return s;
        },
        [](double a, double b) { return a + b; }, 0, 777);
    if (threads == 1) sum_one = sum;
    EXPECT_EQ(sum, sum_one) << threads;
  }
}

TEST(Parallel, NestedLoopsRunSeriallyOnTheCallingThread) {
  Threads t(3);
  const long outer = 64, inner = 50000;
  std::vector<long> sums(static_cast<std::size_t>(outer), 0);
  std::atomic<int> wrong_worker{0}, not_in_parallel{0};
  parallel_for_worker(
      outer,
      [&](long i, int worker) {
        if (!in_parallel()) ++not_in_parallel;
        const std::thread::id me = std::this_thread::get_id();
        parallel_for_worker(
            inner,
            [&](long j, int inner_worker) {
              if (inner_worker != worker || std::this_thread::get_id() != me) ++wrong_worker;
              sums[static_cast<std::size_t>(i)] += j;
            },
            0);
      },
      0, 1);
  EXPECT_EQ(wrong_worker.load(), 0);
  EXPECT_EQ(not_in_parallel.load(), 0);
  for (const long s : sums) EXPECT_EQ(s, inner * (inner - 1) / 2);
  EXPECT_FALSE(in_parallel());
}

TEST(Parallel, ExceptionIsRethrownOnTheCaller) {
  Threads t(2);
  for (int repeat = 0; repeat < 20; ++repeat) {
    std::atomic<long> ran{0};
    EXPECT_THROW(parallel_for(
                     100000,
                     [&](long i) {
                       ++ran;
                       if (i == 5000) throw std::runtime_error("item 5000");
                     },
                     0, 100),
                 std::runtime_error);
    EXPECT_LT(ran.load(), 100000);  // the chunks not yet started are skipped
  }
  // The pool still works.
  std::atomic<long> count{0};
  parallel_for(
      100000, [&](long) { ++count; }, 0);
  EXPECT_EQ(count.load(), 100000);
  EXPECT_FALSE(in_parallel());
}

TEST(Parallel, OneThreadAndSmallLoopsRunOnTheCaller) {
  const std::thread::id me = std::this_thread::get_id();
  std::atomic<int> elsewhere{0}, flagged{0};
  const auto check = [&](long, int worker) {
    if (worker != 0 || std::this_thread::get_id() != me) ++elsewhere;
    if (in_parallel()) ++flagged;
  };
  {
    Threads t(1);
    EXPECT_EQ(parallel_threads(), 1);
    parallel_for_worker(100000, check, 0);
  }
  {
    Threads t(4);
    parallel_for_worker(999, check, 1000);  // below min_items
    parallel_for_worker(5000, check, parallel_when(false));
  }
  EXPECT_EQ(elsewhere.load(), 0);
  EXPECT_EQ(flagged.load(), 0);
}

TEST(Parallel, LoopsFromSeveralThreadsAtOnce) {
  Threads t(2);
  std::vector<long> totals(4, 0);
  std::vector<std::thread> callers;
  for (int c = 0; c < 4; ++c)
    callers.emplace_back([&, c] {
      for (int repeat = 0; repeat < 50; ++repeat)
        totals[static_cast<std::size_t>(c)] += parallel_reduce(
            20000, 0L,
            [](long begin, long end, int) {
              long s = 0;
              for (long i = begin; i < end; ++i) s += i;
              return s;
            },
            [](long a, long b) { return a + b; }, 0);
    });
  for (std::thread& c : callers) c.join();
  for (const long s : totals) EXPECT_EQ(s, 50L * (20000L * 19999L / 2));
}

// A pool thread that holds the caller up (as one descheduled by a busy core
// would) makes the next loops run on the caller alone for a while.
TEST(Parallel, ALoopHeldUpByAPoolThreadBacksOffToSerial) {
  Threads t(2);
  bool held_up = false;
  for (int attempt = 0; attempt < 50 && !held_up; ++attempt) {
    std::atomic<bool> other{false};
    parallel_for_worker(
        8,
        [&](long, int worker) {
          if (worker != 0) other = true;
          std::this_thread::sleep_for(std::chrono::microseconds(worker != 0 ? 20000 : 500));
        },
        0, 1);
    held_up = other;
  }
  ASSERT_TRUE(held_up) << "no pool thread took a chunk in 50 loops";
  std::atomic<int> elsewhere{0};
  parallel_for_worker(
      8,
      [&](long, int worker) {
        elsewhere += worker != 0;
        std::this_thread::sleep_for(std::chrono::microseconds(100));  // time for a pool thread to join
      },
      0, 1);
  EXPECT_EQ(elsewhere.load(), 0) << "the loop after a held-up one ran on the pool";
}

TEST(Parallel, IdleThreadsUseNoCpu) {
  Threads t(4);
  std::atomic<long> count{0};
  parallel_for(
      1000000, [&](long) { ++count; }, 0);  // starts the pool
  const std::clock_t before = std::clock();
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  const double cpu = static_cast<double>(std::clock() - before) / CLOCKS_PER_SEC;
  EXPECT_LT(cpu, 0.05) << "the pool's threads spent CPU time while idle";
}

}  // namespace
}  // namespace femorph
