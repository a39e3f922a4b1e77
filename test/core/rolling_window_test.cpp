#include "reflectance_field_map/core/rolling_window.h"

#include "reflectance_field_map/core/reflectance_field.h"  // activeWindowTiles

#include <gtest/gtest.h>

#include <cmath>

namespace rfm {
namespace {

constexpr double kResolution = 0.05;

TEST(RollingWindow, WindowTilesKeepTheRadiusInside) {
  EXPECT_EQ(activeWindowTiles(10.0, 0.05, 16), 27);
  EXPECT_EQ(activeWindowTiles(0.8, 0.05, 16), 3);
  EXPECT_EQ(activeWindowTiles(0.81, 0.05, 16), 5);
  const RollingWindow window(16, 27);
  for (const Eigen::Vector2d& robot :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.79, 0.79), Eigen::Vector2d(-13.3, 7.7)}) {
    RollingWindow moved = window;
    const CellIndex cell(std::floor(robot.x() / kResolution), std::floor(robot.y() / kResolution));
    moved.setOrigin(moved.originCentredOn(cell));
    const CellBox box = moved.box();
    EXPECT_GE(robot.x() - box.min.x() * kResolution, 10.0);
    EXPECT_GE(box.max.x() * kResolution - robot.x(), 10.0);
    EXPECT_GE(robot.y() - box.min.y() * kResolution, 10.0);
    EXPECT_GE(box.max.y() * kResolution - robot.y(), 10.0);
  }
}

// Over the box and a window beyond it: the tables' indices lie in them and their offsets add up
// to the modulo's slot; storageIndex agrees with the modulo further out too.
void expectOffsetsAgreeWithTheModulo(const RollingWindow& window) {
  const int size = window.sizeCells();
  auto by_modulo = [&](int x, int y) {
    return window.storageSlot(positiveMod(x, size), positiveMod(y, size));
  };
  const CellBox box = window.box();
  const CellBox margin{box.min - CellIndex(size, size), box.max + CellIndex(size, size)};
  const CellIndex& base = window.offsetOrigin();
  for (int y = box.min.y() - 2 * size; y < box.max.y() + 2 * size; ++y) {
    for (int x = box.min.x() - 2 * size; x < box.max.x() + 2 * size; ++x) {
      ASSERT_EQ(window.storageIndex({x, y}), by_modulo(x, y)) << "x " << x << " y " << y;
      if (!margin.contains({x, y})) continue;
      const int column = x - base.x(), row = y - base.y();
      ASSERT_TRUE(column >= 0 && column < 4 * size && row >= 0 && row < 4 * size)
          << "x " << x << " y " << y;
      ASSERT_EQ(window.columnOffsets()[column] + window.rowOffsets()[row], by_modulo(x, y))
          << "x " << x << " y " << y;
    }
  }
}

TEST(RollingWindow, AxisOffsetsAndStorageIndexAgreeWithTheModulo) {
  RollingWindow window(16, 3);
  expectOffsetsAgreeWithTheModulo(window);  // as constructed, before any re-centring
  for (const TileIndex& origin : {TileIndex(-7, 2), TileIndex(5, -1), TileIndex(0, 0)}) {
    SCOPED_TRACE(origin.transpose());
    window.setOrigin(origin);
    expectOffsetsAgreeWithTheModulo(window);
  }
}

TEST(RollingWindow, CellOfSlotIsTheCellOfTheBoxStoredThere) {
  RollingWindow window(16, 3);
  for (const TileIndex& origin : {TileIndex(0, 0), TileIndex(-7, 2), TileIndex(5, -1)}) {
    SCOPED_TRACE(origin.transpose());
    window.setOrigin(origin);
    const CellBox box = window.box();
    for (int y = box.min.y(); y < box.max.y(); ++y) {
      for (int x = box.min.x(); x < box.max.x(); ++x)
        ASSERT_EQ(window.cellOfSlot(window.storageIndex({x, y})), CellIndex(x, y));
    }
  }
}

TEST(RollingWindow, DiffReportsExactlyTheTilesThatLeftAndEntered) {
  RollingWindow window(16, 5);
  window.setOrigin({0, 0});
  const WindowShift shift = diffWindows(window, {2, -1});
  EXPECT_TRUE(shift.moved);
  EXPECT_EQ(shift.left.size(), 25u - 3u * 4u);
  EXPECT_EQ(shift.entered.size(), shift.left.size());
  for (const TileIndex& t : shift.entered) {
    EXPECT_TRUE(t.x() >= 5 || t.y() < 0);
  }
  EXPECT_FALSE(diffWindows(window, {0, 0}).moved);
  // A jump larger than the window: everything leaves and enters.
  const WindowShift jump = diffWindows(window, {100, 100});
  EXPECT_EQ(jump.left.size(), 25u);
  EXPECT_EQ(jump.entered.size(), 25u);
}

}  // namespace
}  // namespace rfm
