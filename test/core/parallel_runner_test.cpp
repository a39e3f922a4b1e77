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

}  // namespace
}  // namespace rfm
