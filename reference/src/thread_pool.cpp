// ThreadPool (thread_pool.hpp): workers wait for a new generation, spinning
// (a frame opens its regions microseconds apart), then, unless the pool is
// hot (within a step), blocking on the atomic (C++20 wait).
#include "thread_pool.hpp"

#include <chrono>

namespace lockstep {

#if defined(LOCKSTEP_NO_THREADS)
ThreadPool::ThreadPool(int threads) : threads_(threads > 1 ? threads : 1) {}
void ThreadPool::set_hot(bool) {}
ThreadPool::~ThreadPool() = default;
int ThreadPool::workers() const { return 0; }
void ThreadPool::run_erased(int parts, Fn fn, const void* arg) {
  for (int k = 0; k < parts; ++k) fn(arg, k);
}
void ThreadPool::work(int) {}
#else
namespace {
// How long a waiting thread spins before it blocks (a cold pool's worker),
// looks again whether the pool is still hot, or yields (the caller): a frame
// opens its regions microseconds apart within a stage, and a worker that
// blocked costs a wake-up (tens of microseconds on a VM) at the next one.
// spin_pause keeps a spinning worker from taking much from a hyperthread
// sibling that runs the caller's serial work.
constexpr auto kSpin = std::chrono::microseconds(50);
// Spins (with spin_pause) until done() or kSpin has passed; returns done().
template <class Done>
bool spin(const Done& done) {
  const auto until = std::chrono::steady_clock::now() + kSpin;
  for (;;) {
    for (int k = 0; k < 64; ++k) {
      if (done()) return true;
      spin_pause();
    }
    if (std::chrono::steady_clock::now() >= until) return done();
  }
}
}  // namespace

ThreadPool::ThreadPool(int threads) : threads_(threads > 1 ? threads : 1) {
  const unsigned cores = std::thread::hardware_concurrency();  // 0: unknown
  may_spin_ = cores > 0 && static_cast<unsigned>(threads_) <= cores;
  const int workers = threads_ - 1;
  errors_.resize(static_cast<std::size_t>(workers) + 1);
  workers_.reserve(static_cast<std::size_t>(workers));
  for (int w = 0; w < workers; ++w) workers_.emplace_back([this, w] { work(w + 1); });
}

int ThreadPool::workers() const { return static_cast<int>(workers_.size()); }

void ThreadPool::set_hot(bool hot) {
  hot = hot && may_spin_;
  if (hot_.exchange(hot, std::memory_order_relaxed) == hot || !hot) return;
  generation_.fetch_add(1, std::memory_order_release);  // a wake-up with no region: the workers spin from now
  generation_.notify_all();
}

ThreadPool::~ThreadPool() {
  stop_ = true;
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  for (std::thread& t : workers_) t.join();
}

void ThreadPool::run_erased(int parts, Fn fn, const void* arg) {
  fn_ = fn;
  arg_ = arg;
  parts_ = parts;
  for (std::exception_ptr& e : errors_) e = nullptr;
  pending_.store(static_cast<int>(workers_.size()), std::memory_order_relaxed);  // every worker acknowledges every region
  regions_.fetch_add(1, std::memory_order_release);  // publishes fn_, arg_, parts_ and pending_
  generation_.fetch_add(1, std::memory_order_release);
  generation_.notify_all();
  try {
    fn(arg, 0);
  } catch (...) {
    errors_[0] = std::current_exception();
  }
  auto done = [this] { return pending_.load(std::memory_order_acquire) == 0; };
  while (!spin(done)) std::this_thread::yield();
  for (std::exception_ptr& e : errors_)
    if (e) std::rethrow_exception(e);
}

void ThreadPool::work(int index) {
  std::uint32_t seen = 0, seen_regions = 0;
  for (;;) {
    std::uint32_t now = seen;
    // Spin kSpin at a time while the pool is hot, yielding between (a
    // machine busy with other work gets the core: threads_test beside a
    // build took 15 times as long with a worker that only spun), then block.
    while (!spin([&] { return (now = generation_.load(std::memory_order_acquire)) != seen; })) {
      if (hot_.load(std::memory_order_relaxed)) std::this_thread::yield();
      else generation_.wait(seen, std::memory_order_acquire);
    }
    seen = now;
    if (stop_) return;
    const std::uint32_t region = regions_.load(std::memory_order_acquire);
    if (region == seen_regions) continue;  // woken to spin (set_hot), no region yet
    seen_regions = region;  // (one more: the caller starts a region only when every worker has acknowledged the last)
    if (index < parts_) {
      try {
        fn_(arg_, index);
      } catch (...) {
        errors_[static_cast<std::size_t>(index)] = std::current_exception();
      }
    }
    pending_.fetch_sub(1, std::memory_order_acq_rel);  // (a worker without a part too: none lags a region behind)
  }
}

#endif

}  // namespace lockstep
