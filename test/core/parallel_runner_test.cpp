#include "reflectance_field_map/core/parallel_runner.h"

#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <thread>
#include <vector>

namespace rfm {
namespace {

TEST(ParallelRunner, RunsEveryPartOnceOnDistinctThreadsPerJob) {
  ParallelRunner runner(3);
  ASSERT_EQ(runner.threads(), 3);
  for (int job = 0; job < 200; ++job) {
    std::vector<int> runs(3, 0);
    std::vector<std::thread::id> ids(3);
    runner.run([&](int part) {
      ++runs[part];
      ids[part] = std::this_thread::get_id();
    });
    EXPECT_EQ(runs, std::vector<int>({1, 1, 1})) << job;
    EXPECT_EQ(ids[0], std::this_thread::get_id());  // part 0 is the caller's
    EXPECT_NE(ids[1], ids[0]);
    EXPECT_NE(ids[2], ids[1]);
  }
}

TEST(ParallelRunner, ReturnsOnlyWhenAllPartsAreDone) {
  ParallelRunner runner(2);
  std::atomic<int> finished{0};
  for (int job = 0; job < 50; ++job) {
    runner.run([&](int part) {
      if (part == 1) std::this_thread::yield();  // the helper may lag behind the caller
      finished.fetch_add(1);
    });
    EXPECT_EQ(finished.load(), 2 * (job + 1));
  }
}

TEST(ParallelRunner, RethrowsAHelpersExceptionAndStaysUsable) {
  ParallelRunner runner(2);
  EXPECT_THROW(runner.run([](int part) {
    if (part == 1) throw std::runtime_error("helper failed");
  }),
               std::runtime_error);
  int sum = 0;
  std::atomic<int> parts{0};
  runner.run([&](int part) {
    parts.fetch_add(1);
    if (part == 0) sum = 1;
  });
  EXPECT_EQ(parts.load(), 2);
  EXPECT_EQ(sum, 1);
}

TEST(ParallelRunner, OneThreadRunsOnTheCaller) {
  ParallelRunner runner(1);
  std::thread::id id;
  runner.run([&](int part) {
    EXPECT_EQ(part, 0);
    id = std::this_thread::get_id();
  });
  EXPECT_EQ(id, std::this_thread::get_id());
}

// Every index exactly once, whatever the grain, on valid threads; a null runner is the caller.
TEST(ParallelFor, VisitsEveryIndexOnceOnValidThreads) {
  ParallelRunner runner(2);
  for (size_t grain : {1u, 3u, 64u, 1000u}) {
    std::vector<std::atomic<int>> visits(257);
    std::atomic<int> bad_thread{0};
    parallelFor(&runner, visits.size(), grain, [&](size_t i, int thread) {
      visits[i].fetch_add(1);
      if (thread < 0 || thread >= runner.threads()) bad_thread.fetch_add(1);
    });
    for (size_t i = 0; i < visits.size(); ++i)
      EXPECT_EQ(visits[i].load(), 1) << "grain " << grain << " index " << i;
    EXPECT_EQ(bad_thread.load(), 0);
  }
  std::vector<std::thread::id> ids;
  parallelFor(nullptr, 3, 1, [&](size_t, int thread) {
    EXPECT_EQ(thread, 0);
    ids.push_back(std::this_thread::get_id());
  });
  EXPECT_EQ(ids, std::vector<std::thread::id>(3, std::this_thread::get_id()));
}

}  // namespace
}  // namespace rfm
