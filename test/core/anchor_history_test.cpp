#include "reflectance_field_map/core/anchor_history.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <limits>
#include <random>
#include <utility>
#include <vector>

namespace rfm {
namespace {

ReflectanceField smallField() {
  return testing::centredField(2.0, GridOptions());
}

// A persistence tick that keeps departure histories of cells with at least
// `remembered_min_bins` reflective bins and certainty histories of cells confirmed for
// `confirmed_min_ticks` ticks (0: none).
void persistenceTick(AnchorHistory& history, ReflectanceField& field,
                     int remembered_min_bins = std::numeric_limits<int>::max(),
                     int confirmed_min_ticks = 0, ParallelRunner* runner = nullptr) {
  AnchorRules rules;
  rules.remembered_min_bins = remembered_min_bins;
  rules.confirmed_min_ticks = confirmed_min_ticks;
  history.tick(field, rules, runner);
}

// Vacancy: ticks over which a remembered cell got new missed bins and no hit. Structure in
// view is hit even where grazing rays pass through its cell; a cell missed only in bins it was
// already missed in shows nothing new; cells without history have none.
TEST(AnchorHistory, VacancyCountsTicksSeenThroughAnewWithoutAHit) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex person(1, 1), wall(5, -5), pane(-3, 2), speck(0, -6);
  for (int bin = 20; bin < 60; ++bin) {
    field.applyHit(person, bin);
    field.applyHit(wall, bin);
  }
  for (int bin = 89; bin < 92; ++bin)
    field.applyHit(pane, bin);
  field.applyMiss(pane, 10);
  field.applyHit(speck, 40);
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  auto vacant = [&](const CellIndex& cell) {
    return history.vacantTicksAt(field.window().storageIndex(cell));
  };
  for (int tick = 1; tick <= 3; ++tick) {
    field.applyMiss(person, 100 + tick);
    field.applyMiss(wall, 100 + tick);
    field.applyHit(wall, 30);
    field.applyMiss(pane, 10);
    field.applyMiss(speck, 100 + tick);
    persistenceTick(history, field, /*remembered_min_bins=*/1000);
    EXPECT_EQ(vacant(person), tick);
    EXPECT_EQ(vacant(wall), 0);
    EXPECT_EQ(vacant(pane), 0);
    EXPECT_EQ(vacant(speck), 0);  // never remembered: too few bins
  }
  persistenceTick(history, field);
  EXPECT_EQ(vacant(person), 3);  // nothing new seen: held
  field.applyHit(person, 30);    // back again
  persistenceTick(history, field);
  EXPECT_EQ(vacant(person), 0);
}

// A cell seen through anew is not vacant where a cell within vacancy_hit_radius of it was hit:
// the side of a round column facing the robot, while it sees through the rim's other cells.
TEST(AnchorHistory, AHitNearbyKeepsACellFromBeingVacant) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex rim(0, 0), far_person(-10, 6), facing(3, -3), far_away(-14, 6);
  for (const CellIndex& cell : {rim, far_person}) {
    for (int bin = 20; bin < 30; ++bin)
      field.applyHit(cell, bin);
  }
  AnchorRules rules;
  rules.remembered_min_bins = 3;
  rules.vacancy_hit_radius = 3;
  history.tick(field, rules);
  for (int tick = 1; tick <= 2; ++tick) {
    field.applyMiss(rim, 100 + tick);
    field.applyMiss(far_person, 100 + tick);
    field.applyHit(facing, 20);    // 3 cells from the rim
    field.applyHit(far_away, 20);  // 4 cells from the person
    history.tick(field, rules);
    EXPECT_EQ(history.vacantTicksAt(field.window().storageIndex(rim)), 0);
    EXPECT_EQ(history.vacantTicksAt(field.window().storageIndex(far_person)), tick);
  }
}

// Vacancy also counts the scans of its ticks, and a hit resets both.
TEST(AnchorHistory, VacancyCountsTheScansOfItsTicks) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex person(1, 1);
  const int slot = field.window().storageIndex(person);
  for (int bin = 20; bin < 30; ++bin)
    field.applyHit(person, bin);
  AnchorRules rules;
  rules.remembered_min_bins = 3;
  history.tick(field, rules, nullptr, /*scans=*/40);
  EXPECT_EQ(history.vacantScansAt(slot), 0);  // hit at that tick
  field.applyMiss(person, 100);
  history.tick(field, rules, nullptr, /*scans=*/40);
  history.tick(field, rules, nullptr, /*scans=*/40);  // nothing new seen: held
  field.applyMiss(person, 101);
  history.tick(field, rules, nullptr, /*scans=*/1);
  EXPECT_EQ(history.vacantTicksAt(slot), 2);
  EXPECT_EQ(history.vacantScansAt(slot), 41);
  for (int i = 0; i < 7; ++i) {
    field.applyMiss(person, 102 + i);
    history.tick(field, rules, nullptr, /*scans=*/40);
  }
  EXPECT_EQ(history.vacantScansAt(slot), 255);  // saturates
  field.applyHit(person, 20);
  history.tick(field, rules, nullptr, /*scans=*/40);
  EXPECT_EQ(history.vacantTicksAt(slot), 0);
  EXPECT_EQ(history.vacantScansAt(slot), 0);
}

// A tile whose cells are none of them reflective any more is ticked in one sweep: its cells
// must still lose their confirmation and their hits since the last tick, as cell by cell.
TEST(AnchorHistory, TickClearsATileWithNoReflectiveCellLeft) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex cell(1, 1);  // alone in its tile
  const int slot = field.window().storageIndex(cell);
  for (int bin = 20; bin < 60; ++bin)
    field.applyHit(cell, bin);
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  EXPECT_EQ(history.confirmedTicksAt(slot), 1);
  const int tile = slot >> field.window().tileSlotShift();

  field.applyHit(cell, 20);  // hit once more, then seen through in every bin
  for (int i = 0; i < 5; ++i) {
    for (int bin = 20; bin < 60; ++bin)
      field.applyMiss(cell, bin);
  }
  ASSERT_EQ(field.tileReflectiveCells(tile), 0);
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  EXPECT_EQ(history.confirmedTicksAt(slot), 0);
  EXPECT_EQ(history.vacantTicksAt(slot), 0);  // hit since the last tick

  field.applyMiss(cell, 100);  // seen through anew, not hit: the hit above is history
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  EXPECT_EQ(history.vacantTicksAt(slot), 1);
}

// Ticks pass over tiles with no hit and no mask change since the last one. A cell that stops
// reflecting through misses alone must still lose its confirmation, beside a cell that holds its
// own, and alone in its tile. The misses take its bins below zero but not to a confident miss,
// so only the mask change marks the tile for the tick.
TEST(AnchorHistory, TickResetsACellThatStoppedReflectingWithoutAHit) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex fading(1, 1), holding(2, 1), alone(-5, -5);
  ASSERT_EQ(field.window().tileOf(fading), field.window().tileOf(holding));
  ASSERT_NE(field.window().tileOf(fading), field.window().tileOf(alone));
  auto ticks = [&](const CellIndex& cell) {
    return history.confirmedTicksAt(field.window().storageIndex(cell));
  };
  for (const CellIndex& cell : {fading, holding, alone}) {
    for (int bin = 20; bin < 60; ++bin)
      field.applyHit(cell, bin);
  }
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  ASSERT_EQ(ticks(fading), 1);
  ASSERT_EQ(ticks(alone), 1);
  for (const CellIndex& cell : {fading, alone}) {
    for (int i = 0; i < 3; ++i) {
      for (int bin = 20; bin < 60; ++bin)
        field.applyMiss(cell, bin);
    }
    ASSERT_EQ(field.reflectiveBins(cell), 0);
    ASSERT_GT(field.value(cell, 20), field.confidentMissValue());
  }
  persistenceTick(history, field, /*remembered_min_bins=*/3);
  EXPECT_EQ(ticks(fading), 0);
  EXPECT_EQ(ticks(alone), 0);
  EXPECT_EQ(ticks(holding), 1);  // not hit since: held
}

// Abandonment: ticks over which a long-confirmed cell was missed in a bin it had been certain
// in, and hit nowhere. Glass seen through at the edge of its lobe and structure still hit are
// not abandoned; cells never confirmed have no such history.
TEST(AnchorHistory, AbandonmentCountsTicksMissedWhereACellWasCertainWithoutAHit) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex person(1, 1), pane(-3, 2), wall(5, -5), speck(0, -6);
  constexpr int kConfirmed = 2;
  auto tick_now = [&] {
    persistenceTick(history, field, /*remembered_min_bins=*/1000, kConfirmed);
  };
  for (int t = 0; t <= kConfirmed; ++t) {  // hit at every tick: confirmed, certain
    for (int i = 0; i < 6; ++i) {
      for (int bin = 40; bin < 60; ++bin)
        field.applyHit(person, bin);
      for (int bin = 20; bin < 30; ++bin)
        field.applyHit(wall, bin);
      field.applyHit(pane, 90);
    }
    field.applyHit(pane, 92);  // the lobe's edge: returns only now and then
    tick_now();
  }
  for (int i = 0; i < 6; ++i)
    field.applyHit(speck, 40);
  tick_now();
  auto abandoned = [&](const CellIndex& cell) {
    return history.abandonedTicksAt(field.window().storageIndex(cell));
  };
  for (int t = 1; t <= 3; ++t) {
    field.applyMiss(person, 45);  // the person left: the robot looks through where they stood
    field.applyMiss(pane, 92);
    field.applyMiss(pane, 120);
    field.applyMiss(wall, 25);  // a ray grazing through the wall's cell, which stays in view
    field.applyHit(wall, 26);
    field.applyMiss(speck, 40);
    tick_now();
    EXPECT_EQ(abandoned(person), t);
    EXPECT_EQ(abandoned(pane), 0);
    EXPECT_EQ(abandoned(wall), 0);
    EXPECT_EQ(abandoned(speck), 0);  // never confirmed
  }
  tick_now();
  EXPECT_EQ(abandoned(person), 3);  // not looked at: held
  field.applyHit(person, 50);
  tick_now();
  EXPECT_EQ(abandoned(person), 0);
}

// The tick splits its work between threads, which collect the histories to create and drop for
// the caller: on two threads every cell must end with the histories of a tick on one thread.
// Cells all over the window stand still for six ticks (remembered, confirmed, certain), then are
// looked through until they reflect nowhere (abandoned, dropped, vacant), among random updates.
TEST(AnchorHistory, TickOnThreadsKeepsTheHistoriesOfOneThread) {
  GridOptions grid;
  ReflectanceField alone = testing::centredField(6.0, grid);  // about 200 tiles
  ReflectanceField shared = testing::centredField(6.0, grid);
  AnchorHistory alone_history(alone), shared_history(shared);
  ParallelRunner runner(2);
  std::mt19937 rng(11);
  const CellBox box = alone.activeBox();
  std::uniform_int_distribution<int> x(box.min.x(), box.max.x() - 1),
      y(box.min.y(), box.max.y() - 1);
  std::uniform_int_distribution<int> bin(0, 179);
  std::vector<std::pair<CellIndex, int>> standing;  // cell, first of its 5 reflective bins
  for (int i = 0; i < 2000; ++i)
    standing.emplace_back(CellIndex(x(rng), y(rng)), bin(rng));
  auto update = [&](const CellIndex& cell, int b, bool hit) {
    for (ReflectanceField* field : {&alone, &shared}) {
      if (hit) {
        field->applyHit(cell, b % 180);
      } else {
        field->applyMiss(cell, b % 180);
      }
    }
  };
  constexpr int kRemembered = 3, kConfirmed = 2;
  size_t abandoned = 0, vacant = 0, dropped = 0;
  for (int tick = 0; tick < 12; ++tick) {
    for (const auto& [cell, first_bin] : standing) {
      for (int b = first_bin; b < first_bin + 5; ++b) {
        for (int repeat = 0; repeat < 4; ++repeat)
          update(cell, b, /*hit=*/tick < 6);
      }
    }
    for (int i = 0; i < 4000; ++i)
      update(CellIndex(x(rng), y(rng)), bin(rng), /*hit=*/i % 3 == 0);
    persistenceTick(alone_history, alone, kRemembered, kConfirmed);
    persistenceTick(shared_history, shared, kRemembered, kConfirmed, &runner);
    const int slots = alone.window().sizeCells() * alone.window().sizeCells();
    for (int slot = 0; slot < slots; ++slot) {
      ASSERT_EQ(shared_history.confirmedTicksAt(slot), alone_history.confirmedTicksAt(slot));
      ASSERT_EQ(shared_history.vacantTicksAt(slot), alone_history.vacantTicksAt(slot));
      ASSERT_EQ(shared_history.contradictedBinsAt(shared, slot),
                alone_history.contradictedBinsAt(alone, slot));
      ASSERT_EQ(shared_history.abandonedTicksAt(slot), alone_history.abandonedTicksAt(slot));
    }
    // The histories were there to compare.
    for (const auto& standing_cell : standing) {
      const int slot = alone.window().storageIndex(standing_cell.first);
      abandoned += tick == 7 && alone_history.abandonedTicksAt(slot) > 0;
      dropped += tick == 8 && alone_history.abandonedTicksAt(slot) == 0;  // no reflective bin left
      vacant += tick == 9 && alone_history.vacantTicksAt(slot) > 0;
    }
  }
  EXPECT_GT(abandoned, 1000u);
  EXPECT_GT(vacant, 1000u);
  EXPECT_GT(dropped, 1000u);
}

// A departure: bins that reflected at a tick and are now confidently missed. Seen through only
// in other directions (glass), or missed but not confidently where it reflected (a wall a few
// rays grazed), is no departure, and small cells keep no history.
TEST(AnchorHistory, ContradictedBinsAreFormerlyReflectiveBinsNowSeenThrough) {
  ReflectanceField field = smallField();
  AnchorHistory history(field);
  const CellIndex person(1, 1), pane(-3, 2), wall(5, -5), speck(0, -6);
  for (int bin = 20; bin < 60; ++bin) {
    for (int i = 0; i < 5; ++i) {
      field.applyHit(person, bin);
      field.applyHit(wall, bin);
    }
  }
  for (int i = 0; i < 5; ++i)
    field.applyHit(pane, 90);
  persistenceTick(history, field, /*remembered_min_bins=*/1);
  for (int bin = 0; bin < 180; ++bin) {  // the pane is seen through away from its normal
    if (std::abs(bin - 90) > 2) field.applyMiss(pane, bin);
  }
  for (int i = 0; i < 5; ++i)
    field.applyHit(speck, 40);
  persistenceTick(history, field, /*remembered_min_bins=*/5);  // the speck is too small to remember
  for (int i = 0; i < 20; ++i) {
    for (int bin = 40; bin < 44; ++bin) {  // the person has left: rays pass where they reflected
      field.applyMiss(person, bin);
      field.applyMiss(speck, bin);
    }
    field.applyMiss(person, 100);  // and beyond, which says nothing about a departure
  }
  for (int i = 0; i < 11; ++i)  // the wall missed where it reflected, but not confidently
    field.applyMiss(wall, 45);
  ASSERT_LT(field.value(wall, 45), 0);
  ASSERT_GT(field.value(wall, 45), field.confidentMissValue());
  const ReflectanceField& f = field;
  auto contradicted = [&](const CellIndex& c) {
    return history.contradictedBinsAt(f, f.window().storageIndex(c));
  };
  EXPECT_EQ(contradicted(person), 4);
  EXPECT_EQ(contradicted(pane), 0);
  EXPECT_EQ(contradicted(wall), 0);
  EXPECT_EQ(contradicted(speck), 0);
  field.clear();
  history.clear();
  EXPECT_EQ(contradicted(person), 0);
}

}  // namespace
}  // namespace rfm
