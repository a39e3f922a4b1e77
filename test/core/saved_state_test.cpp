// Reading a saved state trusts nothing in it: the envelope (version, length, checksum), the global
// map's tiles and the field's archive entries are each checked before anything is allocated
// for them, and a refused read leaves what it was reading into unchanged.
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/state_file.h"
#include "reflectance_field_map/core/tile_archive.h"

#include <gtest/gtest.h>

#include <cstring>
#include <sstream>
#include <string>
#include <vector>

namespace rfm {
namespace {

template <typename T>
void put(std::string& out, T value) {
  out.append(reinterpret_cast<const char*>(&value), sizeof(value));
}

std::string envelope(const std::string& payload) {
  std::ostringstream out;
  writeStateFile(out, payload);
  return out.str();
}

bool readEnvelope(const std::string& bytes, std::string& payload, std::string& error,
                  uint64_t limit = 1 << 20) {
  std::istringstream in(bytes);
  return readStateFile(in, limit, payload, &error);
}

TEST(StateFile, RoundTripsItsPayload) {
  const std::string payload = "RFMS and then the map and the field \x01\x02\x03";
  std::string read, error;
  ASSERT_TRUE(readEnvelope(envelope(payload), read, error)) << error;
  EXPECT_EQ(read, payload);
  EXPECT_EQ(envelope(payload).size(), kStateFileHeaderBytes + payload.size());
}

TEST(StateFile, RefusesAFlippedByteAnywhere) {
  const std::string good = envelope(std::string(300, 'x') + "tail");
  for (size_t at = kStateFileHeaderBytes; at < good.size(); at += 37) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x10);
    std::string read, error;
    EXPECT_FALSE(readEnvelope(bad, read, error)) << "byte " << at;
    EXPECT_NE(error.find("checksum"), std::string::npos) << error;
    EXPECT_TRUE(read.empty());
  }
}

TEST(StateFile, RefusesTruncationTrailingDataAndForeignFiles) {
  const std::string good = envelope(std::string(5000, 'y'));
  std::string read, error;
  EXPECT_FALSE(readEnvelope(good.substr(0, good.size() - 1), read, error));
  EXPECT_NE(error.find("truncated"), std::string::npos) << error;
  EXPECT_FALSE(readEnvelope(good.substr(0, 10), read, error));
  EXPECT_NE(error.find("too short"), std::string::npos) << error;
  EXPECT_FALSE(readEnvelope(good + "z", read, error));
  EXPECT_NE(error.find("after the end"), std::string::npos) << error;
  EXPECT_FALSE(readEnvelope(std::string(64, 'q'), read, error));
  EXPECT_NE(error.find("not a saved rfm state"), std::string::npos) << error;
  // A state saved before the envelope existed starts with the mapper's own magic.
  std::string legacy;
  put<uint32_t>(legacy, 0x52464d53);
  legacy += std::string(60, '\0');
  EXPECT_FALSE(readEnvelope(legacy, read, error));
  EXPECT_NE(error.find("older version"), std::string::npos) << error;
  std::string future = good;
  future[8] = 9;
  EXPECT_FALSE(readEnvelope(future, read, error));
  EXPECT_NE(error.find("version 9"), std::string::npos) << error;
}

// An 80-byte file whose header claims 2^62 bytes: refused by the limit before any allocation,
// and below the limit it costs no more than the bytes that are there.
TEST(StateFile, AForgedLengthAllocatesNothing) {
  std::string forged = envelope("");
  const uint64_t huge = uint64_t{1} << 62;
  std::memcpy(&forged[16], &huge, sizeof(huge));
  forged += std::string(48, 'a');
  std::string read, error;
  EXPECT_FALSE(readEnvelope(forged, read, error, uint64_t{8} << 30));
  EXPECT_NE(error.find("more than the limit"), std::string::npos) << error;
  const uint64_t large = uint64_t{4} << 30;
  std::memcpy(&forged[16], &large, sizeof(large));
  EXPECT_FALSE(readEnvelope(forged, read, error, uint64_t{8} << 30));
  EXPECT_NE(error.find("truncated: 48 of"), std::string::npos) << error;
  EXPECT_TRUE(read.empty());
}

// A global map with one tile at `key`, as GlobalMap2D::write lays it out.
std::string mapBytes(const std::vector<int64_t>& keys, uint8_t cell = 1, int tile_cells = 64) {
  std::string out;
  put<uint32_t>(out, 0x52464d47);
  put<int32_t>(out, tile_cells);
  put<uint64_t>(out, keys.size());
  for (int64_t key : keys) {
    put<int64_t>(out, key);
    out += std::string(static_cast<size_t>(tile_cells) * tile_cells, static_cast<char>(cell));
  }
  return out;
}

int64_t tileKey(int64_t x, int64_t y) {
  return static_cast<int64_t>(static_cast<uint64_t>(x) << 32) ^ static_cast<uint32_t>(y);
}

GlobalMap2D mapWithOneCell() {
  GlobalMap2D map;
  map.set({3, 4}, CellClass::kStatic);
  return map;
}

TEST(GlobalMapRead, RoundTripsTilesOnEitherSideOfTheOrigin) {
  GlobalMap2D map;
  map.set({-70, 5}, CellClass::kGlass);
  map.set({100, -300}, CellClass::kFree);
  std::stringstream bytes;
  map.write(bytes);
  GlobalMap2D read;
  ASSERT_TRUE(read.read(bytes));
  EXPECT_EQ(read.get({-70, 5}), CellClass::kGlass);
  EXPECT_EQ(read.get({100, -300}), CellClass::kFree);
  EXPECT_EQ(read.bounds().min, map.bounds().min);
  EXPECT_EQ(read.bounds().max, map.bounds().max);
}

TEST(GlobalMapRead, RefusesWhatNoMapHoldsAndStaysUnchanged) {
  const int64_t far = GlobalMap2D::kMaxCellCoordinate / 64;
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"a tile beyond the coordinate limit", mapBytes({tileKey(far, 0)})},
      {"a tile far below it", mapBytes({tileKey(0, -far - 1)})},
      {"the largest key", mapBytes({tileKey(0x7fffffff, 0x7fffffff)})},
      {"the same tile twice", mapBytes({tileKey(1, 1), tileKey(1, 1)})},
      {"a class that does not exist", mapBytes({tileKey(0, 0)}, 7)},
      {"another tile size", mapBytes({tileKey(0, 0)}, 1, 32)},
      {"a count beyond the data", mapBytes({tileKey(0, 0)}).substr(0, 4 + 4 + 8 + 8 + 100)},
  };
  for (const auto& [name, bytes] : cases) {
    GlobalMap2D map = mapWithOneCell();
    std::istringstream in(bytes);
    EXPECT_FALSE(map.read(in)) << name;
    EXPECT_EQ(map.get({3, 4}), CellClass::kStatic) << name;
    EXPECT_EQ(map.tileCount(), 1u) << name;
  }
  // Tiles at the edge of the limit are fine: their boxes fit an int.
  GlobalMap2D map;
  std::istringstream edge(mapBytes({tileKey(far - 1, -far)}));
  ASSERT_TRUE(map.read(edge));
  EXPECT_EQ(map.bounds().width(), 64);
}

// An archive as TileArchive::write lays it out.
std::string archiveBytes(const std::vector<std::pair<int64_t, std::vector<uint8_t>>>& entries,
                         uint64_t claimed_size = 0) {
  std::string out;
  put<uint64_t>(out, entries.size());
  for (const auto& [key, packed] : entries) {
    put<int64_t>(out, key);
    put<uint64_t>(out, claimed_size ? claimed_size : packed.size());
    out.append(packed.begin(), packed.end());
  }
  return out;
}

constexpr int kTileCells = 4;
constexpr int kBins = 8;
constexpr size_t kTileBins = kTileCells * kTileCells * kBins;

std::vector<uint8_t> packedTile(int8_t value) {
  std::vector<int8_t> bins(kTileBins, 0);
  bins[5] = value;
  return compressBins(bins.data(), bins.size());
}

TEST(TileArchiveRead, RoundTripsAndRefusesWhatNoTileHolds) {
  TileArchive archive;
  archive.store({-3, 2}, packedTile(4));
  archive.store({7, -9}, packedTile(-2));
  std::stringstream bytes;
  archive.write(bytes);
  TileArchive read;
  ASSERT_TRUE(read.read(bytes, kTileCells, kBins));
  EXPECT_EQ(read.tileCount(), 2u);
  EXPECT_EQ(read.take({-3, 2}), packedTile(4));

  std::vector<uint8_t> too_long(TileArchive::maxPackedBytes(kTileBins) + 1, 0);
  std::vector<uint8_t> short_tile = {130};  // three zeros: not a whole tile
  const int64_t far = GlobalMap2D::kMaxCellCoordinate / kTileCells;
  const std::vector<std::pair<std::string, std::string>> cases = {
      // 80 bytes that claim a gigabyte: refused on the size, before any allocation.
      {"an entry claiming 1 GiB", archiveBytes({{tileKey(0, 0), {}}}, uint64_t{1} << 30)},
      {"an entry longer than a tile compresses to", archiveBytes({{tileKey(0, 0), too_long}})},
      {"an entry that is not a whole tile", archiveBytes({{tileKey(0, 0), short_tile}})},
      {"an empty entry", archiveBytes({{tileKey(0, 0), {}}})},
      {"a tile beyond the coordinate limit", archiveBytes({{tileKey(far, 0), packedTile(1)}})},
      {"the same tile twice",
       archiveBytes({{tileKey(1, 1), packedTile(1)}, {tileKey(1, 1), packedTile(2)}})},
      {"a count beyond the data", archiveBytes({{tileKey(1, 1), packedTile(1)}}).substr(0, 20)},
  };
  for (const auto& [name, entry_bytes] : cases) {
    TileArchive kept;
    kept.store({0, 0}, packedTile(3));
    std::istringstream in(entry_bytes);
    EXPECT_FALSE(kept.read(in, kTileCells, kBins)) << name;
    EXPECT_EQ(kept.tileCount(), 1u) << name;
    EXPECT_TRUE(kept.contains({0, 0})) << name;
  }
}

}  // namespace
}  // namespace rfm
