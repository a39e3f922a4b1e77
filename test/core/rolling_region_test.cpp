#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/reflectance_field.h"
#include "reflectance_field_map/core/rolling_window.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

namespace rfm {
namespace {

constexpr double kResolution = 0.05;

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

// The global map keeps what it is given on both sides of the origin, tile edges included, and
// knows nothing of cells in tiles it never held, inside its bounds or beyond them.
TEST(GlobalMap2D, GetsWhatWasSetAndUnknownElsewhere) {
  GlobalMap2D map(8);
  const std::map<std::pair<int, int>, CellClass> set = {{{-1, -1}, CellClass::kGlass},
                                                        {{-8, 0}, CellClass::kStatic},
                                                        {{7, 7}, CellClass::kFree},
                                                        {{8, -9}, CellClass::kMotion},
                                                        {{40, 3}, CellClass::kMetal}};
  for (const auto& [cell, value] : set)
    map.set({cell.first, cell.second}, value);
  for (int y = -20; y < 20; ++y) {
    for (int x = -20; x < 60; ++x) {
      const auto it = set.find({x, y});
      const CellClass expected = it == set.end() ? CellClass::kUnknown : it->second;
      ASSERT_EQ(map.get({x, y}), expected) << x << " " << y;
    }
  }
  EXPECT_EQ(map.get({1000, -1000}), CellClass::kUnknown);
  EXPECT_EQ(GlobalMap2D(8).get({0, 0}), CellClass::kUnknown);
}

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
}

// Motion removal trusts the per-tile counts and versions to skip and reuse tiles: the counts
// must match the cells through updates, reverts and scrolling, and every change to a cell's
// summaries must change its tile's version.
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
        default:
          field.applyMiss(cell, bin(rng));
      }
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
