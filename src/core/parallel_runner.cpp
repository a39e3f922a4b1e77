#include "reflectance_field_map/core/parallel_runner.h"

#include <algorithm>
#include <chrono>

namespace rfm {
namespace {

inline void cpuRelax() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#endif
}

}  // namespace

ParallelRunner::ParallelRunner(int threads) {
  for (int i = 1; i < threads; ++i)
    helpers_.emplace_back([this, i] { helperLoop(i); });
}

ParallelRunner::~ParallelRunner() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  for (std::thread& helper : helpers_)
    helper.join();
}

void ParallelRunner::run(const std::function<void(int)>& part) {
  if (helpers_.empty()) {
    part(0);
    return;
  }
  job_ = &part;
  error_ = nullptr;
  pending_.store(static_cast<int>(helpers_.size()), std::memory_order_relaxed);
  {
    // Under the lock, so a helper between its last check and its sleep cannot miss the wake-up.
    std::lock_guard<std::mutex> lock(mutex_);
    generation_.fetch_add(1, std::memory_order_release);
  }
  wake_.notify_all();
  std::exception_ptr own_error;
  try {
    part(0);
  } catch (...) {
    own_error = std::current_exception();
  }
  const auto spin_until = std::chrono::steady_clock::now() + kSpinTime;
  for (unsigned spins = 1; pending_.load(std::memory_order_acquire) != 0; ++spins) {
    // Reading the clock costs more than a pause: look at it every few hundred spins.
    if (spins % 256 != 0 || std::chrono::steady_clock::now() < spin_until) {
      cpuRelax();
      continue;
    }
    std::unique_lock<std::mutex> lock(mutex_);
    done_.wait(lock, [this] { return pending_.load(std::memory_order_acquire) == 0; });
  }
  job_ = nullptr;
  if (own_error) std::rethrow_exception(own_error);
  if (error_) std::rethrow_exception(error_);
}

void ParallelRunner::helperLoop(int index) {
  unsigned seen = 0;
  bool back_to_back = true;  // the last job came within kSpinTime of the one before
  while (true) {
    const auto idle_since = std::chrono::steady_clock::now();
    const auto spin_until = idle_since + kSpinTime;
    for (unsigned spins = 1; back_to_back && generation_.load(std::memory_order_acquire) == seen;
         ++spins) {
      if (spins % 256 == 0 && std::chrono::steady_clock::now() >= spin_until) break;
      cpuRelax();
    }
    if (generation_.load(std::memory_order_acquire) == seen) {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [&] { return generation_.load(std::memory_order_acquire) != seen; });
    }
    back_to_back = std::chrono::steady_clock::now() < spin_until;
    seen = generation_.load(std::memory_order_acquire);
    if (stopping_) return;
    try {
      (*job_)(index);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!error_) error_ = std::current_exception();
    }
    if (pending_.fetch_sub(1, std::memory_order_acq_rel) == 1) {
      std::lock_guard<std::mutex> lock(mutex_);  // pairs with the caller's check before sleeping
      done_.notify_one();
    }
  }
}

void parallelFor(ParallelRunner* runner, size_t count, size_t grain,
                 const std::function<void(size_t, int)>& body) {
  grain = std::max<size_t>(grain, 1);
  if (!runner || runner->threads() == 1 || count <= grain) {
    for (size_t i = 0; i < count; ++i)
      body(i, 0);
    return;
  }
  std::atomic<size_t> next{0};
  runner->run([&](int thread) {
    for (size_t first = next.fetch_add(grain, std::memory_order_relaxed); first < count;
         first = next.fetch_add(grain, std::memory_order_relaxed)) {
      for (size_t i = first; i < std::min(count, first + grain); ++i)
        body(i, thread);
    }
  });
}

}  // namespace rfm
