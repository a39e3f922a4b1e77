#include "reflectance_field_map/core/reflectance_field.h"

#include "reflectance_field_map/core/anchor_history.h"
#include "reflectance_field_map/core/detail/slice_writer.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <map>
#include <random>
#include <utility>
#include <vector>

#if defined(__linux__)
#include <sys/mman.h>
#include <unistd.h>
#endif

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

TEST(ReflectanceField, ReflectsNearAnAxisEitherWayAlongIt) {
  ReflectanceField field = smallField();  // 2 deg bins: bin b is centred on 2 b + 1 deg
  const CellIndex cell(1, 1);
  const int slot = field.window().storageIndex(cell);
  const Eigen::Vector2d y_axis(0.0, 1.0);
  const double ten_deg = 10.0 * M_PI / 180.0;
  EXPECT_FALSE(field.reflectsNearAxisAt(slot, y_axis, ten_deg));  // reflects nowhere
  field.applyHit(cell, 22);                                       // 45 deg
  EXPECT_FALSE(field.reflectsNearAxisAt(slot, y_axis, ten_deg));
  EXPECT_TRUE(field.reflectsNearAxisAt(slot, y_axis, 50.0 * M_PI / 180.0));
  field.applyHit(cell, 130);  // 261 deg: 9 deg off -y
  EXPECT_TRUE(field.reflectsNearAxisAt(slot, y_axis, ten_deg));
  EXPECT_FALSE(field.reflectsNearAxisAt(slot, y_axis, 8.0 * M_PI / 180.0));
  EXPECT_FALSE(field.reflectsNearAxisAt(slot, Eigen::Vector2d(1.0, 0.0), ten_deg));
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

// Glass completion asks whether a beam ever ended in a cell, however many went through it since:
// the flag outlives the persistence ticks and the bins' own evidence, until the field is cleared.
TEST(ReflectanceField, RemembersTheCellsEverHitUntilCleared) {
  ReflectanceField field = testing::centredField(2.0);
  const RollingWindow& window = field.window();
  const int hit_once = window.storageIndex({3, 4}), written = window.storageIndex({-5, 7});
  const int missed_only = window.storageIndex({5, 4});
  field.applyHit({3, 4}, 20);
  field.sliceWriter(100, nullptr).hit(written);
  for (int i = 0; i < 10; ++i) {
    field.applyMiss({3, 4}, 20);
    field.sliceWriter(100, nullptr).miss(written);
    field.applyMiss({5, 4}, 20);
  }
  EXPECT_EQ(field.reflectiveBins({3, 4}), 0);  // the bins forgot the hit
  for (const int slot : {hit_once, written}) {
    EXPECT_TRUE(field.everHitAt(slot));
    EXPECT_TRUE(field.hitSinceTick(slot));
  }
  EXPECT_FALSE(field.everHitAt(missed_only));
  EXPECT_FALSE(field.hitSinceTick(missed_only));
  // A persistence tick clears what happened since the last one, not the memory of hits.
  for (const int slot : {hit_once, written}) {
    field.clearSinceTick(slot, 1);
    EXPECT_FALSE(field.hitSinceTick(slot));
    EXPECT_TRUE(field.everHitAt(slot));
  }
  field.clear();
  field.recenter({0.0, 0.0});
  EXPECT_FALSE(field.everHitAt(window.storageIndex({3, 4})));
  EXPECT_FALSE(field.everHitAt(window.storageIndex({-5, 7})));
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

#if defined(__linux__)
// Bytes of [data, data + bytes) the kernel has resident (mincore), to a page.
size_t residentBytes(const void* data, size_t bytes) {
  const size_t page = static_cast<size_t>(sysconf(_SC_PAGESIZE));
  const auto first = reinterpret_cast<uintptr_t>(data) / page * page;
  const size_t pages = (reinterpret_cast<uintptr_t>(data) + bytes - first + page - 1) / page;
  std::vector<unsigned char> resident(pages);
  if (mincore(reinterpret_cast<void*>(first), pages * page, resident.data()) != 0) {
    ADD_FAILURE() << "mincore failed";
    return bytes;
  }
  return page *
         std::count_if(resident.begin(), resident.end(), [](unsigned char r) { return r & 1; });
}

// An array on ordinary pages is resident only around what was written, even where the kernel
// would hand a huge page to the first touch: a big offline window's slices, mostly never reached.
TEST(ZeroedHugeArray, OrdinaryPagesAreResidentOnlyWhereWritten) {
  constexpr size_t kHuge = ZeroedHugeArray<int8_t>::kHugePageBytes;
  ZeroedHugeArray<int8_t> sparse(32 * kHuge, PageKind::kOrdinary);
  for (size_t i = kHuge / 2; i < sparse.size(); i += 4 * kHuge)
    sparse[i] = 1;  // 8 writes, each in a different huge page
  EXPECT_LE(residentBytes(sparse.data(), sparse.size()), 8 * size_t{64} << 10);
  const ZeroedHugeArray<int8_t> small(100, PageKind::kOrdinary);
  EXPECT_EQ(ZeroedHugeArray<int8_t>(small).pages(), PageKind::kOrdinary);  // copies keep it
}

// zeroWhereSet() zeroes an array again whatever was written where, at either side of a page
// boundary too (a large window's cell summaries between batch passes), and the array is usable
// after it.
TEST(ZeroedHugeArray, ZeroWhereSetZeroesEveryWrittenValue) {
  constexpr size_t kHuge = ZeroedHugeArray<uint16_t>::kHugePageBytes;
  ZeroedHugeArray<uint16_t> array(3 * kHuge + 7, PageKind::kOrdinary);
  for (const size_t i : {size_t{0}, size_t{2047}, size_t{2048}, kHuge, array.size() - 1})
    array[i] = 9;
  array.zeroWhereSet();
  EXPECT_EQ(std::count(array.begin(), array.end(), 0), static_cast<long>(array.size()));
  array[5] = 1;  // the array is used again after it
  EXPECT_EQ(std::count(array.begin(), array.end(), 0), static_cast<long>(array.size()) - 1);
  ZeroedHugeArray<uint16_t>().zeroWhereSet();  // an empty array: nothing to do
}

// prefault() brings in every page at once (a live mapper's, before its first scan) and leaves
// the zeros as they were.
TEST(ZeroedHugeArray, PrefaultMakesEveryPageResidentAndKeepsTheZeros) {
  constexpr size_t kHuge = ZeroedHugeArray<int8_t>::kHugePageBytes;
  ZeroedHugeArray<int8_t> array(8 * kHuge + 100, PageKind::kOrdinary);
  ASSERT_LE(residentBytes(array.data(), array.size()), size_t{64} << 10);
  array.prefault();
  EXPECT_GE(residentBytes(array.data(), array.size()), array.size());
  EXPECT_EQ(std::count(array.begin(), array.end(), 0), static_cast<long>(array.size()));
}

// Bytes the process has resident (/proc/self/statm).
size_t residentProcessBytes() {
  std::ifstream statm("/proc/self/statm");
  size_t total_pages = 0, resident_pages = 0;
  statm >> total_pages >> resident_pages;
  return resident_pages * static_cast<size_t>(sysconf(_SC_PAGESIZE));
}

// clear() brings in no page that no ray reached: a large offline window's slices, mostly never
// reached, stay unmapped through the batch's passes, even where rays reached the tile in other
// directions (the campus: each reached tile is reached in a few of its 180 slices).
TEST(ReflectanceField, ClearBringsInNoUnreachedPages) {
  // 127 tiles a side: 709 MiB of slices on ordinary pages.
  ReflectanceField site{GridOptions(), LogOddsOptions(), ActiveRegionOptions(), 50.0};
  site.recenter({0.0, 0.0});
  const CellIndex hit_cell(3, 4), missed_cell(400, -300);  // in different tiles
  for (int bin : {0, 90, 179}) {
    site.applyHit(hit_cell, bin);
    site.applyMiss(missed_cell, bin);
  }
  // One direction in each of 40 x 127 tiles: their other slices' pages (over 200 MiB) unreached.
  const int tile_cells = GridOptions().tile_cells;
  for (int ty = -20; ty < 20; ++ty) {
    for (int tx = -63; tx <= 63; ++tx)
      site.applyHit({tx * tile_cells, ty * tile_cells}, 45);
  }
  const size_t resident_before = residentProcessBytes();
  site.clear();
  EXPECT_LT(residentProcessBytes(), resident_before + (size_t{64} << 20));
  site.recenter({0.0, 0.0});
  for (int bin = 0; bin < 180; ++bin) {
    EXPECT_EQ(site.value(hit_cell, bin), 0) << bin;
    EXPECT_EQ(site.value(missed_cell, bin), 0) << bin;
  }
}
#endif

// A robot-centred window keeps huge pages (fewer page translations for its rays); a window of
// more than 512 MiB of slices, an offline map of a large site, takes ordinary pages.
TEST(ReflectanceField, OnlyLargeWindowsTakeOrdinaryPages) {
  ReflectanceField active{GridOptions(), LogOddsOptions(), ActiveRegionOptions()};
  EXPECT_EQ(active.pages(), PageKind::kHuge);
  // 127 tiles a side: 2032^2 cells x 180 bins = 709 MiB of slices, allocated but never touched.
  ReflectanceField site{GridOptions(), LogOddsOptions(), ActiveRegionOptions(), 50.0};
  EXPECT_EQ(site.pages(), PageKind::kOrdinary);
  site.clear();
  EXPECT_EQ(site.pages(), PageKind::kOrdinary);
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

// Scrolling the active region over the archive.

ReflectanceField makeField(double radius = 2.0) {
  GridOptions grid;
  grid.theta_bins = 36;
  return ReflectanceField(grid, LogOddsOptions(), testing::regionOfRadius(radius));
}

// Writes a value that encodes the cell and bin, so misplaced data is detected.
int8_t signature(const CellIndex& cell, int bin) {
  return static_cast<int8_t>(1 + positiveMod(cell.x() * 7 + cell.y() * 13 + bin * 3, 50));
}

void stampBox(ReflectanceField& field, const CellBox& box) {
  for (int y = box.min.y(); y < box.max.y(); ++y) {
    for (int x = box.min.x(); x < box.max.x(); ++x) {
      for (int bin = 0; bin < 36; bin += 7) {
        for (int k = 0; k < signature({x, y}, bin); ++k)
          field.applyHit({x, y}, bin);
      }
    }
  }
}

// After moves in each direction (and jumps), every cell inside the new window holds exactly
// what was written there (or nothing if never written), and nothing leaks into new cells.
TEST(ReflectanceField, ScrollingKeepsExactlyTheValidCells) {
  ReflectanceField field = makeField();
  field.recenter({0.0, 0.0});
  std::map<std::pair<int, int>, bool> written;
  const CellBox first = field.activeBox();
  stampBox(field, first);
  for (int y = first.min.y(); y < first.max.y(); ++y) {
    for (int x = first.min.x(); x < first.max.x(); ++x)
      written[{x, y}] = true;
  }
  const std::vector<Eigen::Vector2d> moves = {{0.8, 0.0},  {0.0, 0.8},  {-0.8, 0.0},  {0.0, -0.8},
                                              {2.4, -1.6}, {-4.0, 4.0}, {50.0, 50.0}, {0.0, 0.0}};
  for (const Eigen::Vector2d& robot : moves) {
    const WindowShift shift = field.recenter(robot);
    const CellBox box = field.activeBox();
    EXPECT_TRUE(box.contains(field.geometry().cellOf(robot)));
    for (int y = box.min.y(); y < box.max.y(); ++y) {
      for (int x = box.min.x(); x < box.max.x(); ++x) {
        const bool expected = written.count({x, y}) > 0;
        for (int bin = 0; bin < 36; ++bin) {
          const int8_t v = field.value({x, y}, bin);
          if (expected && bin % 7 == 0) {
            int8_t want = 0;
            for (int k = 0; k < signature({x, y}, bin); ++k)
              want = field.logOdds().hit(want);
            ASSERT_EQ(v, want) << "cell " << x << "," << y << " bin " << bin;
          } else {
            ASSERT_EQ(v, 0) << "stale data at " << x << "," << y << " bin " << bin;
          }
        }
      }
    }
    // Newly exposed tiles are reported and lie inside the new window.
    for (const TileIndex& tile : shift.entered)
      EXPECT_FALSE(field.window().tileBox(tile).intersect(box).empty());
  }
}

TEST(ReflectanceField, LeaveAndReturnRestoresEvidenceBitForBit) {
  ReflectanceField field = makeField(3.0);
  field.recenter({0.0, 0.0});
  std::mt19937 rng(1);
  const CellBox box = field.activeBox();
  std::uniform_int_distribution<int> x(box.min.x(), box.max.x() - 1),
      y(box.min.y(), box.max.y() - 1);
  std::uniform_int_distribution<int> bin(0, 35);
  for (int i = 0; i < 50000; ++i) {
    const CellIndex cell(x(rng), y(rng));
    if (rng() % 3 == 0) {
      field.applyHit(cell, bin(rng));
    } else {
      field.applyMiss(cell, bin(rng));
    }
  }
  // Every bin of the box, and each cell's reflective and missed counts.
  auto snapshot = [&](std::vector<int8_t>& bins, std::vector<int>& counts) {
    for (int cy = box.min.y(); cy < box.max.y(); ++cy) {
      for (int cx = box.min.x(); cx < box.max.x(); ++cx) {
        counts.push_back(field.reflectiveBins({cx, cy}) * 1000 + field.missedBins({cx, cy}));
        for (int b = 0; b < 36; ++b)
          bins.push_back(field.value({cx, cy}, b));
      }
    }
  };
  std::vector<int8_t> before;
  std::vector<int> reflective_before;
  snapshot(before, reflective_before);
  field.recenter({40.0, -25.0});  // everything leaves
  EXPECT_GT(field.archivedTiles(), 0u);
  EXPECT_GT(field.archivedBytes(), 0u);
  field.recenter({0.0, 0.0});  // and comes back
  std::vector<int8_t> after;
  std::vector<int> reflective_after;
  snapshot(after, reflective_after);
  EXPECT_EQ(after, before);
  EXPECT_EQ(reflective_after, reflective_before);
  EXPECT_EQ(field.archivedTiles(), 0u);  // restored tiles leave the archive
  // Of the hits, a restored tile remembers those that still show: its reflective cells.
  for (int cy = box.min.y(); cy < box.max.y(); ++cy) {
    for (int cx = box.min.x(); cx < box.max.x(); ++cx) {
      ASSERT_EQ(field.everHitAt(field.window().storageIndex({cx, cy})),
                field.reflectiveBins({cx, cy}) > 0);
    }
  }
}

// Motion removal trusts the per-tile counts and versions to skip and reuse tiles: the counts
// must match the cells through updates, reverts and scrolling, every change to a cell's
// summaries must change its tile's version, and a cell's summaries must be those of its bins.
TEST(ReflectanceField, TileCountsAndVersionsFollowTheSummaries) {
  ReflectanceField field = makeField(3.0);
  const RollingWindow& window = field.window();
  auto check_counts = [&] {
    for (const TileIndex& tile : window.tiles()) {
      const int first = window.tileFirstSlot(tile);
      const int cells = window.tileCells() * window.tileCells();
      int reflective = 0;
      for (int slot = first; slot < first + cells; ++slot)
        reflective += field.anyReflectiveAt(slot);
      ASSERT_EQ(field.tileReflectiveCells(window.storageTile(tile)), reflective)
          << tile.transpose();
    }
  };
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> bin(0, 35);
  for (const Eigen::Vector2d& robot :
       {Eigen::Vector2d(0.0, 0.0), Eigen::Vector2d(0.9, 0.0), Eigen::Vector2d(0.9, -1.7),
        Eigen::Vector2d(40.0, 0.0), Eigen::Vector2d(0.0, 0.0)}) {
    field.recenter(robot);
    check_counts();
    const CellBox box = field.activeBox();
    std::uniform_int_distribution<int> x(box.min.x(), box.max.x() - 1),
        y(box.min.y(), box.max.y() - 1);
    for (int i = 0; i < 20000; ++i) {
      const CellIndex cell(x(rng), y(rng));
      const int slot = window.storageIndex(cell);
      const int tile = slot >> window.tileSlotShift();
      const int reflective = field.reflectiveBinsAt(slot), missed = field.missedBinsAt(slot);
      const uint32_t version = field.tileVersion(tile);
      switch (rng() % 4) {
        case 0:
          field.applyHit(cell, bin(rng));
          break;
        case 1:
          field.revertHitAt(slot, bin(rng));
          break;
        case 2:
          field.revertMissAt(slot, bin(rng));
          break;
        default:
          for (int k = 0; k < 3; ++k)
            field.applyMiss(cell, bin(rng));
      }
      // The cell's summaries are those of its bins (reverts update them incrementally).
      int reflective_bins = 0, missed_bins = 0;
      for (int b = 0; b < field.geometry().thetaBins(); ++b) {
        const int v = field.value(cell, b);
        ASSERT_EQ(field.isReflective(cell, b), v > 0) << b;
        reflective_bins += v > 0;
        missed_bins += v < 0;
      }
      ASSERT_EQ(field.reflectiveBinsAt(slot), reflective_bins);
      ASSERT_EQ(field.missedBinsAt(slot), missed_bins);
      const bool changed =
          field.reflectiveBinsAt(slot) != reflective || field.missedBinsAt(slot) != missed;
      if (changed) {
        ASSERT_NE(field.tileVersion(tile), version);
      }
    }
    check_counts();
  }
  // Clearing changes every version.
  std::vector<uint32_t> versions;
  for (int t = 0; t < window.storageTiles(); ++t)
    versions.push_back(field.tileVersion(t));
  field.clear();
  for (int t = 0; t < window.storageTiles(); ++t) {
    EXPECT_NE(field.tileVersion(t), versions[t]);
    EXPECT_EQ(field.tileReflectiveCells(t), 0);
  }
}

TEST(ReflectanceField, SaveAndReadRoundTrip) {
  ReflectanceField field = makeField();
  field.recenter({1.0, 1.0});
  for (int i = 0; i < 30; ++i)
    field.applyHit({20 + i, 21}, i % 36);
  field.recenter({30.0, 1.0});
  for (int i = 0; i < 30; ++i)
    field.applyMiss({600, 20 + i}, 5);
  std::stringstream state;
  field.write(state);
  ReflectanceField loaded = makeField();
  ASSERT_TRUE(loaded.read(state));
  loaded.recenter({30.0, 1.0});
  EXPECT_LT(loaded.value({600, 25}, 5), 0);
  loaded.recenter({1.0, 1.0});
  EXPECT_GT(loaded.value({25, 21}, 5), 0);
  std::stringstream garbage("not a field");
  EXPECT_FALSE(loaded.read(garbage));
  EXPECT_GT(loaded.value({25, 21}, 5), 0);  // a failed read changes nothing
}

}  // namespace
}  // namespace rfm
