#include "reflectance_field_map/core/glass_completion.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <vector>

namespace rfm {
namespace {

// Classes of a box around the origin, all free, and a field without evidence; cells are set
// and read by x (m) along the row y = 0, or the row `row` rows from it.
class LineOfCells : public ::testing::Test {
 protected:
  LineOfCells() : field_(testing::centredField(3.0)), box_(field_.activeBox()) {
    classes_.assign(static_cast<size_t>(box_.width()) * box_.height(), CellClass::kFree);
  }

  // The class of the cells of [from_x, to_x) on the row.
  void set(double from_x, double to_x, CellClass c, int row = 0) {
    for (double x = from_x + 0.025; x < to_x; x += 0.05)
      classes_[index(x, row)] = c;
  }
  // Glass's evidence in those cells: three hits in `bin`, misses in the twelve bins from
  // `first_missed_bin`.
  void addGlassEvidence(double from_x, double to_x, int bin, int first_missed_bin, int row = 0) {
    for (double x = from_x + 0.025; x < to_x; x += 0.05) {
      const CellIndex cell = cellAt(x, row);
      for (int i = 0; i < 3; ++i)
        field_.applyHit(cell, bin);
      for (int missed = first_missed_bin; missed < first_missed_bin + 12; ++missed)
        field_.applyMiss(cell, missed);
    }
  }
  // A beam ended once in every `every`-th cell of [from_x, to_x) on the row (20 deg, oblique to
  // the row), then two more went through: dirt on a pane seen obliquely. The cells stay free.
  void addEchoes(double from_x, double to_x, int every, int row = 0) {
    int n = 0;
    for (double x = from_x + 0.025; x < to_x; x += 0.05) {
      if (n++ % every != 0) continue;
      field_.applyHit(cellAt(x, row), 10);
      field_.applyMiss(cellAt(x, row), 10);
      field_.applyMiss(cellAt(x, row), 10);
    }
  }
  CellIndex cellAt(double x, int row) const {
    return field_.geometry().cellOf({x, 0.025 + 0.05 * row});
  }
  size_t index(double x, int row = 0) const {
    return static_cast<size_t>(box_.indexOf(cellAt(x, row)));
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
  }
  // The run, on the row or (`straddling`) on the boundary between rows 0 and -1.
  void addRun(bool straddling = false) {
    for (int row : straddling ? std::vector<int>{0, -1} : std::vector<int>{0}) {
      set(0.50, 1.50, CellClass::kGlass, row);
      addGlassEvidence(0.50, 1.50, kNormalBin, 0, row);
    }
  }
  // The run on the boundary between rows 0 and -1, with range noise that put 4 of its 44 cells a
  // row further out, 1.4 cells off its line: a blurred run.
  void addBlurredRun() {
    addRun(true);
    for (double x : {0.625, 0.875, 1.125, 1.375}) {
      set(x - 0.025, x + 0.025, CellClass::kGlass, 1);
      addGlassEvidence(x - 0.025, x + 0.025, kNormalBin, 0, 1);
    }
  }
  int glassCells(double from_x, double to_x) const {
    return cellsOf(from_x, to_x, CellClass::kGlass);
  }
};

TEST_F(FacadeLine, StraightRunClosesAStretchThatNeverReturned) {
  // Clean glass seen obliquely returns nothing: a straight run's line is sure enough without.
  addRun();
  GlassCompletion completion(field_.geometry(), 2.0);
  const std::vector<int>& completed = completion.complete(field_, box_, classes_);
  // The walk from the run's west end passes the mullions and the pane (longer than a frame, but
  // glass of the same line) and closes the gap at the wall.
  EXPECT_EQ(glassCells(-1.35, -0.35), 20);
  EXPECT_EQ(completed.size(), 20u);
  // Nothing beyond the wall.
  EXPECT_EQ(glassCells(-2.5, -1.40), 0);
}

TEST_F(FacadeLine, BlurredRunLeavesAStretchThatNeverReturnedOpen) {
  // An opening the robot never faced: nothing distinguishes it from glass but that no beam ever
  // ended in it.
  addBlurredRun();
  GlassCompletion completion(field_.geometry(), 2.0);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
  addEchoes(-1.35, -0.35, 20);  // 1 of its 20 cells: people crossing, not a pane's dirt
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
  EXPECT_EQ(glassCells(-1.35, -0.35), 0);
}

TEST_F(FacadeLine, BlurredRunLeavesAStretchWithEchoesAllAroundItOpen) {
  // People walked through an opening: beams ended in a quarter of its cells, and as often in
  // those 3-6 cells beside it.
  addBlurredRun();
  for (int row = -6; row <= 6; ++row)
    addEchoes(-1.35, -0.35, 4, row);
  GlassCompletion completion(field_.geometry(), 2.0);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
}

TEST_F(FacadeLine, BlurredRunClosesAStretchWithEchoesOnItsLine) {
  // Dirt on a pane: echoes in half of its cells, an eighth beside it (people passing in front).
  addBlurredRun();
  addEchoes(-1.35, -0.35, 2);
  for (int row : {-6, -5, -4, -3, 3, 4, 5, 6})
    addEchoes(-1.35, -0.35, 8, row);
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-1.35, -0.35), 20);
}

TEST_F(FacadeLine, BlurredRunClosesAStretchShorterThanADoorwayWithoutEchoes) {
  addBlurredRun();
  set(-0.70, -0.65, CellClass::kStatic);  // a wall 0.3 m from the mullion
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-0.65, -0.35), 6);
  EXPECT_EQ(glassCells(-1.35, -0.70), 0);  // beyond that wall: nothing
}

TEST_F(FacadeLine, RunWithAFifthOfItsCellsOffItsLineIsNoRun) {
  addBlurredRun();
  addEchoes(-1.35, -0.35, 4);
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-1.35, -0.35), 20);
  // A fifth of its cells 1.4 cells out: no straight run, nothing completed.
  for (double x : {0.525, 0.575, 0.675, 0.725, 0.775, 0.825, 0.925, 0.975, 1.025, 1.075}) {
    set(x - 0.025, x + 0.025, CellClass::kGlass, 1);
    addGlassEvidence(x - 0.025, x + 0.025, kNormalBin, 0, 1);
  }
  set(-1.35, -0.35, CellClass::kFree);
  EXPECT_TRUE(completion.complete(field_, box_, classes_).empty());
}

TEST_F(FacadeLine, MotionOnAStraightRunsLineFramesAStretch) {
  addRun();
  set(-1.40, -1.35, CellClass::kFree);    // no wall: the free cells go on for more than 2 m
  set(-0.75, -0.70, CellClass::kMotion);  // a mullion glimpsed from a few directions only
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-0.70, -0.35), 7);  // the gap it frames
  EXPECT_EQ(glassCells(-3.0, -0.70), 0);
}

TEST_F(FacadeLine, MotionOnABlurredRunsLineEndsItsWalk) {
  // Someone standing on the floor past the pane's end, 0.3 m from the mullion: no frame.
  addBlurredRun();
  set(-1.40, -1.35, CellClass::kFree);  // no wall: the free cells go on for more than 2 m
  for (int row = -2; row <= 2; ++row)
    set(-0.95, -0.65, CellClass::kMotion, row);
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-3.0, -0.35), 0);
  EXPECT_EQ(cellsOf(-0.95, -0.65, CellClass::kMotion), 6);
}

TEST_F(FacadeLine, GapLookedThroughNearTheNormalStaysOpen) {
  addRun();
  addEchoes(-1.35, -0.35, 4);
  // The robot faced the gap: rays near the run's normal passed through it.
  for (double x = -1.325; x < -0.35; x += 0.05)
    field_.applyMiss(field_.geometry().cellOf({x, 0.025}), kNormalBin);
  GlassCompletion completion(field_.geometry(), 2.0);
  completion.complete(field_, box_, classes_);
  EXPECT_EQ(glassCells(-1.35, -0.35), 0);
}

TEST_F(FacadeLine, GapLookedThroughFromTheOtherFaceStaysOpen) {
  addRun();
  // The run returned from the south; the robot faced the gap from the north (270 deg), where
  // glass would have returned as well.
  for (double x = -1.325; x < -0.35; x += 0.05)
    field_.applyMiss(field_.geometry().cellOf({x, 0.025}), kNormalBin + 90);
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
