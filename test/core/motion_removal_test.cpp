#include "reflectance_field_map/core/motion_removal.h"

#include "reflectance_field_map/core/mapper.h"

#include "scenario.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

namespace rfm {
namespace {

using testing::Disc;
using testing::driveBy;
using testing::fractionAlong;
using testing::runScenario;
using testing::ScenarioStep;
using testing::SyntheticWorld;

TEST(BinIntervals, OverlapWrapsAroundTheCircle) {
  EXPECT_TRUE(binIntervalsOverlap(0, 3, 2, 2, 180));
  EXPECT_FALSE(binIntervalsOverlap(0, 3, 3, 2, 180));
  EXPECT_TRUE(binIntervalsOverlap(178, 4, 1, 1, 180));  // 178,179,0,1
  EXPECT_FALSE(binIntervalsOverlap(178, 3, 1, 1, 180));
  EXPECT_TRUE(binIntervalsOverlap(-1, 3, 179, 1, 180));  // dilated run starting before bin 0
  EXPECT_TRUE(binIntervalsOverlap(10, 180, 50, 1, 180));
}

// Builds field evidence directly: a set of (cell, bin) hits.
struct DirectField {
  DirectField() : field(testing::centredField(2.0)) {}
  void hit(const CellIndex& cell, int bin, int times = 10) {
    for (int i = 0; i < times; ++i)
      field.applyHit(cell, bin);
  }
  CellClass classify(const CellIndex& cell, const AnchorRules& anchors = AnchorRules()) {
    MotionRemover remover(OccupancyRule(OccupancyOptions(), field.geometry().binWidth()), anchors);
    std::vector<CellClass> classes;
    const CellBox box = field.activeBox();
    remover.classify(
        field, history, box, [](const CellIndex&) { return CellClass::kUnknown; }, classes);
    return classes[box.indexOf(cell)];
  }
  // The classes of `cells` by `remover`, which keeps what its previous calls drew.
  std::vector<CellClass> classifyBy(MotionRemover& remover, const std::vector<CellIndex>& cells) {
    std::vector<CellClass> classes;
    const CellBox box = field.activeBox();
    remover.classify(
        field, history, box, [](const CellIndex&) { return CellClass::kUnknown; }, classes);
    std::vector<CellClass> out;
    for (const CellIndex& cell : cells)
      out.push_back(classes[box.indexOf(cell)]);
    return out;
  }
  // classify() with one anchor rule set to `value` on top of `base`.
  CellClass classifyWith(const CellIndex& cell, int AnchorRules::*rule, int value,
                         AnchorRules base = AnchorRules()) {
    base.*rule = value;
    return classify(cell, base);
  }
  // The cell's blob is `anchored` with `rule` off (0), motion with the rule at `met` (what the
  // cell reaches) and `anchored` again one above it.
  void expectRuleMetExactlyAt(const CellIndex& cell, int AnchorRules::*rule, int met,
                              CellClass anchored, const AnchorRules& base = AnchorRules()) {
    EXPECT_EQ(classifyWith(cell, rule, 0, base), anchored) << "rule off";
    EXPECT_EQ(classifyWith(cell, rule, met, base), CellClass::kMotion) << "rule at " << met;
    EXPECT_EQ(classifyWith(cell, rule, met + 1, base), anchored) << "rule at " << met + 1;
  }
  // A persistence tick keeping the histories of cells with at least `remembered_min_bins`
  // reflective bins and of cells confirmed for `confirmed_min_ticks` (0: none).
  void tick(int remembered_min_bins = std::numeric_limits<int>::max(),
            int confirmed_min_ticks = 0) {
    AnchorRules tracked;
    tracked.remembered_min_bins = remembered_min_bins;
    tracked.confirmed_min_ticks = confirmed_min_ticks;
    history.tick(field, tracked);
  }
  ReflectanceField field;
  AnchorHistory history{field};
};

TEST(MotionRemover, TwentySixConnectivityIncludingThetaWrap) {
  DirectField f;
  for (int b = 0; b < 40; ++b)
    f.hit({0, 0}, b);  // widely visible anchor
  // A stroke connected diagonally in (x, y) and by one bin in theta, wrapping 0 -> 179.
  f.hit({1, 1}, 179);
  f.hit({2, 2}, 178);
  f.hit({3, 2}, 177);
  // An island two bins away in theta from the stroke's end: not connected.
  f.hit({4, 2}, 175);
  EXPECT_EQ(f.classify({0, 0}), CellClass::kStatic);
  EXPECT_EQ(f.classify({1, 1}), CellClass::kGlass);
  EXPECT_EQ(f.classify({2, 2}), CellClass::kGlass);
  EXPECT_EQ(f.classify({3, 2}), CellClass::kGlass);
  EXPECT_EQ(f.classify({4, 2}), CellClass::kMotion);
  // Two cells apart in space: not connected either.
  f.hit({6, 2}, 177);
  EXPECT_EQ(f.classify({6, 2}), CellClass::kMotion);
}

// Eq. 7 decides which cells are static, however the remover bounds the sum: cells with random
// evidence around beta are static exactly when their marginal odds exceed it.
TEST(MotionRemover, WidelyVisibleCellsAreThoseOfEquationSeven) {
  DirectField f;
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> bin(0, 179), reflective(20, 70), missed(0, 150), hits(2, 5),
      misses(1, 8);
  std::vector<CellIndex> cells;
  for (int i = 0; i < 200; ++i) {
    const CellIndex cell(-30 + 3 * (i % 20), -30 + 3 * (i / 20));
    for (int k = reflective(rng); k > 0; --k)
      f.hit(cell, bin(rng), hits(rng));
    for (int k = missed(rng); k > 0; --k) {
      const int b = bin(rng);
      for (int m = misses(rng); m > 0; --m)
        f.field.applyMiss(cell, b);
    }
    cells.push_back(cell);
  }
  size_t static_cells = 0, other = 0;
  const double beta = OccupancyOptions().beta;
  for (const CellIndex& cell : cells) {
    const CellClass c = f.classify(cell);
    if (isEmptySpace(c)) continue;  // static when widely visible, else motion (alone)
    const bool widely_visible = f.field.marginalOdds(cell) > beta;
    EXPECT_EQ(c == CellClass::kStatic, widely_visible) << f.field.marginalOdds(cell);
    ++(widely_visible ? static_cells : other);
  }
  EXPECT_GT(static_cells, 20u);  // both sides of beta are exercised
  EXPECT_GT(other, 20u);
}

TEST(MotionRemover, ASecondRunInTheSameCellIsJudgedOnItsOwn) {
  DirectField f;
  for (int b = 0; b < 40; ++b)
    f.hit({0, 0}, b);
  f.hit({1, 0}, 39);   // glass-like lobe attached to the anchor
  f.hit({1, 0}, 120);  // a person crossing the same cell in another direction
  f.hit({2, 0}, 121);
  EXPECT_EQ(f.classify({1, 0}), CellClass::kGlass);   // any anchored run keeps the cell
  EXPECT_EQ(f.classify({2, 0}), CellClass::kMotion);  // the person's run is not anchored
}

TEST(MotionRemover, LongStrokesDoNotOverflowAnything) {
  // A long connected structure (iterative union-find, no recursion).
  DirectField f;
  for (int x = -30; x < 30; ++x) {
    for (int y = -30; y < 30; ++y)
      f.hit({x, y}, positiveMod(x + y, 180), 2);
  }
  EXPECT_EQ(f.classify({0, 0}), CellClass::kMotion);
}

// Long-confirmed evidence anchors structure only when the component is long enough: a wall
// seen from one place does, a person standing still (a small blob) does not.
TEST(MotionRemover, PersistentCellsAnchorOnlyLongComponents) {
  DirectField f;
  for (int tick = 0; tick < 4; ++tick) {
    for (int y = -10; y < 10; ++y)
      f.hit({8, y}, 0, 1);  // a 1 m wall segment, seen head-on
    for (int x = -12; x < -8; ++x)
      f.hit({x, 5}, 90, 1);  // a 0.2 m blob
    f.tick();
  }
  auto persistence = [](int ticks, int min_cells) {
    AnchorRules anchors;
    anchors.persistence_ticks = ticks;
    anchors.persistence_min_cells = min_cells;
    return anchors;
  };
  EXPECT_EQ(f.classify({8, 0}, persistence(3, 0)), CellClass::kGlass);
  EXPECT_EQ(f.classify({-10, 5}, persistence(3, 0)), CellClass::kGlass);
  EXPECT_EQ(f.classify({8, 0}, persistence(3, 12)), CellClass::kGlass);
  EXPECT_EQ(f.classify({-10, 5}, persistence(3, 12)), CellClass::kMotion);
  // Not confirmed long enough.
  EXPECT_EQ(f.classify({8, 0}, persistence(5, 12)), CellClass::kMotion);
}

// A person seen from all around while standing still is widely visible; once rays pass where it
// reflected, it anchors nothing and its component is motion.
TEST(MotionRemover, DepartedCellsAnchorNothing) {
  DirectField f;
  const CellIndex spot(-5, 3);
  for (int bin = 0; bin < 180; ++bin)
    f.hit(spot, bin);
  f.tick(/*remembered_min_bins=*/1);
  for (int i = 0; i < 20; ++i) {
    for (int bin = 10; bin < 13; ++bin)
      f.field.applyMiss(spot, bin);
  }
  f.expectRuleMetExactlyAt(spot, &AnchorRules::departure_min_bins, 3, CellClass::kStatic);
}

// A person seen from all around while standing still, then seen through only from directions
// they were never seen from (the robot looking back after they left): vacant, anchors nothing.
TEST(MotionRemover, VacantCellsAnchorNothing) {
  DirectField f;
  const CellIndex spot(-5, 3);
  for (int bin = 0; bin < 120; ++bin)
    f.hit(spot, bin);
  f.tick(/*remembered_min_bins=*/1);
  for (int tick = 0; tick < 2; ++tick) {
    for (int bin = 150 + 5 * tick; bin < 155 + 5 * tick; ++bin)
      f.field.applyMiss(spot, bin);
    f.tick(1);
  }
  ASSERT_EQ(f.history.vacantTicksAt(f.field.window().storageIndex(spot)), 2);
  f.expectRuleMetExactlyAt(spot, &AnchorRules::departure_vacant_ticks, 2, CellClass::kStatic);
  // One scan a tick (a sparse logger): vacant over 2 scans, short of 3.
  AnchorRules over_scans;
  over_scans.departure_vacant_ticks = 2;
  over_scans.departure_vacant_scans = 2;
  EXPECT_EQ(f.classify(spot, over_scans), CellClass::kMotion);
  over_scans.departure_vacant_scans = 3;
  EXPECT_EQ(f.classify(spot, over_scans), CellClass::kStatic);
}

// A blob of solid cells, each reflective over 20 deg (a solid anchor), `gone` of them then seen
// through from new directions with nothing hit (vacant): a person seen from one side who left,
// the robot seeing through part of the spot only (its rays are cut at the cells it saw first).
// Once the cells seen gone make solid_min_share of the blob, the rest anchors nothing by its
// solid angle.
TEST(MotionRemover, SolidAnchorsOfABlobMostlySeenGoneAnchorNothing) {
  auto classes_with_gone = [](int gone) {
    DirectField f;
    for (int x = 0; x < 6; ++x) {
      for (int bin = 40; bin < 50; ++bin)
        f.hit({x, 3}, bin);
    }
    f.tick(/*remembered_min_bins=*/1);
    for (int tick = 0; tick < 2; ++tick) {
      for (int x = 0; x < gone; ++x) {
        for (int bin = 150 + 5 * tick; bin < 155 + 5 * tick; ++bin)
          f.field.applyMiss({x, 3}, bin);
      }
      f.tick(1);
    }
    AnchorRules rules;
    rules.departure_vacant_ticks = 2;
    rules.solid_max_missed_ratio = 2.0;
    rules.solid_min_share = 0.5;
    rules.solid_anchor_min_bins = 8;
    return std::vector<CellClass>{f.classify({0, 3}, rules), f.classify({5, 3}, rules)};
  };
  using C = CellClass;
  EXPECT_EQ(classes_with_gone(0), (std::vector<C>{C::kStatic, C::kStatic}));
  EXPECT_EQ(classes_with_gone(2), (std::vector<C>{C::kStatic, C::kStatic}));
  // Half seen gone, half still solid: the solid share still makes it structure.
  EXPECT_EQ(classes_with_gone(3), (std::vector<C>{C::kStatic, C::kStatic}));
  EXPECT_EQ(classes_with_gone(4), (std::vector<C>{C::kMotion, C::kMotion}));
}

// A person who stood long enough to be confirmed, then left: the robot looks through the spot
// from where it saw them (missed where the cells were certain, hit nowhere). Abandoned, the
// cells anchor nothing and the blob is motion.
TEST(MotionRemover, AbandonedPersistentCellsAnchorNothing) {
  DirectField f;
  constexpr int kConfirmed = 3;
  for (int tick = 0; tick <= kConfirmed; ++tick) {
    for (int x = -12; x < -8; ++x)
      f.hit({x, 5}, 90, 6);
    f.tick(/*remembered_min_bins=*/1000, kConfirmed);
  }
  for (int tick = 0; tick < 2; ++tick) {
    for (int x = -12; x < -8; ++x)
      f.field.applyMiss({x, 5}, 90);
    f.tick(1000, kConfirmed);
  }
  AnchorRules confirmed;
  confirmed.persistence_ticks = kConfirmed;
  f.expectRuleMetExactlyAt({-10, 5}, &AnchorRules::departure_vacant_ticks, 2, CellClass::kGlass,
                           confirmed);
}

// A pane confirmed for the persistence time, then seen from outside its lobe with nothing near it
// hit: its cells get new missed bins and no hit (vacant), yet a pane keeps returning near its
// normal. Cells merely confirmed depart only if they could have been widely visible
// (wide_min_bins at a tick); the pane's reflect in 3 bins and stay glass.
TEST(MotionRemover, ConfirmedPaneSeenFromOutsideItsLobeStaysGlass) {
  constexpr int kConfirmed = 3;
  auto pane_after_vacancy = [](int wide_min_bins) {
    DirectField f;
    AnchorRules tracked;
    tracked.remembered_min_bins = 3;
    tracked.wide_min_bins = wide_min_bins;
    tracked.confirmed_min_ticks = kConfirmed;
    for (int tick = 0; tick <= kConfirmed; ++tick) {
      for (int x = -12; x < -8; ++x) {
        for (int bin = 89; bin < 92; ++bin)
          f.hit({x, 5}, bin, 6);
        for (int bin = 10; bin < 20; ++bin)
          f.field.applyMiss({x, 5}, bin);  // seen through away from its lobe: not solid
      }
      f.history.tick(f.field, tracked);
    }
    for (int tick = 0; tick < 2; ++tick) {
      for (int x = -12; x < -8; ++x)
        f.field.applyMiss({x, 5}, 120 + tick);
      f.history.tick(f.field, tracked);
    }
    AnchorRules rules;
    rules.persistence_ticks = kConfirmed;
    rules.departure_vacant_ticks = 2;
    rules.solid_max_missed_ratio = 2.0;
    return f.classify({-10, 5}, rules);
  };
  EXPECT_EQ(pane_after_vacancy(/*wide_min_bins=*/22), CellClass::kGlass);
  EXPECT_EQ(pane_after_vacancy(/*wide_min_bins=*/3), CellClass::kMotion);
}

// Hits a stroke of cells {x, y0..y1-1} in bins 40-42; `missed(y)` of them are also missed in 10
// bins each (seen through from elsewhere).
template <typename Missed>
void stroke(DirectField& f, int x, int y0, int y1, Missed&& missed) {
  for (int y = y0; y < y1; ++y) {
    for (int bin = 40; bin < 43; ++bin)
      f.hit({x, y}, bin);
    if (missed(y)) {
      for (int bin = 100; bin < 110; ++bin)
        f.field.applyMiss({x, y}, bin);
    }
  }
}

// A stroke along column x seen free (bin 0) before a persistence tick, then hit: it arrived.
void arrivingStroke(DirectField& f, int x) {
  for (int y = -10; y < 10; ++y) {
    for (int i = 0; i < 5; ++i)
      f.field.applyMiss({x, y}, 0);
  }
  f.tick();
  stroke(f, x, -10, 10, [](int) { return false; });
}

// A wall glimpsed through a doorway is reflective in a few bins and missed in few: solid. A
// person's stroke is seen through where they stood. Neither is widely visible; the solid share
// of a component decides.
TEST(MotionRemover, SolidComponentsAreStructure) {
  DirectField f;
  stroke(f, 8, -10, 10, [](int) { return false; });          // 1 m of wall
  stroke(f, -8, -10, 10, [](int y) { return y % 2 == 0; });  // half its cells seen through
  stroke(f, 0, -10, -6, [](int) { return true; });           // 0.2 m of person
  auto classes_with = [&](double max_missed_ratio, double min_share) {
    AnchorRules anchors;
    anchors.solid_max_missed_ratio = max_missed_ratio;
    anchors.solid_min_share = min_share;
    return std::vector<CellClass>{f.classify({8, 0}, anchors), f.classify({-8, 1}, anchors),
                                  f.classify({-8, 0}, anchors), f.classify({0, -8}, anchors)};
  };
  using C = CellClass;
  EXPECT_EQ(classes_with(0.0, 0.5),
            (std::vector<C>{C::kMotion, C::kMotion, C::kMotion, C::kMotion}));
  // Solid cells of a structure are static; its seen-through cells are glass.
  EXPECT_EQ(classes_with(2.0, 0.5),
            (std::vector<C>{C::kStatic, C::kStatic, C::kGlass, C::kMotion}));
  EXPECT_EQ(classes_with(2.0, 0.6),
            (std::vector<C>{C::kStatic, C::kMotion, C::kMotion, C::kMotion}));
  // 10 missed bins for 3 reflective ones: solid only at a ratio of 10/3.
  EXPECT_EQ(classes_with(3.4, 0.5),
            (std::vector<C>{C::kStatic, C::kStatic, C::kStatic, C::kStatic}));
}

// Something that arrived where the field had seen free space (a person who stopped, a door
// closed) is not structure, however solid it looks since.
TEST(MotionRemover, CellsThatArrivedDoNotMakeStructure) {
  DirectField f;
  arrivingStroke(f, 8);
  stroke(f, -8, -10, 10, [](int) { return false; });
  AnchorRules anchors;
  anchors.solid_max_missed_ratio = 2.0;
  EXPECT_EQ(f.classify({-8, 0}, anchors), CellClass::kStatic);  // before the tick
  EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kStatic);
  f.tick();
  EXPECT_EQ(f.classify({-8, 0}, anchors), CellClass::kStatic);
  EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kMotion);
}

// Someone who walked onto floor the robot had seen free from all round and stood while it drove
// round them is widely visible: that anchors nothing. A wall's cell grazed first by rays running
// along the wall is missed in a bin or two before it is hit, and anchors as before.
TEST(MotionRemover, WidelyVisibleCellsThatArrivedWhereSeenFreeAllRoundAnchorNothing) {
  const CellIndex person(6, 6), wall(-6, -6);
  auto classes_with = [&](int wide_arrival_min_missed_bins) {
    DirectField f;
    for (int bin = 100; bin < 130; ++bin) {
      for (int i = 0; i < 5; ++i)
        f.field.applyMiss(person, bin);  // seen free over 60 deg
    }
    for (int i = 0; i < 5; ++i)
      f.field.applyMiss(wall, 0);  // grazed
    AnchorRules tracked;
    tracked.wide_arrival_min_missed_bins = wide_arrival_min_missed_bins;
    f.history.tick(f.field, tracked);
    for (int bin = 0; bin < 40; ++bin) {
      f.hit(person, bin);  // then widely visible
      f.hit(wall, bin);
    }
    f.history.tick(f.field, tracked);
    EXPECT_TRUE(f.history.arrivedAt(f.field.window().storageIndex(person)));
    EXPECT_TRUE(f.history.arrivedAt(f.field.window().storageIndex(wall)));
    return std::vector<CellClass>{f.classify(person), f.classify(wall)};
  };
  using C = CellClass;
  EXPECT_EQ(classes_with(0), (std::vector<C>{C::kStatic, C::kStatic}));  // off
  EXPECT_EQ(classes_with(10), (std::vector<C>{C::kMotion, C::kStatic}));
  EXPECT_EQ(classes_with(30), (std::vector<C>{C::kMotion, C::kStatic}));
  EXPECT_EQ(classes_with(31), (std::vector<C>{C::kStatic, C::kStatic}));
  EXPECT_EQ(classes_with(1), (std::vector<C>{C::kMotion, C::kMotion}));
}

// A cell the previous pass drew as structure keeps its class while it still reflects and no ray
// has seen through it since, though its component lost what anchored it (the frame beside a
// pane, now seen through). After forgetPrevious() the evidence alone decides again.
TEST(MotionRemover, DrawnStructureStaysWhileItStillReflects) {
  DirectField f;
  for (int b = 0; b < 40; ++b)
    f.hit({0, 0}, b);  // widely visible anchor
  f.hit({1, 0}, 39);   // a pane joined to it by bin 39
  f.hit({2, 0}, 39);
  const OccupancyRule rule(OccupancyOptions(), f.field.geometry().binWidth());
  MotionRemover remover(rule), forgetting(rule);
  auto classify = [&](MotionRemover& m) { return f.classifyBy(m, {{0, 0}, {1, 0}, {2, 0}}); };
  using C = CellClass;
  EXPECT_EQ(classify(remover), (std::vector<C>{C::kStatic, C::kGlass, C::kGlass}));
  EXPECT_EQ(classify(forgetting), (std::vector<C>{C::kStatic, C::kGlass, C::kGlass}));
  forgetting.forgetPrevious();
  for (int b = 0; b < 40; ++b) {
    for (int i = 0; i < 30; ++i)
      f.field.applyMiss({0, 0}, b);  // the anchor is seen through
  }
  EXPECT_EQ(classify(remover), (std::vector<C>{C::kFree, C::kGlass, C::kGlass}));
  EXPECT_EQ(classify(forgetting), (std::vector<C>{C::kFree, C::kMotion, C::kMotion}));
  for (int i = 0; i < 30; ++i)
    f.field.applyMiss({1, 0}, 39);  // seen through where it reflected: free
  for (int i = 0; i < 30; ++i)
    f.field.applyMiss({2, 0}, 100);  // seen through elsewhere, still reflective: not held
  EXPECT_EQ(classify(remover), (std::vector<C>{C::kFree, C::kFree, C::kMotion}));
}

// Structure drawn before is no hold for a component that arrived: a person who walked in and
// stood next to a wall, drawn static with it, is motion once the anchor rules see them arrive.
TEST(MotionRemover, DrawnStructureThatArrivedIsMotion) {
  DirectField f;
  arrivingStroke(f, 8);
  AnchorRules anchors;
  anchors.solid_max_missed_ratio = 2.0;
  MotionRemover remover(OccupancyRule(OccupancyOptions(), f.field.geometry().binWidth()), anchors);
  // Until the next persistence tick: solid, not yet known to have arrived.
  EXPECT_EQ(f.classifyBy(remover, {{8, 0}}), std::vector<CellClass>{CellClass::kStatic});
  f.tick();
  EXPECT_EQ(f.classifyBy(remover, {{8, 0}}), std::vector<CellClass>{CellClass::kMotion});
}

// A person who walked in and stood still is hit throughout their stay, so their cells are
// confirmed: they did not stand long enough to be structure, they arrived. Long-confirmed cells
// do not anchor a component with the solid share's worth of its runs in arrived solid cells.
TEST(MotionRemover, ConfirmedCellsThatArrivedAnchorNothing) {
  DirectField f;
  constexpr int kConfirmed = 3;
  for (int y = -10; y < 10; ++y) {
    for (int i = 0; i < 5; ++i)
      f.field.applyMiss({8, y}, 0);  // seen free ...
  }
  f.tick(/*remembered_min_bins=*/1000, kConfirmed);
  for (int tick = 0; tick <= kConfirmed; ++tick) {
    stroke(f, 8, -10, 10, [](int) { return false; });   // ... then hit at every tick
    stroke(f, -8, -10, 10, [](int) { return false; });  // never seen free
    f.tick(1000, kConfirmed);
  }
  ASSERT_TRUE(f.history.arrivedAt(f.field.window().storageIndex({8, 0})));
  ASSERT_GE(f.history.confirmedTicksAt(f.field.window().storageIndex({8, 0})), kConfirmed);
  AnchorRules anchors;
  anchors.persistence_ticks = kConfirmed;
  // Without the solid rules, arrival is not judged: the confirmed cells anchor both strokes.
  EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kGlass);
  EXPECT_EQ(f.classify({-8, 0}, anchors), CellClass::kGlass);
  anchors.solid_max_missed_ratio = 2.0;
  EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kMotion);
  EXPECT_EQ(f.classify({-8, 0}, anchors), CellClass::kStatic);
  // Not confirmed long enough, the stroke that did not arrive is still structure (its solid
  // share), and the one that did is motion as before.
  anchors.persistence_ticks = kConfirmed + 5;
  EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kMotion);
  EXPECT_EQ(f.classify({-8, 0}, anchors), CellClass::kStatic);
}

// Glass has open space on both sides: a would-be glass cell against static structure is that
// structure's surface, blurred.
TEST(MotionRemover, GlassAgainstStructureIsStatic) {
  DirectField f;
  stroke(f, 8, -10, 10, [](int) { return false; });  // solid wall
  stroke(f, 9, -10, 10, [](int) { return true; });   // its blurred face, seen through
  AnchorRules anchors;
  anchors.solid_max_missed_ratio = 2.0;
  // Off, and at or above the 3 static neighbours (x = 8, y - 1 .. y + 1) of the face's cells.
  for (int max_neighbours : {-1, 3, 8}) {
    anchors.glass_max_static_neighbours = max_neighbours;
    EXPECT_EQ(f.classify({9, 0}, anchors), CellClass::kGlass) << max_neighbours;
  }
  for (int max_neighbours : {0, 2}) {
    anchors.glass_max_static_neighbours = max_neighbours;
    EXPECT_EQ(f.classify({9, 0}, anchors), CellClass::kStatic) << max_neighbours;
    EXPECT_EQ(f.classify({8, 0}, anchors), CellClass::kStatic) << max_neighbours;
  }
}

// Hits the cells of the rim of radius `radius` (cells) about `centre`, at angles [from, to)
// (deg), once in each of the bins within `half_lobe` bins of the ray that returns from it: along
// the rim's inward normal, as polished metal returns.
void rim(DirectField& f, const Eigen::Vector2d& centre, double radius, int from, int to,
         int half_lobe = 5) {
  const GridGeometry& geometry = f.field.geometry();
  std::set<std::tuple<int, int, int>> hits;
  for (int deg = from; deg < to; ++deg) {
    const double a = deg * M_PI / 180.0;
    const Eigen::Vector2d point = centre + radius * Eigen::Vector2d(std::cos(a), std::sin(a));
    const int inward = geometry.binOf(a + M_PI);
    for (int bin = inward - half_lobe; bin <= inward + half_lobe; ++bin) {
      hits.emplace(static_cast<int>(std::lround(point.x())),
                   static_cast<int>(std::lround(point.y())), geometry.wrapBin(bin));
    }
  }
  for (const auto& [x, y, bin] : hits)
    f.hit({x, y}, bin, 1);
}

// A round metal column returns each beam only near its normal: its cells are reflective in a
// few bins each, turning with the rim. Found by that shape, it is structure: metal.
TEST(MotionRemover, RoundColumnIsStructure) {
  DirectField f;
  rim(f, {-10.0, 0.0}, 5.0, -70, 70);  // 25 cm radius, seen over 140 deg
  AnchorRules anchors;
  EXPECT_EQ(f.classify({-5, 0}, anchors), CellClass::kMotion);  // the rule off
  anchors.column_max_radius_cells = 20.0;
  EXPECT_EQ(f.classify({-5, 0}, anchors), CellClass::kMetal);
  EXPECT_EQ(f.classify({-7, 4}, anchors), CellClass::kMetal);
  anchors.column_max_radius_cells = 4.9;
  EXPECT_EQ(f.classify({-5, 0}, anchors), CellClass::kMotion);  // wider than the rule allows
}

// What a round column is not, though no other rule anchors it either: a straight stroke seen
// along one direction (a person crossing the robot's view), a rim seen over too small a turn, a
// rim thinner than 3 cells (table legs, which rays pass beside) and a disc filled with returns.
TEST(MotionRemover, OnlyRoundColumnsAreFoundByTheirShape) {
  struct Shape {
    std::string name;
    CellIndex probe;
    DirectField f;
  };
  std::vector<Shape> shapes(4);
  shapes[0] = {"stroke", {0, 0}, {}};
  for (int y = -5; y <= 5; ++y) {
    for (int bin = 40; bin < 51; ++bin)
      shapes[0].f.hit({0, y}, bin, 1);
  }
  shapes[1] = {"30 deg of a rim", {0, 0}, {}};
  rim(shapes[1].f, {-12.0, 0.0}, 12.0, -15, 15);
  shapes[2] = {"thin rim", {2, 0}, {}};
  rim(shapes[2].f, {0.0, 0.0}, 2.4, -60, 60, 2);
  shapes[3] = {"filled disc", {5, 0}, {}};
  for (double radius = 1.0; radius <= 6.0; radius += 0.5)
    rim(shapes[3].f, {0.0, 0.0}, radius, -70, 70, 2);
  AnchorRules anchors;
  for (Shape& shape : shapes) {
    anchors.column_max_radius_cells = 0.0;
    EXPECT_EQ(shape.f.classify(shape.probe, anchors), CellClass::kMotion)
        << shape.name << ", the rule off";
    anchors.column_max_radius_cells = 20.0;
    EXPECT_EQ(shape.f.classify(shape.probe, anchors), CellClass::kMotion) << shape.name;
  }
}

TEST(MotionRemover, KnownObstaclesOutsideTheBoxSeedComponents) {
  DirectField f;
  const CellBox box = f.field.activeBox();
  const CellIndex border(box.max.x() - 1, 0);
  f.hit(border, 5);
  f.hit(border - CellIndex(1, 0), 6);
  MotionRemover remover(OccupancyRule(OccupancyOptions(), f.field.geometry().binWidth()));
  std::vector<CellClass> classes;
  remover.classify(
      f.field, f.history, box,
      [&](const CellIndex& c) {
        return c.x() == box.max.x() ? CellClass::kStatic : CellClass::kUnknown;
      },
      classes);
  EXPECT_EQ(classes[box.indexOf(border - CellIndex(1, 0))], CellClass::kGlass);
  EXPECT_EQ(classes[box.indexOf(border)], CellClass::kGlass);
  // Without the seed the same evidence is motion.
  EXPECT_EQ(f.classify(border), CellClass::kMotion);
}

// Bands of rows on several threads, joined across their borders, give the classes of one
// thread: components here cross every band border (vertical strokes, a diagonal through theta)
// and some are anchored only in a band other than their own cells'.
TEST(MotionRemover, ThreadsGiveTheClassesOfOneThread) {
  DirectField f;
  const CellBox box = f.field.activeBox();
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    f.hit({0, y}, 10, 2);                              // one long stroke through all bands
    f.hit({5, y}, positiveMod(y, 180), 2);             // a stroke turning through theta
    if (y % 7 != 0) f.hit({-10 + (y % 3), y}, 90, 2);  // broken into pieces
  }
  for (int bin = 0; bin < 180; bin += 2)
    f.hit({0, box.max.y() - 1}, bin);  // widely visible: anchors the first stroke, far away
  for (int x = box.min.x(); x < box.max.x(); x += 3)
    f.hit({x, -x / 4}, 40, 2);  // scattered hits
  const OccupancyRule rule(OccupancyOptions(), f.field.geometry().binWidth());
  auto outside = [](const CellIndex&) { return CellClass::kUnknown; };
  std::vector<CellClass> one, several;
  MotionRemover single(rule), banded(rule);
  const MotionRemovalCounts a = single.classify(f.field, f.history, box, outside, one);
  for (int threads : {2, 3, 7}) {
    ParallelRunner runner(threads);
    const MotionRemovalCounts b =
        banded.classify(f.field, f.history, box, outside, several, &runner);
    EXPECT_EQ(one, several) << threads;
    EXPECT_EQ(a.components, b.components) << threads;
    EXPECT_EQ(a.motion_cells, b.motion_cells) << threads;
    EXPECT_EQ(a.glass_cells, b.glass_cells) << threads;
    EXPECT_EQ(a.static_cells, b.static_cells) << threads;
  }
  EXPECT_GE(a.glass_cells, static_cast<size_t>(box.height() - 1));  // the anchored stroke
  EXPECT_GT(a.motion_cells, static_cast<size_t>(box.height()));     // the others
}

// Reusing unchanged tiles gives exactly what classifying afresh gives, while the robot drives
// (the window scrolls), people walk and persistence ticks pass; the reuse does happen.
TEST(MotionRemover, ReusingUnchangedTilesGivesTheFreshResult) {
  SyntheticWorld world;
  world.addWall({-3.0, 2.5}, {9.0, 2.5});
  world.addFramedPane({2.0, -2.0}, {6.0, -2.0});
  world.addWall({-3.0, -3.5}, {9.0, -3.5});
  MapperOptions options;
  options.active_region.active_region_radius = 3.0;
  options.motion_removal.motion_removal_enabled = false;  // the removers under test run here
  Mapper mapper(options);
  const OccupancyRule rule(options.occupancy, mapper.field().geometry().binWidth());
  const AnchorRules anchors{/*persistence_ticks=*/4, /*persistence_min_cells=*/10,
                            /*departure_min_bins=*/3};
  // The reference classifies a copy of the field each time (a field of its own identity: no
  // tile is reused), with the same history of calls (the classes drawn before hold).
  MotionRemover incremental(rule, anchors), reference(rule, anchors);
  ParallelRunner runner(2);
  auto outside = [&](const CellIndex& cell) { return mapper.map().get(cell); };
  std::vector<CellClass> reused, fresh;
  size_t runs_with_reuse = 0;
  for (int i = 0; i < 480; ++i) {
    const double t = 0.025 * i;
    world.people = {Disc{{-1.0 + 0.9 * t, 1.0}, 0.25}, Disc{{5.0, -0.5}, 0.25}};
    if (t > 8.0) world.people.pop_back();  // the one standing still leaves
    mapper.addScan(world.timedScan({{0.6 * t, 0.0}, 0.0}, t));
    if ((i + 1) % 20 != 0) continue;
    const CellBox box = mapper.field().activeBox();
    const MotionRemovalCounts a =
        incremental.classify(mapper.field(), mapper.anchorHistory(), box, outside, reused,
                             i % 40 == 19 ? &runner : nullptr);
    const ReflectanceField copy = mapper.field();
    const MotionRemovalCounts b =
        reference.classify(copy, mapper.anchorHistory(), box, outside, fresh);
    ASSERT_EQ(reused, fresh) << "after scan " << i;
    ASSERT_EQ(a.free_cells, b.free_cells);
    ASSERT_EQ(a.motion_cells, b.motion_cells);
    ASSERT_EQ(a.glass_cells, b.glass_cells);
    ASSERT_EQ(a.static_cells, b.static_cells);
    bool any_reused = false;
    for (int y = box.min.y(); y < box.max.y(); y += 16)
      for (int x = box.min.x(); x < box.max.x(); x += 16)
        any_reused |= incremental.reusedTile({x, y});
    runs_with_reuse += any_reused;
  }
  EXPECT_GE(runs_with_reuse, 20u);  // of 24 runs: all but the first few
  // Sub-boxes and a different field are classified afresh.
  const CellBox inner{mapper.field().activeBox().min + CellIndex(5, 7),
                      mapper.field().activeBox().max - CellIndex(9, 3)};
  incremental.classify(mapper.field(), mapper.anchorHistory(), inner, outside, reused);
  const ReflectanceField copy = mapper.field();
  reference.classify(copy, mapper.anchorHistory(), inner, outside, fresh);
  EXPECT_EQ(reused, fresh);
}

// Fig. 2: a freestanding pane with frames passed by the robot: the frames are widely visible,
// the face is reflective only near its normal (the H), and the face is classified glass.
TEST(MotionRemoval, FreestandingPaneIsGlassWithTheHShape) {
  SyntheticWorld world;
  world.addFramedPane({3.0, -2.0}, {3.0, 2.0});
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, driveBy({0.0, -5.0}, {0.0, 5.0}, kPi / 2));
  EXPECT_GT(fractionAlong(mapper, {3.0, -1.85}, {3.0, 1.85},
                          [](CellClass c) { return c == CellClass::kGlass; }),
            0.9);
  // The H: frame cells reflective over a wide angle, face cells over a narrow one near 0 rad.
  const ReflectanceField& field = mapper.field();
  const GridGeometry& g = field.geometry();
  const CellIndex frame = g.cellOf({3.0 + 1e-3, 1.97});
  const CellIndex face = g.cellOf({3.0 + 1e-3, 0.5});
  EXPECT_GE(field.reflectiveBins(frame) * g.binWidth(), 30.0 * kPi / 180.0);
  EXPECT_EQ(mapper.cellClass(frame), CellClass::kStatic);
  EXPECT_LE(field.reflectiveBins(face) * g.binWidth(), 16.0 * kPi / 180.0);
  EXPECT_TRUE(field.isReflective(face, g.binOf(0.0)) || field.isReflective(face, g.binOf(-0.01)));
}

// Fig. 3: a pedestrian walking past leaves a thin stroke: removed, not an obstacle. The sensor
// does not move, so the wall is never widely visible: it is kept because it persists.
TEST(MotionRemoval, PedestrianWalkingPastIsRemoved) {
  SyntheticWorld world;
  world.addWall({-6.0, 4.0}, {6.0, 4.0});
  std::vector<ScenarioStep> steps;
  for (int i = 0; i < 600; ++i) {  // 15 s: longer than persistence_time
    const double t = 0.025 * i;
    steps.push_back({{{0.0, 0.0}, kPi / 2}, {Disc{{-4.0 + 0.8 * t, 2.0}, 0.25}}});
  }
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, steps);
  // Where the person stood at the start no later ray contradicts the evidence (the rays there
  // return nothing, and clear only up to clearing_distance): it is solid, and stays (README,
  // Limitations). Everywhere they walked they were seen through afterwards.
  EXPECT_EQ(
      fractionAlong(mapper, {-3.5, 1.75}, {3.5, 1.75}, [](CellClass c) { return isObstacle(c); }),
      0.0);
  EXPECT_GT(
      fractionAlong(mapper, {-2.0, 4.0}, {2.0, 4.0}, [](CellClass c) { return isObstacle(c); }),
      0.95);
}

// No cell within `half` m of `spot` on either axis is an obstacle: whoever stood there is gone
// from the map.
void expectSpotCleared(const Mapper& mapper, const Eigen::Vector2d& spot, double half) {
  const GridGeometry& g = mapper.field().geometry();
  for (double dx = -half; dx <= half; dx += 0.05) {
    for (double dy = -half; dy <= half; dy += 0.05) {
      EXPECT_FALSE(isObstacle(mapper.cellClass(g.cellOf(spot + Eigen::Vector2d(dx, dy)))))
          << dx << "," << dy;
    }
  }
}

// A person who stands still long enough looks static; once they walk away the misses through
// their old place must remove them (log-odds, not discarding).
TEST(MotionRemoval, PedestrianPausingThenLeavingIsRemoved) {
  SyntheticWorld world;
  world.addWall({-6.0, 5.0}, {6.0, 5.0});
  std::vector<ScenarioStep> steps;
  const Eigen::Vector2d spot(0.5, 2.5);
  for (int i = 0; i < 400; ++i) {  // 10 s standing while the robot circles slowly in place
    steps.push_back({{{0.0, 0.0}, 0.01 * i}, {Disc{spot, 0.25}}});
  }
  for (int i = 0; i < 120; ++i) {  // walks off to the left
    steps.push_back({{{0.0, 0.0}, 4.0}, {Disc{spot + Eigen::Vector2d(-0.03 * i, 0.0), 0.25}}});
  }
  for (int i = 0; i < 400; ++i) {  // gone; the robot keeps looking
    steps.push_back({{{0.0, 0.0}, 4.0 - 0.005 * i}, {}});
  }
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, steps);
  expectSpotCleared(mapper, spot, 0.25);
}

// A person seen standing from one side only, over too few directions to be widely visible and
// missed in few of them (solid, like a wall), who then leaves while the robot drives on: the rays
// that now cross the spot come from directions the person was never seen from. Vacant, those
// cells anchor nothing; the cells behind them, which the rays cut at the first ones never reach,
// anchor nothing either once most of the blob is seen gone. The wall behind stays.
TEST(MotionRemoval, PersonSeenFromOneSideThenGoneIsRemoved) {
  SyntheticWorld world;
  world.addWall({-10.0, 8.0}, {10.0, 8.0});
  const Eigen::Vector2d spot(0.0, 6.0);
  std::vector<ScenarioStep> steps = driveBy({-3.0, 0.0}, {5.0, 0.0}, 0.0);
  for (ScenarioStep& step : steps) {
    if (step.robot.position.x() < 1.0) step.people = {Disc{spot, 0.25}};
  }
  Mapper mapper(testing::scenarioOptions());
  runScenario(mapper, world, steps);
  expectSpotCleared(mapper, spot, 0.3);
  EXPECT_GT(
      fractionAlong(mapper, {-2.0, 8.0}, {2.0, 8.0}, [](CellClass c) { return isObstacle(c); }),
      0.95);
}

// The control: an office without glass loses nothing.
TEST(MotionRemoval, PlainOfficeKeepsEveryWall) {
  SyntheticWorld world;
  world.addWall({-5.0, -3.0}, {5.0, -3.0});
  world.addWall({5.0, -3.0}, {5.0, 3.0});
  world.addWall({5.0, 3.0}, {-5.0, 3.0});
  world.addWall({-5.0, 3.0}, {-5.0, -3.0});
  world.addWall({-1.0, 1.0}, {1.0, 1.0});  // a desk edge
  Mapper mapper(testing::scenarioOptions());
  const std::vector<TimedScan> scans =
      runScenario(mapper, world, driveBy({-3.5, -1.5}, {3.5, -1.5}, 0.3));
  size_t kept = 0, returns = 0;
  for (const TimedScan& scan : scans) {
    for (RayLabel label : mapper.labelScan(scan, true)) {
      returns += label != RayLabel::kNoReturn;
      kept += label == RayLabel::kKept;
    }
  }
  EXPECT_GT(static_cast<double>(kept) / returns, 0.99);
  EXPECT_EQ(mapper.stats().motion_cells, 0u);
}

}  // namespace
}  // namespace rfm
