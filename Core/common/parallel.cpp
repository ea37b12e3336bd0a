// The thread pool behind parallel.h: threads block on a condition variable
// between loops and take chunks from an atomic counter during one.
#include "common/parallel.h"

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <mutex>
#include <thread>

#ifdef __linux__
#include <sched.h>
#endif

namespace femorph {
namespace {

thread_local bool t_in_parallel = false;
thread_local int t_worker = 0;

int default_threads() {
  if (const char* env = std::getenv("OMP_NUM_THREADS")) {
    const int n = std::atoi(env);  // "4" or "4,2": the first level
    if (n > 0) return n;
  }
#ifdef __linux__
  cpu_set_t set;
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
#endif
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

/// One loop: its chunks, the counter they are taken from, the threads in it.
struct Job {
  detail::ChunkBody body;
  long num_chunks = 0;
  std::atomic<long> next{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;  // the first exception, under Pool::mutex_
  int participants = 0;      // pool threads inside, under Pool::mutex_
};

class Pool {
 public:
  ~Pool() { resize(0); }

  int threads() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (threads_ <= 0) threads_ = default_threads();
    return threads_;
  }

  void set_threads(int n) {
    std::lock_guard<std::mutex> config(config_mutex_);
    resize(0);
    serial_until_ = {};
    backoff_ = Clock::duration::zero();
    std::lock_guard<std::mutex> lock(mutex_);
    threads_ = n > 0 ? n : default_threads();
  }

  /// False when another thread's loop holds the pool, or while it backs off.
  bool run(long num_chunks, detail::ChunkBody body) {
    std::unique_lock<std::mutex> config(config_mutex_, std::try_to_lock);
    if (!config.owns_lock()) return false;
    const int n = threads();
    if (n <= 1) return false;
    const Clock::time_point start = Clock::now();
    if (start < serial_until_) return false;
    if (static_cast<int>(workers_.size()) != n - 1) resize(n - 1);
    Job job;
    job.body = body;
    job.num_chunks = num_chunks;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      job_ = &job;
      ++generation_;
    }
    wake_.notify_all();
    work(job, 0);
    const Clock::time_point own_done = Clock::now();
    {
      // Late threads no longer join; wait for those inside to finish.
      std::unique_lock<std::mutex> lock(mutex_);
      job_ = nullptr;
      done_.wait(lock, [&] { return job.participants == 0; });
    }
    back_off(start, own_done, Clock::now());
    if (job.error) std::rethrow_exception(job.error);
    return true;
  }

 private:
  using Clock = std::chrono::steady_clock;

  /// A pool thread on a core taken by another process can be descheduled in
  /// the middle of a chunk, and the caller then waits a whole time slice for
  /// it. When the caller waited longer than half its own share of the loop
  /// (and over 0.2 ms), loops run serially for a while, twice as long after
  /// each such loop in a row (1 ms to 0.25 s); a loop without that wait ends
  /// the back-off. So a busy core costs at most a probe per interval.
  void back_off(Clock::time_point start, Clock::time_point own_done, Clock::time_point end) {
    const auto waited = end - own_done, own = own_done - start;
    if (waited > std::chrono::microseconds(200) && waited * 2 > own) {
      backoff_ = std::min<Clock::duration>(std::chrono::milliseconds(250),
                                           backoff_ == Clock::duration::zero() ? std::chrono::milliseconds(1)
                                                                               : 2 * backoff_);
      serial_until_ = end + backoff_;
    } else {
      backoff_ = Clock::duration::zero();
    }
  }

  /// Chunks of `job` until none is left, as thread `worker`.
  void work(Job& job, int worker) {
    const bool was_in = t_in_parallel;
    const int was_worker = t_worker;
    t_in_parallel = true;
    t_worker = worker;
    while (!job.failed.load(std::memory_order_relaxed)) {
      const long c = job.next.fetch_add(1, std::memory_order_relaxed);
      if (c >= job.num_chunks) break;
      try {
        job.body.call(job.body.object, c, worker);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex_);
        if (!job.error) job.error = std::current_exception();
        job.failed = true;
      }
    }
    t_in_parallel = was_in;
    t_worker = was_worker;
  }

  void thread_main(int worker) {
    std::uint64_t seen = 0;
    for (;;) {
      Job* job = nullptr;
      {
        std::unique_lock<std::mutex> lock(mutex_);
        wake_.wait(lock, [&] { return stop_ || (job_ && generation_ != seen); });
        if (stop_) return;
        seen = generation_;
        job = job_;
        ++job->participants;
      }
      work(*job, worker);
      std::lock_guard<std::mutex> lock(mutex_);
      if (--job->participants == 0) done_.notify_all();
    }
  }

  /// Stops the threads and starts `count` new ones (under config_mutex_, or
  /// from the destructor).
  void resize(int count) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      stop_ = true;
    }
    wake_.notify_all();
    for (std::thread& t : workers_) t.join();
    workers_.clear();
    stop_ = false;
    for (int i = 0; i < count; ++i) workers_.emplace_back([this, i] { thread_main(i + 1); });
  }

  std::mutex config_mutex_;  // held by the running loop and by set_threads
  std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::vector<std::thread> workers_;
  Job* job_ = nullptr;
  std::uint64_t generation_ = 0;
  bool stop_ = false;
  int threads_ = 0;
  Clock::time_point serial_until_{};          // under config_mutex_
  Clock::duration backoff_ = Clock::duration::zero();
};

Pool& pool() {
  static Pool p;
  return p;
}

}  // namespace

int parallel_threads() { return pool().threads(); }

void set_parallel_threads(int n) { pool().set_threads(n); }

bool in_parallel() { return t_in_parallel; }

namespace detail {

void run_chunks(long num_chunks, bool parallel, ChunkBody body) {
  if (parallel && !t_in_parallel && pool().run(num_chunks, body)) return;
  const int worker = t_worker;
  for (long c = 0; c < num_chunks; ++c) body.call(body.object, c, worker);
}

}  // namespace detail
}  // namespace femorph
