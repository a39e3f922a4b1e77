#include "reflectance_field_map/core/global_map.h"

#include <gtest/gtest.h>

#include <map>
#include <utility>

namespace rfm {
namespace {

// The global map keeps what it is given on both sides of the origin, tile edges included, and
// knows nothing of cells in tiles it never held, inside its bounds or beyond them.
TEST(GlobalMap2D, GetsWhatWasSetAndUnknownElsewhere) {
  GlobalMap2D map(8);
  const std::map<std::pair<int, int>, CellClass> set = {{{-1, -1}, CellClass::kGlass},
                                                        {{-8, 0}, CellClass::kStatic},
                                                        {{7, 7}, CellClass::kFree},
                                                        {{8, -9}, CellClass::kMotion},
                                                        {{40, 3}, CellClass::kMetal}};
  for (const auto& [cell, value] : set)
    map.set({cell.first, cell.second}, value);
  for (int y = -20; y < 20; ++y) {
    for (int x = -20; x < 60; ++x) {
      const auto it = set.find({x, y});
      const CellClass expected = it == set.end() ? CellClass::kUnknown : it->second;
      ASSERT_EQ(map.get({x, y}), expected) << x << " " << y;
    }
  }
  EXPECT_EQ(map.get({1000, -1000}), CellClass::kUnknown);
  EXPECT_EQ(GlobalMap2D(8).get({0, 0}), CellClass::kUnknown);
}

}  // namespace
}  // namespace rfm
