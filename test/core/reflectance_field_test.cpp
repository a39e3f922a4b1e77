#include "reflectance_field_map/core/reflectance_field.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <random>
#include <utility>
#include <vector>

namespace rfm {
namespace {

ReflectanceField smallField(int theta_bins = 180) {
  GridOptions grid;
  grid.theta_bins = theta_bins;
  return testing::centredField(2.0, grid);
}

TEST(LogOddsModel, QuantisedUpdatesClampAtTheLimits) {
  LogOddsOptions options;  // hit 0.85, miss -0.4, clamp [-2, 3.5]
  const LogOddsModel model(options);
  EXPECT_EQ(model.hitStep(), 14);  // 0.85 * 16 rounded
  EXPECT_EQ(model.missStep(), -6);
  int8_t v = 0;
  v = model.hit(v);
  EXPECT_NEAR(LogOddsModel::toLogOdds(v), 0.875, 1e-9);
  EXPECT_GT(LogOddsModel::toProbability(v), 0.7);
  for (int i = 0; i < 100; ++i)
    v = model.hit(v);
  EXPECT_EQ(v, model.maxValue());
  EXPECT_NEAR(LogOddsModel::toLogOdds(v), 3.5, 1e-9);
  for (int i = 0; i < 100; ++i)
    v = model.miss(v);
  EXPECT_EQ(v, model.minValue());
  EXPECT_NEAR(LogOddsModel::toLogOdds(v), -2.0, 1e-9);
  EXPECT_NEAR(LogOddsModel::toProbability(0), 0.5, 1e-12);
  EXPECT_NEAR(model.odds(0), 1.0f, 1e-6);
}

TEST(ReflectanceField, BayesUpdatesPerBinAndSummaries) {
  ReflectanceField field = smallField();
  const CellIndex cell(3, -4);
  field.applyHit(cell, 10);
  EXPECT_GT(field.value(cell, 10), 0);
  EXPECT_EQ(field.value(cell, 11), 0);  // other directions untouched
  EXPECT_TRUE(field.isReflective(cell, 10));
  EXPECT_EQ(field.reflectiveBins(cell), 1);
  EXPECT_EQ(field.missedBins(cell), 0);
  // One hit outweighs two misses (0.875 - 2 * 0.375 > 0), three flip it.
  field.applyMiss(cell, 10);
  field.applyMiss(cell, 10);
  EXPECT_TRUE(field.isReflective(cell, 10));
  field.applyMiss(cell, 10);
  EXPECT_FALSE(field.isReflective(cell, 10));
  EXPECT_EQ(field.reflectiveBins(cell), 0);
  EXPECT_EQ(field.missedBins(cell), 1);
  field.applyMiss(cell, 179);
  EXPECT_EQ(field.missedBins(cell), 2);
}

// Vacancy: ticks over which a remembered cell got new missed bins and no hit. Structure in
// view is hit even where grazing rays pass through its cell; a cell missed only in bins it was
// already missed in shows nothing new; cells without history have none.
TEST(ReflectanceField, VacancyCountsTicksSeenThroughAnewWithoutAHit) {
  ReflectanceField field = smallField();
  const CellIndex person(1, 1), wall(5, -5), pane(-3, 2), speck(0, -6);
  for (int bin = 20; bin < 60; ++bin) {
    field.applyHit(person, bin);
    field.applyHit(wall, bin);
  }
  for (int bin = 89; bin < 92; ++bin)
    field.applyHit(pane, bin);
  field.applyMiss(pane, 10);
  field.applyHit(speck, 40);
  field.tickPersistence(/*remembered_min_bins=*/3);
  auto vacant = [&](const CellIndex& cell) {
    return field.vacantTicksAt(field.window().storageIndex(cell));
  };
  for (int tick = 1; tick <= 3; ++tick) {
    field.applyMiss(person, 100 + tick);
    field.applyMiss(wall, 100 + tick);
    field.applyHit(wall, 30);
    field.applyMiss(pane, 10);
    field.applyMiss(speck, 100 + tick);
    field.tickPersistence(/*remembered_min_bins=*/1000);
    EXPECT_EQ(vacant(person), tick);
    EXPECT_EQ(vacant(wall), 0);
    EXPECT_EQ(vacant(pane), 0);
    EXPECT_EQ(vacant(speck), 0);  // never remembered: too few bins
  }
  field.tickPersistence();
  EXPECT_EQ(vacant(person), 3);  // nothing new seen: held
  field.applyHit(person, 30);    // back again
  field.tickPersistence();
  EXPECT_EQ(vacant(person), 0);
}

// A tile whose cells are none of them reflective any more is ticked in one sweep: its cells
// must still lose their confirmation and their hits since the last tick, as cell by cell.
TEST(ReflectanceField, TickClearsATileWithNoReflectiveCellLeft) {
  ReflectanceField field = smallField();
  const CellIndex cell(1, 1);  // alone in its tile
  const int slot = field.window().storageIndex(cell);
  for (int bin = 20; bin < 60; ++bin)
    field.applyHit(cell, bin);
  field.tickPersistence(/*remembered_min_bins=*/3);
  EXPECT_EQ(field.confirmedTicksAt(slot), 1);
  const int tile = slot >> field.window().tileSlotShift();

  field.applyHit(cell, 20);  // hit once more, then seen through in every bin
  for (int i = 0; i < 5; ++i) {
    for (int bin = 20; bin < 60; ++bin)
      field.applyMiss(cell, bin);
  }
  ASSERT_EQ(field.tileReflectiveCells(tile), 0);
  field.tickPersistence(/*remembered_min_bins=*/3);
  EXPECT_EQ(field.confirmedTicksAt(slot), 0);
  EXPECT_EQ(field.vacantTicksAt(slot), 0);  // hit since the last tick

  field.applyMiss(cell, 100);  // seen through anew, not hit: the hit above is history
  field.tickPersistence(/*remembered_min_bins=*/3);
  EXPECT_EQ(field.vacantTicksAt(slot), 1);
}

// Ticks pass over tiles with no hit and no mask change since the last one. A cell that stops
// reflecting through misses alone must still lose its confirmation, beside a cell that holds its
// own, and alone in its tile.
TEST(ReflectanceField, TickResetsACellThatStoppedReflectingWithoutAHit) {
  ReflectanceField field = smallField();
  const CellIndex fading(1, 1), holding(2, 1), alone(-5, -5);
  ASSERT_EQ(field.window().tileOf(fading), field.window().tileOf(holding));
  ASSERT_NE(field.window().tileOf(fading), field.window().tileOf(alone));
  auto ticks = [&](const CellIndex& cell) {
    return field.confirmedTicksAt(field.window().storageIndex(cell));
  };
  for (const CellIndex& cell : {fading, holding, alone}) {
    for (int bin = 20; bin < 60; ++bin)
      field.applyHit(cell, bin);
  }
  field.tickPersistence(/*remembered_min_bins=*/3);
  ASSERT_EQ(ticks(fading), 1);
  ASSERT_EQ(ticks(alone), 1);
  for (const CellIndex& cell : {fading, alone}) {
    for (int i = 0; i < 5; ++i) {
      for (int bin = 20; bin < 60; ++bin)
        field.applyMiss(cell, bin);
    }
    ASSERT_EQ(field.reflectiveBins(cell), 0);
  }
  field.tickPersistence(/*remembered_min_bins=*/3);
  EXPECT_EQ(ticks(fading), 0);
  EXPECT_EQ(ticks(alone), 0);
  EXPECT_EQ(ticks(holding), 1);  // not hit since: held
}

// Abandonment: ticks over which a long-confirmed cell was missed in a bin it had been certain
// in, and hit nowhere. Glass seen through at the edge of its lobe and structure still hit are
// not abandoned; cells never confirmed have no such history.
TEST(ReflectanceField, AbandonmentCountsTicksMissedWhereACellWasCertainWithoutAHit) {
  ReflectanceField field = smallField();
  const CellIndex person(1, 1), pane(-3, 2), wall(5, -5), speck(0, -6);
  constexpr int kConfirmed = 2;
  auto tick = [&] { field.tickPersistence(/*remembered_min_bins=*/1000, kConfirmed); };
  for (int t = 0; t <= kConfirmed; ++t) {  // hit at every tick: confirmed, certain
    for (int i = 0; i < 6; ++i) {
      for (int bin = 40; bin < 60; ++bin)
        field.applyHit(person, bin);
      for (int bin = 20; bin < 30; ++bin)
        field.applyHit(wall, bin);
      field.applyHit(pane, 90);
    }
    field.applyHit(pane, 92);  // the lobe's edge: returns only now and then
    tick();
  }
  for (int i = 0; i < 6; ++i)
    field.applyHit(speck, 40);
  tick();
  auto abandoned = [&](const CellIndex& cell) {
    return field.abandonedTicksAt(field.window().storageIndex(cell));
  };
  for (int t = 1; t <= 3; ++t) {
    field.applyMiss(person, 45);  // the person left: the robot looks through where they stood
    field.applyMiss(pane, 92);
    field.applyMiss(pane, 120);
    field.applyMiss(wall, 25);  // a ray grazing through the wall's cell, which stays in view
    field.applyHit(wall, 26);
    field.applyMiss(speck, 40);
    tick();
    EXPECT_EQ(abandoned(person), t);
    EXPECT_EQ(abandoned(pane), 0);
    EXPECT_EQ(abandoned(wall), 0);
    EXPECT_EQ(abandoned(speck), 0);  // never confirmed
  }
  tick();
  EXPECT_EQ(abandoned(person), 3);  // not looked at: held
  field.applyHit(person, 50);
  tick();
  EXPECT_EQ(abandoned(person), 0);
}

// The tick splits its work between threads, which collect the histories to create and drop for
// the caller: on two threads every cell must end with the histories of a tick on one thread.
// Cells all over the window stand still for six ticks (remembered, confirmed, certain), then are
// looked through until they reflect nowhere (abandoned, dropped, vacant), among random updates.
TEST(ReflectanceField, TickOnThreadsKeepsTheHistoriesOfOneThread) {
  GridOptions grid;
  ReflectanceField alone = testing::centredField(6.0, grid);  // about 200 tiles
  ReflectanceField shared = testing::centredField(6.0, grid);
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
    alone.tickPersistence(kRemembered, kConfirmed);
    shared.tickPersistence(kRemembered, kConfirmed, &runner);
    const int slots = alone.window().sizeCells() * alone.window().sizeCells();
    for (int slot = 0; slot < slots; ++slot) {
      ASSERT_EQ(shared.confirmedTicksAt(slot), alone.confirmedTicksAt(slot));
      ASSERT_EQ(shared.vacantTicksAt(slot), alone.vacantTicksAt(slot));
      ASSERT_EQ(shared.contradictedBinsAt(slot), alone.contradictedBinsAt(slot));
      ASSERT_EQ(shared.abandonedTicksAt(slot), alone.abandonedTicksAt(slot));
    }
    // The histories were there to compare.
    for (const auto& standing_cell : standing) {
      const int slot = alone.window().storageIndex(standing_cell.first);
      abandoned += tick == 7 && alone.abandonedTicksAt(slot) > 0;
      dropped += tick == 8 && alone.abandonedTicksAt(slot) == 0;  // no reflective bin left
      vacant += tick == 9 && alone.vacantTicksAt(slot) > 0;
    }
  }
  EXPECT_GT(abandoned, 1000u);
  EXPECT_GT(vacant, 1000u);
  EXPECT_GT(dropped, 1000u);
}

// A departure: bins that reflected at a tick and are now confidently missed. Seen through only
// in other directions (glass) or never (a wall) is no departure, and small cells keep no history.
TEST(ReflectanceField, ContradictedBinsAreFormerlyReflectiveBinsNowSeenThrough) {
  ReflectanceField field = smallField();
  const CellIndex person(1, 1), pane(-3, 2), wall(5, -5), speck(0, -6);
  for (int bin = 20; bin < 60; ++bin) {
    for (int i = 0; i < 5; ++i) {
      field.applyHit(person, bin);
      field.applyHit(wall, bin);
    }
  }
  for (int i = 0; i < 5; ++i)
    field.applyHit(pane, 90);
  field.tickPersistence(/*remembered_min_bins=*/1);
  for (int bin = 0; bin < 180; ++bin) {  // the pane is seen through away from its normal
    if (std::abs(bin - 90) > 2) field.applyMiss(pane, bin);
  }
  for (int i = 0; i < 5; ++i)
    field.applyHit(speck, 40);
  field.tickPersistence(/*remembered_min_bins=*/5);  // the speck is too small to remember
  for (int i = 0; i < 20; ++i) {
    for (int bin = 40; bin < 44; ++bin) {  // the person has left: rays pass where they reflected
      field.applyMiss(person, bin);
      field.applyMiss(speck, bin);
    }
    field.applyMiss(person, 100);  // and beyond, which says nothing about a departure
  }
  field.applyMiss(wall, 45);  // once: not confident
  field.applyMiss(wall, 45);
  field.applyMiss(wall, 45);
  const ReflectanceField& f = field;
  auto contradicted = [&](const CellIndex& c) {
    return f.contradictedBinsAt(f.window().storageIndex(c));
  };
  EXPECT_EQ(contradicted(person), 4);
  EXPECT_EQ(contradicted(pane), 0);
  EXPECT_EQ(contradicted(wall), 0);
  EXPECT_EQ(contradicted(speck), 0);
  field.clear();
  EXPECT_EQ(contradicted(person), 0);
}

TEST(ReflectanceField, ClearPutsEveryBinBackAtThePrior) {
  ReflectanceField field = smallField();
  const CellIndex cell(3, 4);
  for (int bin : {0, 90, 179}) {
    field.applyHit(cell, bin);
    field.applyMiss({5, 4}, bin);
  }
  field.clear();
  field.recenter({0.0, 0.0});  // a cleared field is placed afresh
  for (int bin = 0; bin < 180; ++bin) {
    EXPECT_EQ(field.value(cell, bin), 0) << bin;
    EXPECT_EQ(field.value({5, 4}, bin), 0) << bin;
  }
  EXPECT_EQ(field.reflectiveBins(cell), 0);
  EXPECT_EQ(field.missedBins({5, 4}), 0);
}

TEST(ReflectanceField, SummariesMatchBinsAfterRandomUpdates) {
  ReflectanceField field = smallField();
  std::mt19937 rng(5);
  const CellBox box = field.activeBox();
  std::uniform_int_distribution<int> x(box.min.x(), box.max.x() - 1),
      y(box.min.y(), box.max.y() - 1);
  std::uniform_int_distribution<int> bin(0, 179), coin(0, 2);
  for (int i = 0; i < 200000; ++i) {
    const CellIndex cell(x(rng) % 8, y(rng) % 8);
    if (coin(rng) == 0) {
      field.applyHit(cell, bin(rng));
    } else {
      field.applyMiss(cell, bin(rng));
    }
  }
  for (int cy = -7; cy < 8; ++cy) {
    for (int cx = -7; cx < 8; ++cx) {
      int reflective = 0, missed = 0;
      double marginal = 0.0, reflective_odds = 0.0;
      for (int b = 0; b < 180; ++b) {
        const int8_t v = field.value({cx, cy}, b);
        reflective += v > 0;
        missed += v < 0;
        marginal += std::exp(LogOddsModel::toLogOdds(v)) * field.geometry().binWidth();
        if (v > 0) reflective_odds += std::exp(LogOddsModel::toLogOdds(v));
        ASSERT_EQ(field.isReflective({cx, cy}, b), v > 0);
      }
      ASSERT_EQ(field.reflectiveBins({cx, cy}), reflective);
      ASSERT_EQ(field.anyReflectiveAt(field.window().storageIndex({cx, cy})), reflective > 0);
      ASSERT_EQ(field.missedBins({cx, cy}), missed);
      ASSERT_NEAR(field.marginalOdds({cx, cy}), marginal, 1e-3 * marginal);
      const int slot = field.window().storageIndex({cx, cy});
      ASSERT_NEAR(field.reflectiveOddsAt(slot), reflective_odds, 1e-3 * reflective_odds + 1e-9);
    }
  }
}

// The slice writers decide with one range test whether an update can cross the prior: with
// steps smaller than, equal to and larger than the clamps, applied at once or deferred, the
// summaries must still match the bins.
TEST(ReflectanceField, SliceWriterSummariesMatchBinsForAnyStepsAndClamps) {
  struct Steps {
    double hit, miss, min, max;
  };
  for (const Steps& steps : {Steps{0.85, -0.4, -2.0, 3.5}, Steps{0.0625, -0.0625, -0.0625, 0.0625},
                             Steps{7.9375, -7.9375, -0.5, 0.25}, Steps{0.25, -1.0, -7.9375, 7.9375},
                             Steps{1.0, -0.125, -1.0, 1.0}}) {
    LogOddsOptions log_odds;
    log_odds.log_odds_hit = steps.hit;
    log_odds.log_odds_miss = steps.miss;
    log_odds.log_odds_min = steps.min;
    log_odds.log_odds_max = steps.max;
    ReflectanceField field(GridOptions(), log_odds, testing::regionOfRadius(2.0));
    field.recenter({0.0, 0.0});
    std::mt19937 rng(11);
    // Cells in four tiles along each axis, so the deferred changes fill all four lists.
    constexpr int kCoordinates[] = {-20, -17, -3, -1, 0, 2, 17, 19};
    std::uniform_int_distribution<int> coordinate(0, 7), bin(0, 179), coin(0, 2);
    ParallelRunner runner(2);
    // Two writers' changes (each bin has one writer, as in the inserter), each in four lists
    // by tile, applied on two threads. The writers defer twice: applying empties them.
    std::vector<ReflectanceField::DeferredSummaries> changes(
        2, ReflectanceField::DeferredSummaries(4));
    for (const bool deferred : {false, true, true}) {
      for (ReflectanceField::DeferredSummaries& writer : changes)
        writer.clear();
      for (int i = 0; i < 100000; ++i) {
        const int slot = field.window().storageIndex(
            {kCoordinates[coordinate(rng)], kCoordinates[coordinate(rng)]});
        const int b = bin(rng);
        auto writer = field.sliceWriter(b, deferred ? &changes[b % 2] : nullptr);
        if (coin(rng) == 0) {
          writer.hit(slot);
        } else {
          writer.miss(slot);
        }
      }
      field.applySummaryChanges(changes, &runner);
    }
    for (const int cy : kCoordinates) {
      for (const int cx : kCoordinates) {
        int reflective = 0, missed = 0;
        for (int b = 0; b < 180; ++b) {
          const int8_t v = field.value({cx, cy}, b);
          reflective += v > 0;
          missed += v < 0;
          ASSERT_EQ(field.isReflective({cx, cy}, b), v > 0) << "hit step " << steps.hit;
        }
        ASSERT_EQ(field.reflectiveBins({cx, cy}), reflective) << "hit step " << steps.hit;
        ASSERT_EQ(field.missedBins({cx, cy}), missed) << "hit step " << steps.hit;
      }
    }
  }
}

// Online reflection removal takes evidence back; clamping means a miss at the lower clamp
// changed nothing, so reverts stop at the prior instead of inventing the opposite evidence.
TEST(ReflectanceField, RevertsMoveTowardsThePriorAndNeverPastIt) {
  ReflectanceField field = smallField();
  const CellIndex cell(2, 2);
  const int slot = field.window().storageIndex(cell);
  for (int i = 0; i < 20; ++i)
    field.applyMiss(cell, 7);  // clamped at the minimum
  for (int i = 0; i < 20; ++i)
    field.revertMissAt(slot, 7);
  EXPECT_EQ(field.value(cell, 7), 0);
  EXPECT_FALSE(field.isReflective(cell, 7));
  EXPECT_EQ(field.missedBins(cell), 0);
  field.applyHit(cell, 8);
  field.applyMiss(cell, 8);
  field.revertMissAt(slot, 8);  // exact when nothing was clamped
  EXPECT_EQ(field.value(cell, 8), field.logOdds().hit(0));
  for (int i = 0; i < 5; ++i)
    field.revertHitAt(slot, 8);
  EXPECT_EQ(field.value(cell, 8), 0);
  EXPECT_EQ(field.reflectiveBins(cell), 0);
}

TEST(ReflectanceField, UnobservedCellHasPriorMarginalOddsOfTwoPi) {
  ReflectanceField field = smallField();
  EXPECT_NEAR(field.marginalOdds({1, 1}), kTwoPi, 1e-4);
}

TEST(ReflectanceField, DefaultActiveRegionFitsInFortyMegabytes) {
  ReflectanceField field{GridOptions(), LogOddsOptions(), ActiveRegionOptions()};
  EXPECT_EQ(field.window().sizeCells(), 27 * 16);  // 10 m each way from anywhere in the centre tile
  EXPECT_LE(field.activeBytes(), 40u * 1000u * 1000u);
}

// The field's slices and masks live in these arrays: zero without being written, whatever their
// size, and they hold what is written; copies are deep, a moved-from array is empty.
TEST(ZeroedHugeArray, StartsZeroAndHoldsWhatIsWritten) {
  constexpr size_t kHuge = ZeroedHugeArray<int8_t>::kHugePageBytes;
  ZeroedHugeArray<int8_t> large(3 * kHuge + 12345);
  ASSERT_EQ(large.size(), 3 * kHuge + 12345);
  EXPECT_EQ(std::count(large.begin(), large.end(), 0), static_cast<long>(large.size()));
  large[large.size() - 1] = 7;
  large[kHuge] = -3;
  EXPECT_EQ(std::count(large.begin(), large.end(), 0), static_cast<long>(large.size()) - 2);

  ZeroedHugeArray<uint64_t> small(100);
  EXPECT_EQ(std::count(small.begin(), small.end(), 0u), 100);
  small[99] = 5;
  const ZeroedHugeArray<uint64_t> copy = small;
  small[99] = 6;
  EXPECT_EQ(copy[99], 5u);
  ZeroedHugeArray<uint64_t> moved = std::move(small);
  EXPECT_EQ(moved[99], 6u);
  EXPECT_EQ(small.size(), 0u);  // NOLINT: the moved-from state is specified
  EXPECT_EQ(ZeroedHugeArray<int8_t>().size(), 0u);
}

TEST(TileArchive, CompressionRoundTripsEveryPattern) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 200; ++trial) {
    std::vector<int8_t> bins(16 * 16 * 180);
    const int density = trial % 10;
    for (int8_t& v : bins) {
      if (static_cast<int>(rng() % 10) < density)
        v = static_cast<int8_t>(static_cast<int>(rng() % 255) - 127);
    }
    const std::vector<uint8_t> packed = compressBins(bins.data(), bins.size());
    std::vector<int8_t> restored(bins.size(), 42);
    ASSERT_TRUE(decompressBins(packed, restored.data(), restored.size()));
    ASSERT_EQ(restored, bins);
    if (density == 0) {
      EXPECT_LT(packed.size(), bins.size() / 100);
    }
  }
  std::vector<int8_t> out(10);
  EXPECT_FALSE(decompressBins({200}, out.data(), out.size()));   // run past the end
  EXPECT_FALSE(decompressBins({5, 1}, out.data(), out.size()));  // truncated literals
}

}  // namespace
}  // namespace rfm
