// rfm_render: class colours, map pictures (y up, scale), PNG round trip, theta-resolved slices.

#include "reflectance_field_map/render/image.h"
#include "reflectance_field_map/render/map_image.h"
#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/render/theta_view.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <set>
#include <tuple>

namespace rfm {
namespace render {
namespace {

std::string tempPath(const std::string& name) {
  return (std::filesystem::temp_directory_path() /
          ("rfm_render_test_" + std::to_string(::getpid()) + "_" + name))
      .string();
}

const CellClass kAllClasses[] = {CellClass::kUnknown, CellClass::kFree,  CellClass::kStatic,
                                 CellClass::kGlass,   CellClass::kMetal, CellClass::kMotion,
                                 CellClass::kOccupied};

TEST(ClassColor, EveryClassHasItsOwnColour) {
  std::set<std::tuple<int, int, int>> seen;
  for (const CellClass c : kAllClasses) {
    const Rgb rgb = classColor(c);
    EXPECT_TRUE(seen.insert({rgb.r, rgb.g, rgb.b}).second) << toString(c) << " shares a colour";
  }
}

TEST(ClassColor, FollowsThePaperPalette) {
  const Rgb glass = classColor(CellClass::kGlass);
  EXPECT_GT(glass.b, 200);
  EXPECT_LT(glass.r, 100);
  const Rgb metal = classColor(CellClass::kMetal);
  EXPECT_GT(metal.r, 200);
  EXPECT_LT(metal.g, 100);
  EXPECT_LT(metal.b, 100);
  const Rgb motion = classColor(CellClass::kMotion);
  EXPECT_GT(motion.r, 200);
  EXPECT_GT(motion.b, 200);
  EXPECT_LT(motion.g, 100);
  const Rgb wall = classColor(CellClass::kStatic);
  EXPECT_GT(wall.g, wall.r);
  EXPECT_LT(wall.r + wall.g + wall.b, 300);  // dark
  const Rgb free_cell = classColor(CellClass::kFree);
  EXPECT_GT(free_cell.r, 220);
  const Rgb unknown = classColor(CellClass::kUnknown);
  EXPECT_EQ(unknown.r, unknown.g);
  EXPECT_LT(unknown.r, free_cell.r);
}

TEST(RenderMap, OnePixelPerCellWithYUp) {
  GlobalMap2D map(4);
  map.set({0, 0}, CellClass::kGlass);  // bottom left
  map.set({2, 1}, CellClass::kMetal);  // top right of a 3 x 2 box
  map.set({1, 0}, CellClass::kFree);
  const CellBox box{{0, 0}, {3, 2}};
  const RgbImage image = renderMap(map, box);
  ASSERT_EQ(image.width(), 3);
  ASSERT_EQ(image.height(), 2);
  EXPECT_EQ(image.at(0, 1), classColor(CellClass::kGlass));  // cell y 0 = bottom row
  EXPECT_EQ(image.at(2, 0), classColor(CellClass::kMetal));  // cell y 1 = top row
  EXPECT_EQ(image.at(1, 1), classColor(CellClass::kFree));
  EXPECT_EQ(image.at(0, 0), classColor(CellClass::kUnknown));
}

TEST(RenderMap, ScalesByWholePixels) {
  GlobalMap2D map(4);
  map.set({-1, -1}, CellClass::kStatic);
  const CellBox box{{-1, -1}, {1, 1}};
  const RgbImage image = renderMap(map, box, 3);
  ASSERT_EQ(image.width(), 6);
  ASSERT_EQ(image.height(), 6);
  for (int y = 3; y < 6; ++y) {
    for (int x = 0; x < 3; ++x)
      EXPECT_EQ(image.at(x, y), classColor(CellClass::kStatic));
  }
  EXPECT_EQ(image.at(3, 0), classColor(CellClass::kUnknown));
  EXPECT_THROW(renderMap(map, box, 0), std::invalid_argument);
  EXPECT_TRUE(renderMap(map, CellBox{}, 2).empty());
}

TEST(RenderMap, WholeMapCoversItsBounds) {
  GlobalMap2D map(8);
  map.set({3, 5}, CellClass::kMotion);
  const RgbImage image = renderMap(map);
  EXPECT_EQ(image.width(), map.bounds().width());
  EXPECT_EQ(image.height(), map.bounds().height());
}

TEST(AutoScale, StaysWithinLimits) {
  EXPECT_EQ(autoScale(CellBox{{0, 0}, {100, 50}}, 400, 8), 4);
  EXPECT_EQ(autoScale(CellBox{{0, 0}, {5000, 50}}, 1200, 4), 1);
  EXPECT_EQ(autoScale(CellBox{{0, 0}, {10, 10}}, 1200, 4), 4);
  EXPECT_EQ(autoScale(CellBox{}, 1200, 4), 1);
}

TEST(Png, WrittenAndReadBack) {
  RgbImage image(7, 5, {10, 20, 30});
  image.set(6, 4, {255, 0, 128});
  image.set(0, 0, {1, 2, 3});
  const std::string path = tempPath("roundtrip.png");
  writePng(path, image);
  const RgbImage back = readPng(path);
  ASSERT_EQ(back.width(), 7);
  ASSERT_EQ(back.height(), 5);
  EXPECT_EQ(back.at(6, 4), (Rgb{255, 0, 128}));
  EXPECT_EQ(back.at(0, 0), (Rgb{1, 2, 3}));
  EXPECT_EQ(back.at(3, 2), (Rgb{10, 20, 30}));
  EXPECT_EQ(back.pixels(), image.pixels());
  std::filesystem::remove(path);
}

TEST(Png, MapPictureRoundTrip) {
  GlobalMap2D map(4);
  map.set({0, 0}, CellClass::kGlass);
  map.set({1, 1}, CellClass::kStatic);
  const std::string path = tempPath("map.png");
  writePng(path, renderMap(map, CellBox{{0, 0}, {2, 2}}, 2));
  const RgbImage back = readPng(path);
  ASSERT_EQ(back.width(), 4);
  ASSERT_EQ(back.height(), 4);
  EXPECT_EQ(back.at(0, 3), classColor(CellClass::kGlass));
  EXPECT_EQ(back.at(3, 0), classColor(CellClass::kStatic));
  std::filesystem::remove(path);
}

TEST(Png, ErrorsNameTheFile) {
  const std::vector<uint8_t> rgb(2 * 2 * 3, 0);
  try {
    writePng("/nonexistent-dir/x.png", 2, 2, rgb);
    FAIL() << "no error";
  } catch (const PngError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent-dir/x.png"), std::string::npos);
  }
  EXPECT_THROW(writePng(tempPath("bad.png"), 3, 2, rgb), PngError);  // size mismatch
  EXPECT_THROW(writePng(tempPath("empty.png"), 0, 2, {}), PngError);
  EXPECT_THROW(readPng(tempPath("missing.png")), PngError);
  const std::string not_png = tempPath("not.png");
  {
    std::FILE* f = std::fopen(not_png.c_str(), "wb");
    ASSERT_NE(f, nullptr);
    std::fputs("hello, not a png", f);
    std::fclose(f);
  }
  EXPECT_THROW(readPng(not_png), PngError);
  std::filesystem::remove(not_png);
}

TEST(ThetaView, SegmentColumnsFollowTheLine) {
  const GridGeometry geometry(0.1, 36);
  const auto columns = segmentColumns(geometry, {0.05, 0.05}, {0.95, 0.05});
  ASSERT_EQ(columns.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    ASSERT_EQ(columns[static_cast<size_t>(i)].size(), 1u);
    EXPECT_EQ(columns[static_cast<size_t>(i)][0], CellIndex(i, 0));
  }
  const auto rect = rectangleColumns(geometry, {0.05, 0.05}, {0.55, 0.25});
  ASSERT_EQ(rect.size(), 6u);  // along x
  EXPECT_EQ(rect[0].size(), 3u);
  EXPECT_EQ(rect[5][2], CellIndex(5, 2));
}

// A glass pane along x from the field's point of view: its two edge cells reflect from every
// direction, its face only near the normal. The slice shows the H of paper Fig. 2.
class SyntheticPane : public ::testing::Test {
 protected:
  SyntheticPane() : field_(gridOptions(), LogOddsOptions(), regionOptions()) {
    field_.recenter({0.0, 0.0});
    const int bins = field_.geometry().thetaBins();
    for (int x = 0; x < kCells; ++x) {
      const CellIndex cell(x, 0);
      const bool edge = x == 0 || x == kCells - 1;
      for (int bin = 0; bin < bins; ++bin) {
        const bool reflective = edge || (bin >= kNormalBin - 1 && bin <= kNormalBin + 1);
        for (int k = 0; k < 3; ++k) {
          if (reflective) {
            field_.applyHit(cell, bin);
          } else if (bin % 2 == 0) {
            field_.applyMiss(cell, bin);  // seen through from half the directions
          }
        }
      }
    }
  }
  static GridOptions gridOptions() {
    GridOptions grid;
    grid.resolution = 0.1;
    grid.theta_bins = 36;
    grid.tile_cells = 8;
    return grid;
  }
  static ActiveRegionOptions regionOptions() {
    ActiveRegionOptions region;
    region.active_region_radius = 2.0;
    return region;
  }

  static constexpr int kCells = 10;
  static constexpr int kNormalBin = 27;  // rays travelling -y hit a pane lying along x
  ReflectanceField field_;
};

TEST_F(SyntheticPane, SliceMarksReflectiveBins) {
  const auto columns = segmentColumns(field_.geometry(), {0.05, 0.05}, {0.95, 0.05});
  const ThetaSlice slice = sampleThetaSlice(field_, columns);
  ASSERT_EQ(slice.columns, kCells);
  ASSERT_EQ(slice.bins, 36);
  EXPECT_EQ(slice.reflectiveCount(0), 36);
  EXPECT_EQ(slice.reflectiveCount(kCells - 1), 36);
  for (int c = 1; c < kCells - 1; ++c) {
    EXPECT_EQ(slice.reflectiveCount(c), 3) << "column " << c;
    EXPECT_EQ(slice.at(c, kNormalBin), ThetaSlice::Bin::kReflective);
    EXPECT_EQ(slice.at(c, 0), ThetaSlice::Bin::kMissed);
    EXPECT_EQ(slice.at(c, 1), ThetaSlice::Bin::kUnobserved);
  }
  for (int c = 0; c < kCells; ++c) {
    for (int bin = 0; bin < slice.bins; ++bin) {
      EXPECT_EQ(slice.at(c, bin) == ThetaSlice::Bin::kReflective,
                field_.isReflective(CellIndex(c, 0), bin));
    }
  }
  EXPECT_EQ(slice.outsideColumns(), 0);
}

TEST_F(SyntheticPane, PictureShowsTheH) {
  const auto columns = segmentColumns(field_.geometry(), {0.05, 0.05}, {0.95, 0.05});
  GlobalMap2D map(8);
  for (int x = 0; x < kCells; ++x)
    map.set({x, 0}, CellClass::kGlass);
  map.set({0, 0}, CellClass::kStatic);
  map.set({kCells - 1, 0}, CellClass::kStatic);
  const ThetaSlice slice = sampleThetaSlice(field_, columns, &map);
  const RgbImage image = renderThetaSlice(slice, 2, 3);
  ASSERT_EQ(image.width(), kCells * 2);
  ASSERT_EQ(image.height(), 36 * 3);
  auto pixel = [&image](int column, int bin) {
    return image.at(column * 2 + 1, (35 - bin) * 3 + 1);  // theta up: bin 0 at the bottom
  };
  for (int bin = 0; bin < 36; ++bin) {
    EXPECT_EQ(pixel(0, bin), classColor(CellClass::kStatic));  // the sides of the H
    EXPECT_EQ(pixel(kCells - 1, bin), classColor(CellClass::kStatic));
  }
  EXPECT_EQ(pixel(4, kNormalBin), classColor(CellClass::kGlass));  // the bar of the H
  EXPECT_EQ(pixel(4, 0), (Rgb{255, 255, 255}));                    // missed
  EXPECT_NE(pixel(4, 1), classColor(CellClass::kGlass));           // unobserved
  EXPECT_NE(pixel(4, 1), (Rgb{255, 255, 255}));
}

TEST_F(SyntheticPane, CellsOutsideTheActiveRegionAreMarked) {
  const auto columns = segmentColumns(field_.geometry(), {0.05, 0.05}, {50.0, 0.05});
  const ThetaSlice slice = sampleThetaSlice(field_, columns);
  EXPECT_GT(slice.outsideColumns(), 0);
  EXPECT_EQ(slice.at(slice.columns - 1, 0), ThetaSlice::Bin::kOutside);
  EXPECT_EQ(slice.reflectiveCount(0), 36);
}

TEST(ThetaView, EmptySliceGivesEmptyPicture) {
  EXPECT_TRUE(renderThetaSlice(ThetaSlice{}).empty());
}

}  // namespace
}  // namespace render
}  // namespace rfm
