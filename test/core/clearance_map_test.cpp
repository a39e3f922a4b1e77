#include "reflectance_field_map/core/clearance_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <random>
#include <stdexcept>

namespace rfm {
namespace {

// The promise a leap relies on: at(c) = d means every cell within Chebyshev distance d - 1 of c
// is empty. Checked against brute force on random maps, for single cells (exact), the online
// blocks of 4 and the largest blocks, and the bound is not uselessly loose.
TEST(ClearanceMap, EveryCellWithinTheClearanceIsEmpty) {
  const CellBox box{{-37, 12}, {61, 95}};
  std::mt19937 rng(7);
  for (int trial = 0; trial < 15; ++trial) {
    const int shift = trial % 3 * 2;
    std::vector<CellIndex> occupied;
    const int count = 1 + trial * 7;
    std::uniform_int_distribution<int> x(box.min.x(), box.max.x() - 1);
    std::uniform_int_distribution<int> y(box.min.y(), box.max.y() - 1);
    for (int i = 0; i < count; ++i)
      occupied.emplace_back(x(rng), y(rng));
    auto nearest = [&](const CellIndex& c) {
      int best = 1 << 20;
      for (const CellIndex& o : occupied)
        best = std::min(best, std::max(std::abs(o.x() - c.x()), std::abs(o.y() - c.y())));
      return best;
    };
    ClearanceMap map(shift);
    ASSERT_EQ(map.blockCells(), 1 << shift);
    map.compute(box, [&](int dx, int dy) {
      const CellIndex cell = box.min + CellIndex(dx, dy);
      return std::find(occupied.begin(), occupied.end(), cell) == occupied.end();
    });
    for (int cy = box.min.y(); cy < box.max.y(); ++cy) {
      for (int cx = box.min.x(); cx < box.max.x(); ++cx) {
        const int truth = nearest({cx, cy});  // the exact clearance
        const int bound = map.at({cx, cy});
        ASSERT_LE(bound, truth) << cx << "," << cy;
        if (shift == 0) {
          ASSERT_EQ(bound, std::min(truth, 255)) << cx << "," << cy;
        } else {
          // Blocks cost at most two blocks of slack.
          ASSERT_GE(bound, std::min(truth, 255) - 2 * map.blockCells()) << cx << "," << cy;
        }
      }
    }
  }
}

TEST(ClearanceMap, NoLeapOutsideTheBoxOrBeforeComputing) {
  EXPECT_THROW(ClearanceMap(-1), std::invalid_argument);
  EXPECT_THROW(ClearanceMap(5), std::invalid_argument);
  ClearanceMap map;
  EXPECT_EQ(map.blockCells(), 4);
  EXPECT_EQ(map.at({0, 0}), 0);
  const CellBox box{{0, 0}, {40, 40}};
  map.compute(box, [](int, int) { return true; });
  EXPECT_GT(map.at({20, 20}), 8);
  EXPECT_EQ(map.at({40, 20}), 0);
  EXPECT_EQ(map.at({-1, 0}), 0);
  // A box off the origin: cells on either side of it, on both axes.
  map.compute({{-30, -10}, {10, 30}}, [](int, int) { return true; });
  EXPECT_GT(map.at({-10, 10}), 8);
  EXPECT_EQ(map.at({-31, 10}), 0);
  EXPECT_EQ(map.at({10, 10}), 0);
  EXPECT_EQ(map.at({-10, -11}), 0);
  EXPECT_EQ(map.at({-10, 30}), 0);
  map.clear();
  EXPECT_EQ(map.at({20, 20}), 0);
}

}  // namespace
}  // namespace rfm
