#include "reflectance_field_map/core/glass_completion.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <vector>

namespace rfm {
namespace {

// Classes of a box around the origin, all free, and a field without evidence; cells are set
// and read along the row y = 0 by x (m).
class LineOfCells : public ::testing::Test {
 protected:
  LineOfCells() : field_(testing::centredField(3.0)), box_(field_.activeBox()) {
    classes_.assign(static_cast<size_t>(box_.width()) * box_.height(), CellClass::kFree);
  }

  // The class of the cells of [from_x, to_x) on the row.
  void set(double from_x, double to_x, CellClass c) {
    for (double x = from_x + 0.025; x < to_x; x += 0.05)
      classes_[index(x)] = c;
  }
  // Glass's evidence in those cells: three hits in `bin`, misses in the twelve bins from
  // `first_missed_bin`.
  void addGlassEvidence(double from_x, double to_x, int bin, int first_missed_bin) {
    for (double x = from_x + 0.025; x < to_x; x += 0.05) {
      const CellIndex cell = field_.geometry().cellOf({x, 0.025});
      for (int i = 0; i < 3; ++i)
        field_.applyHit(cell, bin);
      for (int missed = first_missed_bin; missed < first_missed_bin + 12; ++missed)
        field_.applyMiss(cell, missed);
    }
  }
  size_t index(double x) const {
    return static_cast<size_t>(box_.indexOf(field_.geometry().cellOf({x, 0.025})));
  }
  int cellsOf(double from_x, double to_x, CellClass c) const {
    int n = 0;
    for (double x = from_x + 0.025; x < to_x; x += 0.05)
      n += classes_[index(x)] == c;
    return n;
  }

  static constexpr int kNormalBin = 45;  // 90 deg: across the row
  ReflectanceField field_;
  CellBox box_;
  std::vector<CellClass> classes_;
};

// A facade along y = 0 as motion removal leaves it (west to east): a wall, 1 m of free cells the
// robot never faced, a mullion, a 0.75 m pane whose cells make no run of their own (the field
// holds nothing for them), a mullion, and 1 m of glass that returned near its normal (bin 45,
// 90 deg) and was missed from twelve other directions: a run.
class FacadeLine : public LineOfCells {
 protected:
  FacadeLine() {
    set(-1.40, -1.35, CellClass::kStatic);  // wall
    set(-0.35, -0.30, CellClass::kStatic);  // mullion
    set(-0.30, 0.45, CellClass::kGlass);    // pane, no run
    set(0.45, 0.50, CellClass::kStatic);    // mullion
    set(0.50, 1.50, CellClass::kGlass);     // the run
    addGlassEvidence(0.50, 1.50, kNormalBin, 0);
  }
  int glassCells(double from_x, double to_x) const {
    return cellsOf(from_x, to_x, CellClass::kGlass);
  }
};

TEST_F(FacadeLine, GapBeyondAPaneThatIsNoRunIsCompleted) {
  GlassCompletion completion(field_.geometry(), 2.0);
  const std::vector<int>& completed = completion.complete(field_, box_, classes_);
  // The walk from the run's west end passes the mullions and the pane (longer than a frame, but
  // glass of the same line) and closes the gap at the wall.
  EXPECT_EQ(glassCells(-1.35, -0.35), 20);
  EXPECT_EQ(completed.size(), 20u);
  // Nothing beyond the wall.
  EXPECT_EQ(glassCells(-2.5, -1.40), 0);
}

TEST_F(FacadeLine, GapLookedThroughNearTheNormalStaysOpen) {
  // The robot faced the gap: rays near the run's normal passed through it.
  for (double x = -1.325; x < -0.35; x += 0.05)
    field_.applyMiss(field_.geometry().cellOf({x, 0.025}), kNormalBin);
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-1.35, -0.35), 0);
}

// A pane along y = 0 that the robot faced only in passing, as motion removal leaves it: walls
// (static) at both ends, and between them a run of motion cells that returned near the pane's
// normal and were missed from twelve other directions, 0.2 m short of each wall.
class UnanchoredPane : public LineOfCells {
 protected:
  UnanchoredPane() {
    set(-1.5, -1.0, CellClass::kStatic);
    set(0.6, 1.1, CellClass::kStatic);
  }

  // The run from `from_x` to `to_x`, returning in `bin`.
  void addRun(double from_x, double to_x, int bin) {
    set(from_x, to_x, CellClass::kMotion);
    addGlassEvidence(from_x, to_x, bin, 60);
  }
};

TEST_F(UnanchoredPane, RunBetweenStructureIsGlass) {
  addRun(-0.8, 0.4, kNormalBin);
  GlassCompletion completion(field_.geometry(), 2.0);
  const std::vector<int>& completed = completion.complete(field_, box_, classes_);
  // The run and the unfaced ends between it and the walls.
  EXPECT_EQ(cellsOf(-1.0, 0.6, CellClass::kGlass), 32);
  EXPECT_EQ(completed.size(), 32u);
  EXPECT_EQ(completion.turnedFromMotion(), 24u);
  EXPECT_EQ(cellsOf(-1.5, -1.0, CellClass::kStatic), 10);
}

TEST_F(UnanchoredPane, RunSeenAlongItsLineStaysMotion) {
  addRun(-0.8, 0.4, 0);  // a trail of someone walking away from the robot
  GlassCompletion completion(field_.geometry(), 2.0);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
  EXPECT_EQ(cellsOf(-0.8, 0.4, CellClass::kMotion), 24);
}

TEST_F(UnanchoredPane, RunFarFromStructureStaysMotion) {
  addRun(-0.8, -0.1, kNormalBin);  // 0.7 m short of the east wall: no pane's unfaced end
  GlassCompletion completion(field_.geometry(), 2.0);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
  EXPECT_EQ(cellsOf(-0.8, -0.1, CellClass::kMotion), 14);
}

TEST_F(UnanchoredPane, RunBesideAnOpeningFacedStaysMotion) {
  addRun(-0.8, 0.4, kNormalBin);
  // Rays near the normal passed between the run and the east wall.
  for (double x = 0.425; x < 0.6; x += 0.05)
    field_.applyMiss(field_.geometry().cellOf({x, 0.025}), kNormalBin);
  GlassCompletion completion(field_.geometry(), 2.0);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
}

}  // namespace
}  // namespace rfm
