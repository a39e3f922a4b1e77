#include "reflectance_field_map/core/pane_shape.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rfm {
namespace {

constexpr int kWidth = 80;

struct Grid {
  std::vector<CellClass> classes = std::vector<CellClass>(kWidth * kWidth, CellClass::kFree);
  void set(int x, int y, CellClass c) { classes[static_cast<size_t>(y) * kWidth + x] = c; }
  CellClass at(int x, int y) const { return classes[static_cast<size_t>(y) * kWidth + x]; }
  // Draws the glass and metal on no pane static; returns how many.
  size_t drawStatic() {
    PaneShape panes;
    const OffPaneCells drawn = drawStaticOffPane({{0, 0}, {kWidth, kWidth}}, classes, panes);
    EXPECT_EQ(drawn.cells.size(), drawn.glass + drawn.metal);
    return drawn.cells.size();
  }
};

TEST(PaneShape, StraightRunsOfGlassAreOnAPaneInAnyDirection) {
  Grid grid;
  for (int i = 0; i < 12; ++i) {
    grid.set(10 + i, 10, CellClass::kGlass);          // along x
    grid.set(10 + i, 30 + i, CellClass::kGlass);      // diagonal
    grid.set(50 + i, 30 + i / 3, CellClass::kMetal);  // a shallow slope, rasterised in steps
  }
  EXPECT_EQ(grid.drawStatic(), 0u);
  for (int i = 0; i < 12; ++i) {
    EXPECT_EQ(grid.at(10 + i, 10), CellClass::kGlass) << i;
    EXPECT_EQ(grid.at(10 + i, 30 + i), CellClass::kGlass) << i;
    EXPECT_EQ(grid.at(50 + i, 30 + i / 3), CellClass::kMetal) << i;
  }
}

TEST(PaneShape, APaneInItsFramesAndAsThickAsOdometryDrawsItIsOnAPane) {
  Grid grid;
  // Three cells thick, glass and static frames mixed along it.
  for (int x = 10; x < 30; ++x) {
    for (int y = 20; y < 23; ++y)
      grid.set(x, y, (x % 5 == 0 || y != 21) ? CellClass::kStatic : CellClass::kGlass);
  }
  EXPECT_EQ(grid.drawStatic(), 0u);
  EXPECT_EQ(grid.at(12, 21), CellClass::kGlass);
}

TEST(PaneShape, CurvedGlassIsOnAPane) {
  Grid grid;
  // A 300 degree arc of radius 3 m at 5 cm (60 cells would not fit: radius 35 cells, 1.75 m).
  const double radius = 35.0;
  for (double a = 0.0; a < 300.0 * M_PI / 180.0; a += 0.2 / radius) {
    grid.set(static_cast<int>(std::lround(40 + radius * std::cos(a))),
             static_cast<int>(std::lround(40 + radius * std::sin(a))), CellClass::kGlass);
  }
  EXPECT_EQ(grid.drawStatic(), 0u);
}

TEST(PaneShape, BlobsShortRunsAndPilesAreOnNoPane) {
  Grid grid;
  for (int y = 10; y < 13; ++y) {
    for (int x = 10; x < 13; ++x)
      grid.set(x, y, CellClass::kGlass);  // a 3 x 3 blob
  }
  for (int x = 30; x < 33; ++x)
    grid.set(x, 10, CellClass::kGlass);  // three cells in a row
  for (int y = 40; y < 50; ++y) {
    for (int x = 40; x < 50; ++x)
      grid.set(x, y, CellClass::kStatic);  // a pile of clutter ...
  }
  grid.set(44, 44, CellClass::kGlass);  // ... with glass returns in it
  grid.set(45, 47, CellClass::kMetal);
  grid.set(60, 60, CellClass::kGlass);  // alone
  PaneShape panes;
  const OffPaneCells drawn = drawStaticOffPane({{0, 0}, {kWidth, kWidth}}, grid.classes, panes);
  EXPECT_EQ(drawn.glass, 9u + 3u + 1u + 1u);
  EXPECT_EQ(drawn.metal, 1u);
  EXPECT_EQ(drawn.cells.front(), 10 * kWidth + 10);
  EXPECT_EQ(grid.at(11, 11), CellClass::kStatic);
  EXPECT_EQ(grid.at(31, 10), CellClass::kStatic);
  EXPECT_EQ(grid.at(44, 44), CellClass::kStatic);
  EXPECT_EQ(grid.at(45, 47), CellClass::kStatic);
  EXPECT_EQ(grid.at(60, 60), CellClass::kStatic);
  // Only glass and metal change.
  EXPECT_EQ(grid.at(40, 40), CellClass::kStatic);
  EXPECT_EQ(grid.at(0, 0), CellClass::kFree);
}

TEST(PaneShape, SpecksOfGlassInAWallAreNoPane) {
  Grid grid;
  // A wall 30 cells long, its face seen through here and there by grazing rays: glass specks of
  // one to three cells in it, and one stretch of four (20 cm), as short as a pane can be.
  for (int x = 10; x < 40; ++x)
    grid.set(x, 20, CellClass::kStatic);
  grid.set(12, 20, CellClass::kGlass);
  grid.set(15, 21, CellClass::kGlass);  // on the wall's face, beside it
  grid.set(16, 21, CellClass::kMetal);  // glass and metal join one speck
  for (int x = 20; x < 23; ++x)
    grid.set(x, 20, CellClass::kGlass);
  for (int x = 30; x < 34; ++x)
    grid.set(x, 20, CellClass::kGlass);
  EXPECT_EQ(grid.drawStatic(), 6u);
  EXPECT_EQ(grid.at(12, 20), CellClass::kStatic);
  EXPECT_EQ(grid.at(16, 21), CellClass::kStatic);
  EXPECT_EQ(grid.at(21, 20), CellClass::kStatic);
  for (int x = 30; x < 34; ++x)
    EXPECT_EQ(grid.at(x, 20), CellClass::kGlass) << x;
}

TEST(PaneShape, SpecksAreMeasuredAfreshOnEveryCall) {
  PaneShape panes;
  std::vector<CellClass> pane(10, CellClass::kGlass);  // a box of 10 x 1 cells: a pane
  EXPECT_TRUE(drawStaticOffPane({{0, 0}, {10, 1}}, pane, panes).cells.empty());
  std::vector<CellClass> wall(10, CellClass::kStatic);  // the same cells: a wall with a speck
  wall[4] = CellClass::kGlass;
  EXPECT_EQ(drawStaticOffPane({{0, 0}, {10, 1}}, wall, panes).cells, std::vector<int>{4});
}

TEST(PaneShape, GlassThatReflectsOnlyFarFromItsPanesNormalIsNoPane) {
  // A line of glass along x (normal along y) whose cells reflect in directions given by index.
  const CellBox box{{0, 0}, {20, 3}};
  std::vector<CellClass> classes(20 * 3, CellClass::kFree);
  std::vector<std::vector<double>> reflects_at(classes.size());  // rad, world directions
  for (int x = 2; x < 18; ++x) {
    classes[20 + x] = CellClass::kGlass;
    reflects_at[20 + x] = {M_PI / 2.0};  // faced: seen along the normal
  }
  reflects_at[20 + 5] = {M_PI / 4.0};                    // only 45 deg off: a reflection's image
  reflects_at[20 + 6] = {-M_PI / 2.0 + 0.1};             // faced from the other side
  reflects_at[20 + 7] = {M_PI / 4.0, M_PI / 2.0};        // faced, and a speck of dirt elsewhere
  reflects_at[20 + 8] = {};                              // no reflective direction: completed glass
  reflects_at[20 + 9] = {0.0, M_PI, M_PI / 4.0 + M_PI};  // along the line and oblique only
  const FacesNormal faces_normal = [&](int i, const Eigen::Vector2d& normal, double max_off) {
    if (reflects_at[i].empty()) return true;
    for (const double a : reflects_at[i]) {
      if (std::abs(std::cos(a) * normal.x() + std::sin(a) * normal.y()) >= std::cos(max_off)) {
        return true;
      }
    }
    return false;
  };
  PaneShape panes;
  const OffPaneCells drawn = drawStaticOffPane(box, classes, panes, faces_normal);
  EXPECT_EQ(drawn.cells, (std::vector<int>{20 + 5, 20 + 9}));
  EXPECT_EQ(classes[20 + 5], CellClass::kStatic);
  EXPECT_EQ(classes[20 + 6], CellClass::kGlass);
  EXPECT_EQ(classes[20 + 7], CellClass::kGlass);
  EXPECT_EQ(classes[20 + 8], CellClass::kGlass);
}

TEST(PaneShape, MotionAndFreeCellsDoNotJoinAPane) {
  Grid grid;
  // Glass continued by a trail of motion: three glass cells are no pane.
  for (int x = 10; x < 13; ++x)
    grid.set(x, 10, CellClass::kGlass);
  for (int x = 13; x < 25; ++x)
    grid.set(x, 10, CellClass::kMotion);
  EXPECT_EQ(grid.drawStatic(), 3u);
  EXPECT_EQ(grid.at(13, 10), CellClass::kMotion);
}

TEST(PaneShape, ABoxAnywhereIsJudgedInItsOwnCells) {
  const CellBox box{{-50, 30}, {-30, 40}};  // 20 x 10 cells
  std::vector<CellClass> classes(20 * 10, CellClass::kFree);
  for (int x = 2; x < 13; ++x)
    classes[5 * 20 + x] = CellClass::kGlass;  // a pane
  classes[2 * 20 + 17] = CellClass::kGlass;   // alone
  classes[9 * 20 + 19] = CellClass::kMetal;   // alone, in the box's last cell
  PaneShape panes;
  const OffPaneCells drawn = drawStaticOffPane(box, classes, panes);
  EXPECT_EQ(drawn.cells, (std::vector<int>{2 * 20 + 17, 9 * 20 + 19}));
  EXPECT_EQ(classes[5 * 20 + 2], CellClass::kGlass);
  // Judged alone, the pane's first cell is a lone cell of a box of its own.
  std::vector<CellClass> one(1, CellClass::kGlass);
  EXPECT_EQ(drawStaticOffPane({{-48, 35}, {-47, 36}}, one, panes).glass, 1u);
}

}  // namespace
}  // namespace rfm
