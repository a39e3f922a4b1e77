// Class metrics: a tiny world and hand-drawn class maps, cell by cell.
#include <gtest/gtest.h>

#include <string>

#include "reflectance_field_map/sim/cell_evaluation.h"

namespace rfm::sim {
namespace {

constexpr std::uint8_t U = 0, F = 1, S = 2, G = 3, M = 4, X = 5;  // classes.pgm codes

// A 10 x 5 grid of 1 m cells from (0, 0). Rows are given top (y = 4) first, as in the picture.
ClassGrid grid(const std::vector<std::vector<std::uint8_t>>& rows_top_down) {
  ClassGrid g;
  g.height = static_cast<int>(rows_top_down.size());
  g.width = static_cast<int>(rows_top_down.front().size());
  g.resolution = 1.0;
  g.cells.resize(static_cast<std::size_t>(g.width) * g.height);
  for (int row = 0; row < g.height; ++row)
    for (int x = 0; x < g.width; ++x)
      g.cells[static_cast<std::size_t>(g.height - 1 - row) * g.width + x] = rows_top_down[row][x];
  return g;
}

// Along y = 2.5: a wall over cells 0-3, glass over cells 4-6 with a diffuse frame piece in cell 4
// (a mixed cell), metal over cells 7-9; a mirror in cell (9, 0).
World tinyWorld() {
  World world;
  world.addSegment({0.0, 2.5}, {3.9, 2.5}, Material::kDiffuse);
  world.addSegment({4.1, 2.5}, {4.3, 2.5}, Material::kDiffuse);
  world.addSegment({4.3, 2.5}, {6.9, 2.5}, Material::kGlass);
  world.addSegment({7.1, 2.5}, {9.9, 2.5}, Material::kMetal);
  world.addSegment({9.5, 0.2}, {9.5, 0.8}, Material::kMirror);
  return world;
}

// Row y = 2 (third from the top): wall cells 0-3 drawn S, S, G, M; cell 4 (mixed) S; glass
// cells 5-6 drawn G, F; metal cells 7-8 drawn M, X; metal cell 9 unknown: not observed. A glass
// cell is drawn where a person stood (y = 0, x = 2); the mirror (x = 9, y = 0) is drawn glass.
ClassGrid mixedDrawing() {
  return grid({{F, F, F, F, F, F, F, F, U, U},
               {F, F, F, F, F, F, F, F, U, U},
               {S, S, G, M, S, G, F, M, X, U},
               {F, F, F, F, F, F, F, F, U, U},
               {F, F, G, F, F, F, F, F, F, G}});
}

TEST(CellEvaluationTest, RasterisesMaterialsPerCellAndMarksSharedCellsMixed) {
  const ClassGrid classes =
      grid(std::vector<std::vector<std::uint8_t>>(5, std::vector<std::uint8_t>(10, F)));
  const std::vector<std::uint8_t> truth = rasterizeSurfaces(tinyWorld(), classes);
  auto at = [&](int x, int y) { return truth[static_cast<std::size_t>(y) * 10 + x]; };
  EXPECT_EQ(at(0, 2), kDiffuseBit);
  EXPECT_EQ(at(3, 2), kDiffuseBit);
  EXPECT_EQ(at(4, 2), kDiffuseBit | kGlassBit);  // the pane's frame and its glass
  EXPECT_EQ(at(5, 2), kGlassBit);
  EXPECT_EQ(at(7, 2), kMetalBit);
  EXPECT_EQ(at(9, 2), kMetalBit);
  EXPECT_EQ(at(9, 0), kMirrorBit);
  EXPECT_EQ(at(0, 1), 0);
  EXPECT_EQ(at(9, 1), 0);
}

TEST(CellEvaluationTest, WritesTheSurfacesInTheClassMapsLayout) {
  const ClassGrid classes =
      grid(std::vector<std::vector<std::uint8_t>>(5, std::vector<std::uint8_t>(10, F)));
  const std::vector<std::uint8_t> truth = rasterizeSurfaces(tinyWorld(), classes);
  const std::string pgm = surfacesPgm(classes, truth);
  const std::string header_end = "\n10 5\n255\n";
  const std::size_t pixels = pgm.find(header_end);
  ASSERT_EQ(pgm.rfind("P5\n", 0), 0u);
  ASSERT_NE(pixels, std::string::npos);
  const std::string image = pgm.substr(pixels + header_end.size());
  ASSERT_EQ(image.size(), 50u);
  // The picture's top row is y = 4: map cell (x, y) is picture row 4 - y.
  auto at = [&](int x, int y) { return static_cast<std::uint8_t>(image[(4 - y) * 10 + x]); };
  EXPECT_EQ(at(4, 2), kDiffuseBit | kGlassBit);
  EXPECT_EQ(at(9, 0), kMirrorBit);
  EXPECT_EQ(at(9, 1), 0);
  EXPECT_THROW(surfacesPgm(classes, std::vector<std::uint8_t>(49, 0)), std::invalid_argument);
}

TEST(CellEvaluationTest, CountsExactlyWithoutTolerance) {
  const ClassGrid classes = mixedDrawing();
  const CellConfusion c =
      CellConfusion::evaluate(classes, rasterizeSurfaces(tinyWorld(), classes), 0);

  EXPECT_EQ(c.count(SurfaceRow::kWall, MapClass::kStatic), 2u);
  EXPECT_EQ(c.count(SurfaceRow::kWall, MapClass::kGlass), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kWall, MapClass::kMetal), 1u);
  EXPECT_EQ(c.rowTotal(SurfaceRow::kWall), 4u);
  EXPECT_EQ(c.count(SurfaceRow::kMixed, MapClass::kStatic), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kGlass, MapClass::kGlass), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kGlass, MapClass::kFree), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kMetal, MapClass::kMetal), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kMetal, MapClass::kMotion), 1u);
  EXPECT_EQ(c.unobserved(SurfaceRow::kMetal), 1u);
  EXPECT_EQ(c.count(SurfaceRow::kMirror, MapClass::kGlass), 1u);

  // Drawn glass: (2,2) on a wall, (5,2) on glass, (2,0) on nothing, (9,0) on the mirror.
  EXPECT_EQ(c.drawn(MapClass::kGlass), 4u);
  EXPECT_EQ(c.drawnRight(MapClass::kGlass), 2u);
  EXPECT_DOUBLE_EQ(c.precision(MapClass::kGlass), 50.0);
  EXPECT_DOUBLE_EQ(c.recall(MapClass::kGlass), 50.0);
  // Drawn metal: (3,2) on a wall, (7,2) on metal.
  EXPECT_DOUBLE_EQ(c.precision(MapClass::kMetal), 50.0);
  EXPECT_DOUBLE_EQ(c.recall(MapClass::kMetal), 50.0);
  // Drawn static: (0,2), (1,2) on walls and (4,2) on the wall's end.
  EXPECT_DOUBLE_EQ(c.precision(MapClass::kStatic), 100.0);
  EXPECT_DOUBLE_EQ(c.recall(MapClass::kStatic), 50.0);
  EXPECT_DOUBLE_EQ(c.wallsDrawnSpecular(), 50.0);
  EXPECT_DOUBLE_EQ(c.mirrorsDrawnSpecular(), 100.0);
}

TEST(CellEvaluationTest, ToleranceFindsTheTrueClassNextDoorButKeepsWrongClasses) {
  // The pane (x 4-6, y = 2) is drawn one row too high; the wall is drawn static one row too low.
  const ClassGrid classes = grid({{F, F, F, F, F, F, F, F, F, F},
                                  {F, F, F, F, G, G, G, F, F, F},
                                  {F, F, F, F, F, F, F, F, F, F},
                                  {S, S, S, G, F, F, F, F, F, F},
                                  {F, F, F, F, F, F, F, F, F, F}});
  const std::vector<std::uint8_t> truth = rasterizeSurfaces(tinyWorld(), classes);
  const CellConfusion exact = CellConfusion::evaluate(classes, truth, 0);
  EXPECT_DOUBLE_EQ(exact.recall(MapClass::kGlass), 0.0);
  EXPECT_DOUBLE_EQ(exact.precision(MapClass::kGlass), 0.0);

  const CellConfusion near = CellConfusion::evaluate(classes, truth, 1);
  EXPECT_DOUBLE_EQ(near.recall(MapClass::kGlass), 100.0);     // cells 5 and 6
  EXPECT_DOUBLE_EQ(near.precision(MapClass::kGlass), 100.0);  // (3,1) has glass at (4,2)
  // Wall cells 0-2 find static below; wall cell 3 finds static at (2,1): the true class wins
  // over the glass drawn right below it.
  EXPECT_EQ(near.count(SurfaceRow::kWall, MapClass::kStatic), 4u);
  EXPECT_DOUBLE_EQ(near.wallsDrawnSpecular(), 0.0);
  // Metal cell 7 has only the glass at (6, 3) within a cell, so it counts as drawn glass; cells
  // 8 and 9 have no obstacle within a cell: drawn free.
  EXPECT_EQ(near.count(SurfaceRow::kMetal, MapClass::kGlass), 1u);
  EXPECT_EQ(near.count(SurfaceRow::kMetal, MapClass::kFree), 2u);
  EXPECT_DOUBLE_EQ(near.recall(MapClass::kMetal), 0.0);
  EXPECT_LT(near.precision(MapClass::kMetal), 0.0);  // nothing drawn metal: undefined
}

TEST(CellEvaluationTest, WallsNearOnlyGlassCountAsDrawnGlass) {
  const ClassGrid classes = grid({{F, F, F, F, F, F, F, F, F, F},
                                  {F, F, F, F, F, F, F, F, F, F},
                                  {F, F, F, F, F, F, F, F, F, F},
                                  {G, G, F, F, F, F, F, F, F, F},
                                  {F, F, F, F, F, F, F, F, F, F}});
  const CellConfusion c =
      CellConfusion::evaluate(classes, rasterizeSurfaces(tinyWorld(), classes), 1);
  // Wall cells 0-2 have glass within a cell and no static: drawn glass; cell 3 has nothing.
  EXPECT_EQ(c.count(SurfaceRow::kWall, MapClass::kGlass), 3u);
  EXPECT_EQ(c.count(SurfaceRow::kWall, MapClass::kFree), 1u);
  EXPECT_DOUBLE_EQ(c.wallsDrawnSpecular(), 75.0);
  EXPECT_DOUBLE_EQ(c.precision(MapClass::kGlass), 0.0);
}

TEST(CellEvaluationTest, JsonRoundTripAndMerge) {
  const ClassGrid classes = mixedDrawing();
  const CellConfusion c =
      CellConfusion::evaluate(classes, rasterizeSurfaces(tinyWorld(), classes), 0);
  EXPECT_EQ(CellConfusion::fromJson(c.toJson()), c);
  CellConfusion twice = c;
  twice.merge(c);
  EXPECT_EQ(twice.rowTotal(SurfaceRow::kWall), 8u);
  EXPECT_EQ(twice.drawn(MapClass::kGlass), 8u);
  EXPECT_DOUBLE_EQ(twice.precision(MapClass::kGlass), c.precision(MapClass::kGlass));
  EXPECT_THROW(CellConfusion::fromJson("{\"rows\": {}}"), std::runtime_error);
  EXPECT_NE(c.toMarkdown().find("| glass | 50.0 | 50.0 | 4 | 2 |"), std::string::npos);
}

TEST(CellEvaluationTest, ParsesClassPgmRowsTopDownAndRejectsBadFiles) {
  // 3 x 2: top row 0 1 2, bottom row 3 4 5.
  const std::string good =
      std::string("P5\n# classes\n3 2\n255\n") + '\0' + '\1' + '\2' + '\3' + '\4' + '\5';
  const ClassGrid g = parseClassPgm(good, 0.05, {1.0, -2.0}, "good.pgm");
  EXPECT_EQ(g.width, 3);
  EXPECT_EQ(g.height, 2);
  EXPECT_EQ(g.at(0, 0), 3);  // bottom left
  EXPECT_EQ(g.at(2, 1), 2);  // top right
  EXPECT_DOUBLE_EQ(g.origin.y(), -2.0);

  auto fails = [](const std::string& bytes, const std::string& expected) {
    try {
      parseClassPgm(bytes, 0.05, {0.0, 0.0}, "bad.pgm");
    } catch (const std::runtime_error& error) {
      return std::string(error.what()).find(expected) != std::string::npos;
    }
    return false;
  };
  EXPECT_TRUE(fails("P2\n3 2\n255\n", "not a binary PGM"));
  EXPECT_TRUE(fails("P5\n3 2\n255\nabc", "fewer than 6 cells"));
  EXPECT_TRUE(fails("P5\n999999999 2\n255\n", "bad PGM width"));
  EXPECT_TRUE(fails("P5\n200000 2\n255\n", "out of range"));
  EXPECT_TRUE(fails("P5\n1 1\n65535\n", "maxval"));
  EXPECT_TRUE(fails(std::string("P5\n1 1\n255\n") + '\6', "class code 6"));
  EXPECT_THROW(parseClassPgm(good, 0.0, {0.0, 0.0}, "zero.pgm"), std::runtime_error);
}

TEST(CellEvaluationTest, RejectsMismatchedTruth) {
  const ClassGrid classes = grid({{F, F}, {F, F}});
  EXPECT_THROW(CellConfusion::evaluate(classes, std::vector<std::uint8_t>(3, 0), 0),
               std::invalid_argument);
  EXPECT_THROW(CellConfusion::evaluate(classes, std::vector<std::uint8_t>(4, 0), -1),
               std::invalid_argument);
}

}  // namespace
}  // namespace rfm::sim
