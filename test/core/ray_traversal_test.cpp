#include "reflectance_field_map/core/ray_traversal.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <vector>

namespace rfm {
namespace {

// Reference: every cell whose square the segment crosses with positive length, ordered by
// where the segment enters it.
std::vector<CellIndex> bruteForceCells(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                       double resolution) {
  const Eigen::Vector2d p = a / resolution, q = b / resolution;
  const Eigen::Vector2d d = q - p;
  std::vector<std::pair<double, CellIndex>> hits;
  for (int y = static_cast<int>(std::floor(std::min(p.y(), q.y()))) - 1;
       y <= static_cast<int>(std::floor(std::max(p.y(), q.y()))) + 1; ++y) {
    for (int x = static_cast<int>(std::floor(std::min(p.x(), q.x()))) - 1;
         x <= static_cast<int>(std::floor(std::max(p.x(), q.x()))) + 1; ++x) {
      double t0 = 0.0, t1 = 1.0;
      bool inside = true;
      const double low[2] = {static_cast<double>(x), static_cast<double>(y)};
      for (int axis = 0; axis < 2 && inside; ++axis) {
        if (d[axis] == 0.0) {
          inside = p[axis] >= low[axis] && p[axis] < low[axis] + 1;
          continue;
        }
        double e0 = (low[axis] - p[axis]) / d[axis], e1 = (low[axis] + 1 - p[axis]) / d[axis];
        if (e0 > e1) std::swap(e0, e1);
        t0 = std::max(t0, e0);
        t1 = std::min(t1, e1);
      }
      if (inside && t1 - t0 > 1e-9) hits.push_back({t0, CellIndex(x, y)});
    }
  }
  std::sort(hits.begin(), hits.end(),
            [](const auto& l, const auto& r) { return l.first < r.first; });
  std::vector<CellIndex> cells;
  for (const auto& hit : hits)
    cells.push_back(hit.second);
  return cells;
}

std::vector<CellIndex> traversedCells(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                                      double resolution) {
  std::vector<CellIndex> cells;
  forEachCellOnRay(a, b, 1.0 / resolution, [&](const CellIndex& c) { cells.push_back(c); });
  return cells;
}

TEST(GridRayTraversal, MatchesBruteForceOnRandomRays) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> coordinate(-12.0, 12.0);
  const double resolution = 0.05;
  for (int trial = 0; trial < 3000; ++trial) {
    const Eigen::Vector2d a(coordinate(rng), coordinate(rng));
    const Eigen::Vector2d b(coordinate(rng), coordinate(rng));
    const std::vector<CellIndex> expected = bruteForceCells(a, b, resolution);
    const std::vector<CellIndex> actual = traversedCells(a, b, resolution);
    ASSERT_EQ(actual.size(), expected.size()) << "trial " << trial;
    for (size_t i = 0; i < actual.size(); ++i) {
      ASSERT_EQ(actual[i], expected[i]) << "trial " << trial << " cell " << i;
    }
    ASSERT_EQ(actual.front(),
              CellIndex(std::floor(a.x() / resolution), std::floor(a.y() / resolution)));
    ASSERT_EQ(actual.back(),
              CellIndex(std::floor(b.x() / resolution), std::floor(b.y() / resolution)));
  }
}

TEST(GridRayTraversal, ConsecutiveCellsAreFourNeighbours) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-30.0, 30.0);
  for (int trial = 0; trial < 500; ++trial) {
    const std::vector<CellIndex> cells = traversedCells({coordinate(rng), coordinate(rng)},
                                                        {coordinate(rng), coordinate(rng)}, 0.05);
    for (size_t i = 1; i < cells.size(); ++i) {
      ASSERT_EQ((cells[i] - cells[i - 1]).cwiseAbs().sum(), 1);
    }
  }
}

TEST(GridRayTraversal, AxisAlignedAndDegenerateRays) {
  EXPECT_EQ(traversedCells({0.01, 0.01}, {0.01, 0.01}, 0.05).size(), 1u);
  const std::vector<CellIndex> horizontal = traversedCells({0.01, 0.02}, {0.26, 0.02}, 0.05);
  ASSERT_EQ(horizontal.size(), 6u);
  for (int i = 0; i < 6; ++i)
    EXPECT_EQ(horizontal[i], CellIndex(i, 0));
  const std::vector<CellIndex> down = traversedCells({0.02, 0.01}, {0.02, -0.11}, 0.05);
  ASSERT_EQ(down.size(), 4u);
  EXPECT_EQ(down.back(), CellIndex(0, -3));
}

TEST(GridRayTraversal, EndsExactlyOnTheEndCellDespiteDrift) {
  // Long, nearly diagonal rays accumulate floating-point error in t; the walk must still stop
  // on the end cell after exactly |dx| + |dy| steps.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(-1e-9, 1e-9);
  for (int trial = 0; trial < 200; ++trial) {
    const Eigen::Vector2d a(0.025 + jitter(rng), 0.025 + jitter(rng));
    const Eigen::Vector2d b(a.x() + 29.0 + jitter(rng), a.y() + 29.0 + jitter(rng));
    GridRayTraversal traversal(a, b, 20.0);
    const CellIndex end(static_cast<int>(std::floor(b.x() * 20.0)),
                        static_cast<int>(std::floor(b.y() * 20.0)));
    const int steps = traversal.remaining();
    EXPECT_EQ(steps, (end - traversal.cell()).cwiseAbs().sum());
    while (!traversal.atEnd())
      traversal.next();
    EXPECT_EQ(traversal.cell(), end);
  }
}

}  // namespace
}  // namespace rfm
