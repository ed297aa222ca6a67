// World<T>'s workers (docs/SPEC.md 7.7 "Threads"): a fixed set of
// threads that run the parts of one parallel region. The parts a region is
// cut into, and what each part does, are decided by the caller from the
// work alone (never from timing), so a result does not depend on which
// thread ran which part, nor on how many threads there are.
#pragma once
#include <atomic>
#include <cstdint>
#include <exception>
#include <vector>

// Targets without threads (WASI; Emscripten without -pthread; a libstdc++
// without std::thread, as mingw-w64's win32 thread model before GCC 13): the
// pool has no workers and runs every part on the caller's thread (the same
// bits).
#if defined(__wasi__) || (defined(__EMSCRIPTEN__) && !defined(__EMSCRIPTEN_PTHREADS__)) || \
    (defined(__GLIBCXX__) && !defined(_GLIBCXX_HAS_GTHREADS))
#define LOCKSTEP_NO_THREADS 1
#else
#include <thread>
#endif

namespace lockstep {

// A spin loop's pause: lets the sibling hyperthread run (the pool's waits and
// the solver's chains, solve_schedule.hpp).
inline void spin_pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#elif defined(__aarch64__) || defined(__arm__)
  asm volatile("yield");
#endif
}

class ThreadPool {
 public:
  // `threads` >= 1 threads in all: the caller and threads - 1 workers.
  explicit ThreadPool(int threads);
  ~ThreadPool();
  ThreadPool(const ThreadPool&) = delete;
  ThreadPool& operator=(const ThreadPool&) = delete;
  int size() const { return threads_; }

  // While hot (World<T>::step: a frame's regions are tens to hundreds of
  // microseconds apart, with serial work between them), an idle worker spins
  // until the next region instead of blocking after a short spin: a blocked
  // worker costs a wake-up of tens of microseconds on a VM at every region
  // that follows serial work (pile1000 on 2 threads: 0.25 ms of a 7 ms
  // frame). Cold (between steps), it blocks, and burns no core while the
  // game runs. A pool of more threads than the machine has cores never
  // spins on (its spinning workers would take the cores from those with
  // work: threads_test's 8 threads on 2 cores ran 15x slower). Timing only:
  // never a result.
  // Turning hot wakes the blocked workers at once (not at the step's first
  // region).
  void set_hot(bool hot);
  // Whether the pool has no more threads than the machine has cores (its
  // waits may spin).
  bool may_spin() const { return may_spin_; }

  // Runs part(k) for k in [0, parts), parts <= size(): part 0 on the calling
  // thread, part k on worker k - 1; returns when every part has returned.
  // An exception thrown by a part is caught and rethrown here (the lowest
  // part's when several throw).
  template <class Part>
  void run(int parts, const Part& part) {
    if (parts <= 1 || workers() == 0) {
      for (int k = 0; k < parts; ++k) part(k);
      return;
    }
    run_erased(parts, [](const void* p, int k) { (*static_cast<const Part*>(p))(k); }, &part);
  }

 private:
  using Fn = void (*)(const void*, int);
  void run_erased(int parts, Fn fn, const void* arg);
  void work(int index);
  int workers() const;

  int threads_ = 1;
#if !defined(LOCKSTEP_NO_THREADS)
  std::vector<std::thread> workers_;
#endif
  std::vector<std::exception_ptr> errors_;  // per part
  Fn fn_ = nullptr;
  const void* arg_ = nullptr;
  int parts_ = 0;
  std::atomic<std::uint32_t> generation_{0};  // bumped to wake the workers: a region, turning hot, stopping
  std::atomic<std::uint32_t> regions_{0};     // bumped to start a region (publishes fn_, arg_, parts_)
  std::atomic<int> pending_{0};               // workers that have not finished this region
  bool stop_ = false;
  std::atomic<bool> hot_{false};
  bool may_spin_ = false;  // threads_ <= the machine's cores
};

}  // namespace lockstep
