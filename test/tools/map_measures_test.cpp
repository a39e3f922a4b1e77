// The measures of maps on real recordings, on small synthetic maps: reading map_server maps and
// classes.pgm, aligning them, walls kept, the picture and people left.

#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/tools/comparison_picture.h"
#include "reflectance_field_map/tools/grid_map_file.h"
#include "reflectance_field_map/tools/map_comparison.h"
#include "reflectance_field_map/tools/transient_evidence.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace rfm::tools;

// Rows top down: '#' occupied (0), '.' free (254), '?' unknown (205); classes: a digit a cell.
void writeMap(const fs::path& dir, double origin_x, double origin_y,
              const std::vector<std::string>& rows, const std::vector<std::string>& classes = {},
              double resolution = 0.05) {
  fs::create_directories(dir);
  const int width = static_cast<int>(rows[0].size()), height = static_cast<int>(rows.size());
  std::ofstream pgm(dir / "map.pgm", std::ios::binary);
  pgm << "P5\n# test\n" << width << ' ' << height << "\n255\n";
  for (const std::string& row : rows) {
    for (const char c : row)
      pgm.put(static_cast<char>(c == '#' ? 0 : (c == '.' ? 254 : 205)));
  }
  pgm.close();
  std::ofstream yaml(dir / "map.yaml");
  yaml << "image: map.pgm\nresolution: " << resolution << "\norigin: [" << origin_x << ", "
       << origin_y << ", 0.0]\nnegate: 0\noccupied_thresh: 0.65\nfree_thresh: 0.196\n";
  if (classes.empty()) return;
  std::ofstream out(dir / "classes.pgm", std::ios::binary);
  out << "P5\n" << width << ' ' << height << "\n255\n";
  for (const std::string& row : classes) {
    for (const char c : row)
      out.put(static_cast<char>(c - '0'));
  }
}

class MapMeasures : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("rfm_map_measures_test_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

std::string errorOf(const std::function<void()>& f) {
  try {
    f();
  } catch (const MapFileError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no MapFileError";
  return "";
}

TEST_F(MapMeasures, ReadsMapServerMapsYUp) {
  writeMap(dir_ / "m", -1.0, 2.0, {"#.?", "..#"}, {"230", "115"});
  const GridMap map = readMapDirectory((dir_ / "m").string());
  EXPECT_EQ(map.width, 3);
  EXPECT_EQ(map.height, 2);
  EXPECT_DOUBLE_EQ(map.origin_x, -1.0);
  EXPECT_DOUBLE_EQ(map.origin_y, 2.0);
  // Row 0 of the grid is the image's bottom row.
  EXPECT_EQ(map.occupancyAt(2, 0), Occupancy::kOccupied);
  EXPECT_EQ(map.occupancyAt(0, 0), Occupancy::kFree);
  EXPECT_EQ(map.occupancyAt(0, 1), Occupancy::kOccupied);
  EXPECT_EQ(map.occupancyAt(2, 1), Occupancy::kUnknown);
  ASSERT_TRUE(map.hasClasses());
  EXPECT_EQ(classAt(map, 0, 1), kCodeStatic);
  EXPECT_EQ(classAt(map, 1, 1), kCodeGlass);
  EXPECT_EQ(classAt(map, 2, 0), kCodeMotion);
  EXPECT_EQ(classAt(map, 7, 7), kCodeUnknown);  // beyond the map
}

TEST_F(MapMeasures, TrinaryThresholdsAndNegate) {
  fs::create_directories(dir_ / "t");
  std::ofstream(dir_ / "t" / "map.pgm", std::ios::binary) << "P5 4 1 255\n"
                                                          << std::string{0, 50, 100, char(230)};
  std::ofstream(dir_ / "t" / "map.yaml")
      << "image: map.pgm\nresolution: 0.1\norigin: [0, 0, 0]\noccupied_thresh: 0.65\n"
         "free_thresh: 0.196\nnegate: 1\n";
  const GridMap map = readMapServerMap((dir_ / "t" / "map.yaml").string());
  // Negated: p = v / 255.
  EXPECT_EQ(map.occupancyAt(0, 0), Occupancy::kFree);      // 0
  EXPECT_EQ(map.occupancyAt(1, 0), Occupancy::kUnknown);   // 0.196...
  EXPECT_EQ(map.occupancyAt(2, 0), Occupancy::kUnknown);   // 0.39
  EXPECT_EQ(map.occupancyAt(3, 0), Occupancy::kOccupied);  // 0.90
}

TEST_F(MapMeasures, BadFilesAreRefusedBeforeTrustingTheirSizes) {
  const fs::path d = dir_ / "bad";
  writeMap(d, 0, 0, {"##", ".."});
  auto write = [&](const std::string& name, const std::string& bytes) {
    std::ofstream(d / name, std::ios::binary) << bytes;
  };
  write("huge.pgm", "P5 100000 100000 255\n");
  EXPECT_NE(errorOf([&] { readPgm((d / "huge.pgm").string()); }).find("more than a map may have"),
            std::string::npos);
  write("short.pgm", "P5 4 4 255\nabc");
  EXPECT_NE(errorOf([&] { readPgm((d / "short.pgm").string()); }).find("3 pixel bytes"),
            std::string::npos);
  write("wide.pgm", "P5 2 2 65535\n12345678");
  EXPECT_NE(errorOf([&] { readPgm((d / "wide.pgm").string()); }).find("maxval 65535"),
            std::string::npos);
  write("ascii.pgm", "P2 2 2 255\n0 0 0 0\n");
  EXPECT_NE(errorOf([&] { readPgm((d / "ascii.pgm").string()); }).find("not a binary PGM"),
            std::string::npos);
  write("classes.pgm", std::string("P5 3 2 255\n") + std::string(6, '\1'));
  EXPECT_NE(errorOf([&] { readMapDirectory(d.string()); }).find("is 3 x 2, map.pgm 2 x 2"),
            std::string::npos);
  write("classes.pgm", std::string("P5 2 2 255\n") + std::string{1, 1, 7, 1});
  EXPECT_NE(errorOf([&] { readMapDirectory(d.string()); }).find("class code 7"), std::string::npos);
  EXPECT_NE(errorOf([&] { readMapDirectory((dir_ / "absent").string()); }).find("map.yaml"),
            std::string::npos);
}

TEST_F(MapMeasures, AlignmentByOrigins) {
  writeMap(dir_ / "a", 1.0, -0.5, {"."});
  writeMap(dir_ / "b", 0.8, -0.25, {"."});
  writeMap(dir_ / "c", 0.81, -0.25, {"."});
  writeMap(dir_ / "d", 1.0, -0.5, {"."}, {}, 0.1);
  const GridMap a = readMapDirectory((dir_ / "a").string());
  const CellOffset offset = alignment(a, readMapDirectory((dir_ / "b").string()));
  EXPECT_EQ(offset.dx, 4);  // a's cell 0 is b's cell 4
  EXPECT_EQ(offset.dy, -5);
  EXPECT_NE(errorOf([&] {
              alignment(a, readMapDirectory((dir_ / "c").string()));
            }).find("not on one grid"),
            std::string::npos);
  EXPECT_NE(errorOf([&] {
              alignment(a, readMapDirectory((dir_ / "d").string()));
            }).find("resolutions differ"),
            std::string::npos);
}

// The plain grid's wall: the RFM keeps part of it one cell off (kept), loses a stretch to motion
// and one cell to free space, and does not cover the last cell at all (unknown). The RFM's map
// starts a cell to the right of the plain grid's.
TEST_F(MapMeasures, WallsKeptWithinOneCell) {
  writeMap(dir_ / "plain", 0.0, 0.0,
           {"........",  //
            "########",  //
            "........"});
  writeMap(dir_ / "rfm", 0.05, 0.0,
           {"##.....",  //
            "...... ",  //
            "......."},
           {"2211111",  //
            "1115550",  //
            "1111111"});
  const GridMap plain = readMapDirectory((dir_ / "plain").string());
  const GridMap rfm = readMapDirectory((dir_ / "rfm").string());
  const WallsKept walls = measureWallsKept(rfm, plain);
  EXPECT_EQ(walls.plain_occupied, 8u);
  // Plain cells 0-3 have an RFM obstacle within one cell (RFM cells 0 and 1 are plain 1, 2).
  EXPECT_EQ(walls.kept, 4u);
  EXPECT_EQ(walls.dropped_by_class[kCodeMotion], 3u);   // plain 4-6 (RFM 3-5)
  EXPECT_EQ(walls.dropped_by_class[kCodeUnknown], 1u);  // plain 7 (RFM 6: unknown)
  EXPECT_EQ(walls.dropped_by_class[kCodeFree], 0u);
  EXPECT_DOUBLE_EQ(walls.percent(), 50.0);
  // Chebyshev distance 0: only exact cells count (none here).
  EXPECT_EQ(measureWallsKept(rfm, plain, 0).kept, 0u);

  const auto classes = countClasses(rfm);
  EXPECT_EQ(classes[kCodeStatic], 2u);
  EXPECT_EQ(classes[kCodeMotion], 3u);
  EXPECT_EQ(classes[kCodeUnknown], 1u);
}

TEST_F(MapMeasures, PictureShowsGlassAndDroppedCells) {
  writeMap(dir_ / "plain", 0.0, 0.0, {"....", "####", "...."});
  writeMap(dir_ / "rfm", 0.0, 0.0, {"....", "##..", "...."}, {"1111", "3455", "1111"});
  const GridMap plain = readMapDirectory((dir_ / "plain").string());
  const GridMap rfm = readMapDirectory((dir_ / "rfm").string());
  const rfm::render::RgbImage image = renderComparison(rfm, plain, 1);
  ASSERT_EQ(image.width(), 4 + 4 + 4);
  ASSERT_EQ(image.height(), 3);
  const rfm::render::Rgb glass{20, 90, 255}, metal{225, 20, 20}, motion{235, 0, 235};
  EXPECT_EQ(image.at(0, 1), glass);
  EXPECT_EQ(image.at(1, 1), metal);
  EXPECT_EQ(image.at(2, 1), motion);
  EXPECT_EQ(image.at(8, 1), plainOccupiedColor());   // kept
  EXPECT_EQ(image.at(10, 1), plainOccupiedColor());  // kept: the metal cell is a cell away
  EXPECT_EQ(image.at(11, 1), droppedColor(kCodeMotion));

  // Two cells a pixel: a block shows its most telling cell (glass over metal over motion).
  const rfm::render::RgbImage half = renderComparison(rfm, plain, 2);
  EXPECT_EQ(half.width(), 2 + 4 + 2);
  EXPECT_EQ(half.at(0, 0), glass);  // blocks run from the top: the wall is in row 0
  EXPECT_EQ(half.at(6, 0), plainOccupiedColor());
  EXPECT_EQ(half.at(7, 0), droppedColor(kCodeMotion));

  const std::string path = (dir_ / "picture.png").string();
  const int k = writeComparisonPicture(path, rfm, plain, 10, 100000);
  EXPECT_EQ(k, 2);  // 12 pixels at one cell a pixel is wider than 10
  EXPECT_LE(fs::file_size(path), 100000u);
  EXPECT_EQ(rfm::render::readPng(path).width(), 8);
}

rfm::TimedScan scanAlongX(float range) {
  rfm::TimedScan timed;
  timed.scan.angle_min = 0.0f;
  timed.scan.angle_max = 0.0f;
  timed.scan.angle_increment = 0.01f;
  timed.scan.range_min = 0.05f;
  timed.scan.range_max = 5.0f;
  timed.scan.ranges = {range};
  timed.sensor_pose.position = Eigen::Vector2d(0.01, 0.025);
  return timed;
}

// A wall at 2 m hit by every scan; a person at 1 m in one scan of four; a no-return scan.
TEST(TransientEvidence, PeopleAreSeenThroughWallsAreNot) {
  TransientEvidence evidence(0.05, 0, 0, 60, 1);
  for (const float range : {2.0f, 1.0f, 2.0f, 2.0f, INFINITY})
    evidence.addScan(scanAlongX(range));
  EXPECT_EQ(evidence.hitScans(40, 0), 3u);  // the wall
  EXPECT_EQ(evidence.passedScans(40, 0), 0u);
  EXPECT_FALSE(evidence.isTransient(40, 0));
  EXPECT_EQ(evidence.hitScans(20, 0), 1u);  // the person
  EXPECT_EQ(evidence.passedScans(20, 0), 3u);
  EXPECT_TRUE(evidence.isTransient(20, 0));
  // Within two cells of a return is no sight through: range noise.
  EXPECT_EQ(evidence.passedScans(38, 0), 0u);
  EXPECT_EQ(evidence.passedScans(37, 0), 3u);
  TransientEvidence no_margin(0.05, 0, 0, 60, 1, 0);
  no_margin.addScan(scanAlongX(2.0f));
  EXPECT_EQ(no_margin.passedScans(39, 0), 1u);

  GridMap map;
  map.width = 60;
  map.height = 1;
  map.resolution = 0.05;
  map.occupancy.assign(60, Occupancy::kFree);
  map.occupancy[20] = map.occupancy[40] = Occupancy::kOccupied;
  const PeopleLeft left = measurePeopleLeft(map, evidence);
  EXPECT_EQ(left.occupied, 2u);
  EXPECT_EQ(left.transient, 1u);
}

// A scan counts once per cell, and a cell one beam ends in is hit even if another crosses it.
TEST(TransientEvidence, OneScanCountsOncePerCell) {
  rfm::TimedScan timed = scanAlongX(2.0f);
  timed.scan.ranges = {2.0f, 2.0f, 1.0f};
  timed.scan.angle_increment = 1e-4f;
  timed.scan.angle_max = 2e-4f;
  TransientEvidence evidence(0.05, 0, 0, 60, 1);
  evidence.addScan(timed);
  EXPECT_EQ(evidence.passedScans(10, 0), 1u);
  EXPECT_EQ(evidence.hitScans(40, 0), 1u);
  EXPECT_EQ(evidence.hitScans(20, 0), 1u);
  EXPECT_EQ(evidence.passedScans(20, 0), 0u);  // hit by beam 2, crossed by beams 0 and 1
}

}  // namespace
