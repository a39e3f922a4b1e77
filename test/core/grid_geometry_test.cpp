#include "reflectance_field_map/core/grid_geometry.h"

#include "reflectance_field_map/core/cell_class.h"

#include <gtest/gtest.h>

namespace rfm {
namespace {

TEST(GridGeometry, CellsFloorTowardsNegativeInfinity) {
  const GridGeometry geometry(0.05, 180);
  EXPECT_EQ(geometry.cellOf({0.0, 0.0}), CellIndex(0, 0));
  EXPECT_EQ(geometry.cellOf({0.049, 0.051}), CellIndex(0, 1));
  EXPECT_EQ(geometry.cellOf({-0.001, -0.05}), CellIndex(-1, -1));
  EXPECT_EQ(geometry.cellOf({-0.0501, 1.0}), CellIndex(-2, 20));
  EXPECT_TRUE(geometry.cellCenter({-1, 2}).isApprox(Eigen::Vector2d(-0.025, 0.125)));
}

TEST(GridGeometry, BinsWrapAroundZeroAndTwoPi) {
  const GridGeometry geometry(0.05, 180);  // 2 deg bins
  const double deg = kPi / 180.0;
  EXPECT_EQ(geometry.binOf(0.0), 0);
  EXPECT_EQ(geometry.binOf(1.9 * deg), 0);
  EXPECT_EQ(geometry.binOf(2.1 * deg), 1);
  EXPECT_EQ(geometry.binOf(-0.1 * deg), 179);
  EXPECT_EQ(geometry.binOf(kTwoPi), 0);
  EXPECT_EQ(geometry.binOf(kTwoPi - 1e-12), 179);
  EXPECT_EQ(geometry.binOf(-kTwoPi - 1.0 * deg), 179);
  EXPECT_EQ(geometry.binOf(3 * kTwoPi + 3.0 * deg), 1);
  EXPECT_EQ(geometry.wrapBin(-1), 179);
  EXPECT_EQ(geometry.wrapBin(180), 0);
  EXPECT_NEAR(geometry.binCenter(-1), kTwoPi - 1.0 * deg, 1e-12);
}

TEST(GridGeometry, WrapTwoPiStaysInRange) {
  for (double a = -20.0; a < 20.0; a += 0.001) {
    const double w = wrapTwoPi(a);
    ASSERT_GE(w, 0.0);
    ASSERT_LT(w, kTwoPi);
    ASSERT_NEAR(std::remainder(w - a, kTwoPi), 0.0, 1e-9);
  }
}

TEST(GridGeometry, FloorToIntMatchesStdFloor) {
  for (double v : {0.0, -0.0, 0.5, -0.5, 1.0, -1.0, -1e-300, 1e-300, 2.999999999, -2.000000001,
                   -123456.0, 123456.75, -2147483647.5}) {
    EXPECT_EQ(floorToInt(v), static_cast<int>(std::floor(v))) << v;
  }
  for (double v = -50.0; v < 50.0; v += 0.0625 / 3.0)
    ASSERT_EQ(floorToInt(v), static_cast<int>(std::floor(v))) << v;
}

TEST(GridGeometry, IntegerHelpers) {
  EXPECT_EQ(floorDiv(-1, 16), -1);
  EXPECT_EQ(floorDiv(-16, 16), -1);
  EXPECT_EQ(floorDiv(-17, 16), -2);
  EXPECT_EQ(floorDiv(15, 16), 0);
  EXPECT_EQ(positiveMod(-1, 16), 15);
  EXPECT_EQ(positiveMod(32, 16), 0);
}

// Row-major indices over a box off the origin, x fastest, and back.
TEST(CellBox, IndexOfAndCellAtAreRowMajorInverses) {
  const CellBox box{{-3, 5}, {2, 9}};  // 5 x 4 cells
  EXPECT_EQ(box.indexOf({-3, 5}), 0);
  EXPECT_EQ(box.indexOf({-2, 5}), 1);
  EXPECT_EQ(box.indexOf({-3, 6}), 5);
  EXPECT_EQ(box.indexOf({1, 8}), 19);
  for (int i = 0; i < box.width() * box.height(); ++i) {
    const CellIndex cell = box.cellAt(i);
    EXPECT_TRUE(box.contains(cell)) << i;
    EXPECT_EQ(box.indexOf(cell), i);
  }
}

// A class grid over a box reads unknown outside it.
TEST(CellBox, ClassInBoxIsUnknownOutside) {
  const CellBox box{{-1, -1}, {1, 1}};
  const std::vector<CellClass> classes = {CellClass::kFree, CellClass::kStatic, CellClass::kGlass,
                                          CellClass::kMotion};
  EXPECT_EQ(classInBox(box, classes, {0, -1}), CellClass::kStatic);
  EXPECT_EQ(classInBox(box, classes, {-1, 0}), CellClass::kGlass);
  EXPECT_EQ(classInBox(box, classes, {1, 0}), CellClass::kUnknown);
  EXPECT_EQ(classInBox(box, classes, {0, -2}), CellClass::kUnknown);
}

TEST(Pose2D, ComposeAndTransform) {
  const Pose2D base{{1.0, 2.0}, kPi / 2};
  const Pose2D laser{{0.5, 0.0}, kPi};
  const Pose2D world = base.compose(laser);
  EXPECT_TRUE(world.position.isApprox(Eigen::Vector2d(1.0, 2.5)));
  EXPECT_NEAR(world.yaw, 1.5 * kPi, 1e-12);
  EXPECT_TRUE(base.transform({1.0, 0.0}).isApprox(Eigen::Vector2d(1.0, 3.0)));
}

}  // namespace
}  // namespace rfm
