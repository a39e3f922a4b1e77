// classes.pgm (a contract): map.pgm's geometry, one byte per cell holding the class code
// 0 unknown, 1 free, 2 static, 3 glass, 4 metal, 5 motion.

#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/offline/outputs.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using rfm::CellClass;
using rfm::CellIndex;

struct Pgm {
  std::string comment;
  int width = 0;
  int height = 0;
  int max_value = 0;
  std::vector<unsigned char> pixels;  // top row first

  unsigned char at(int column, int row) const {
    return pixels[static_cast<size_t>(row) * static_cast<size_t>(width) +
                  static_cast<size_t>(column)];
  }
};

Pgm readPgm(const std::string& path) {
  Pgm pgm;
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  in >> magic;
  EXPECT_EQ(magic, "P5") << path;
  in.ignore(1);
  if (in.peek() == '#') std::getline(in, pgm.comment);
  in >> pgm.width >> pgm.height >> pgm.max_value;
  in.ignore(1);
  pgm.pixels.resize(static_cast<size_t>(pgm.width) * static_cast<size_t>(pgm.height));
  in.read(reinterpret_cast<char*>(pgm.pixels.data()),
          static_cast<std::streamsize>(pgm.pixels.size()));
  EXPECT_TRUE(in.good()) << path << " is shorter than its header says";
  in.get();
  EXPECT_TRUE(in.eof()) << path << " has bytes after its pixels";
  return pgm;
}

class ClassesPgm : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rfm_classes_pgm_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
};

// One cell of every class at a known place, across the origin, so the origin, the row order
// and each code are checked.
TEST_F(ClassesPgm, EveryClassAtItsCellWithMapPgmsGeometry) {
  rfm::GlobalMap2D map(8);
  struct Placed {
    CellIndex cell;
    CellClass value;
    unsigned char code;
    unsigned char map_pgm;  // 0 occupied, 254 free, 205 unknown
  };
  const std::vector<Placed> placed = {
      {CellIndex(-5, -3), CellClass::kFree, 1, 254},
      {CellIndex(-4, 6), CellClass::kStatic, 2, 0},
      {CellIndex(0, 0), CellClass::kGlass, 3, 0},
      {CellIndex(3, -2), CellClass::kMetal, 4, 0},
      {CellIndex(7, 5), CellClass::kMotion, 5, 254},
      {CellIndex(2, 9), CellClass::kOccupied, 2, 0},  // the plain grid's obstacle: static
  };
  for (const Placed& p : placed)
    map.set(p.cell, p.value);

  rfm::offline::writeMapServerFiles(dir_.string(), "map", map, 0.05);
  rfm::offline::writeClassesPgm(dir_.string(), map);
  const Pgm classes = readPgm((dir_ / "classes.pgm").string());
  const Pgm occupancy = readPgm((dir_ / "map.pgm").string());

  // The tiles of 8 cells holding those cells span x -8..7 and y -8..15.
  EXPECT_EQ(classes.width, 16);
  EXPECT_EQ(classes.height, 24);
  EXPECT_EQ(classes.width, occupancy.width);
  EXPECT_EQ(classes.height, occupancy.height);
  EXPECT_EQ(classes.max_value, 255);
  const CellIndex min = map.bounds().min;
  ASSERT_EQ(min, CellIndex(-8, -8));

  for (const Placed& p : placed) {
    const int column = p.cell.x() - min.x();
    const int row = classes.height - 1 - (p.cell.y() - min.y());  // top row = highest y
    SCOPED_TRACE(rfm::toString(p.value));
    EXPECT_EQ(classes.at(column, row), p.code);
    EXPECT_EQ(occupancy.at(column, row), p.map_pgm);
  }
  // Everything else is unknown in both.
  int unknown = 0;
  for (size_t i = 0; i < classes.pixels.size(); ++i) {
    if (classes.pixels[i] == 0) {
      ++unknown;
      EXPECT_EQ(occupancy.pixels[i], 205);
    }
  }
  EXPECT_EQ(unknown, 16 * 24 - static_cast<int>(placed.size()));
}

TEST_F(ClassesPgm, CodesAreTheContractsNumbers) {
  using rfm::offline::classCode;
  EXPECT_EQ(classCode(CellClass::kUnknown), 0);
  EXPECT_EQ(classCode(CellClass::kFree), 1);
  EXPECT_EQ(classCode(CellClass::kStatic), 2);
  EXPECT_EQ(classCode(CellClass::kGlass), 3);
  EXPECT_EQ(classCode(CellClass::kMetal), 4);
  EXPECT_EQ(classCode(CellClass::kMotion), 5);
  EXPECT_EQ(classCode(CellClass::kOccupied), 2);
}

// An empty map gives map.pgm's single unknown cell.
TEST_F(ClassesPgm, EmptyMapIsOneUnknownCell) {
  const rfm::GlobalMap2D map;
  rfm::offline::writeMapServerFiles(dir_.string(), "map", map, 0.05);
  rfm::offline::writeClassesPgm(dir_.string(), map);
  const Pgm classes = readPgm((dir_ / "classes.pgm").string());
  EXPECT_EQ(classes.width, 1);
  EXPECT_EQ(classes.height, 1);
  ASSERT_EQ(classes.pixels.size(), 1u);
  EXPECT_EQ(classes.pixels[0], 0);
}

TEST_F(ClassesPgm, UnwritableDirectoryNamesTheFile) {
  const rfm::GlobalMap2D map;
  try {
    rfm::offline::writeClassesPgm((dir_ / "absent").string(), map);
    FAIL() << "no error";
  } catch (const rfm::offline::OutputError& e) {
    EXPECT_NE(std::string(e.what()).find("classes.pgm"), std::string::npos) << e.what();
  }
}

}  // namespace
