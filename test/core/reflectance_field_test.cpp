#include "reflectance_field_map/core/reflectance_field.h"

#include "reflectance_field_map/core/anchor_history.h"
#include "reflectance_field_map/core/detail/slice_writer.h"

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
  EXPECT_LE(field.activeBytes() + AnchorHistory(field).bytes(), 40u * 1000u * 1000u);
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
