#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace rfm {

// Runs the parts of one job at a time: part 0 on the calling thread, the others on helper
// threads that live as long as the runner, so handing work over costs a wake-up, not a thread
// start. The core uses it where the work splits into parts that write disjoint memory (theta
// slices of the field, per-scan labels).
class ParallelRunner {
 public:
  // `threads` >= 1, the caller included.
  explicit ParallelRunner(int threads);
  ~ParallelRunner();
  ParallelRunner(const ParallelRunner&) = delete;
  ParallelRunner& operator=(const ParallelRunner&) = delete;

  int threads() const { return static_cast<int>(helpers_.size()) + 1; }

  // Waking a sleeping thread costs tens of microseconds on a VM, as much as a scan's share of
  // work: helpers spin this long for the next job before they sleep, and the caller spins for
  // the helpers to finish (their parts are about as long as its own). A helper spins only while
  // jobs follow each other within this time (the batch's scans); a live mapper's scans come
  // milliseconds apart, and spinning after each would only burn the core.
  static constexpr std::chrono::microseconds kSpinTime{200};

  // Calls part(i) for every i in [0, threads()) and returns when all have finished. The first
  // exception thrown by any part is rethrown here. One job at a time: not reentrant (a part
  // must not call run), and not for several callers at once.
  void run(const std::function<void(int)>& part);

 private:
  void helperLoop(int index);

  std::mutex mutex_;  // guards sleeping and waking, and error_
  std::condition_variable wake_;
  std::condition_variable done_;
  const std::function<void(int)>* job_ = nullptr;  // published by generation_
  std::atomic<unsigned> generation_{0};  // bumped per job, so each helper runs each job once
  std::atomic<int> pending_{0};          // helpers still running the current job
  bool stopping_ = false;                // set under mutex_, published by generation_
  std::exception_ptr error_;
  std::vector<std::thread> helpers_;
};

// Calls body(i, thread) for every i in [0, count) on the runner's threads (thread in
// [0, threads())), handing out `grain` indices at a time as threads become free, so unequal
// items balance out. A null runner, or too little work to share, runs on the caller alone
// (thread 0).
void parallelFor(ParallelRunner* runner, size_t count, size_t grain,
                 const std::function<void(size_t, int)>& body);

}  // namespace rfm
