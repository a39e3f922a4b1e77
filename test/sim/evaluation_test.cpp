// Confusion matrix arithmetic, JSON round trip and the aggregated report.
#include <gtest/gtest.h>

#include "reflectance_field_map/sim/evaluation.h"

namespace rfm::sim {
namespace {

// Truth: 0 no_return, 1 diffuse, 2 glass, 3 metal, 4 motion, 5 reflection.
// Labels: 0 no_return, 1 kept, 2 motion, 3 reflection.
TEST(ConfusionMatrixTest, CountsKeptAndRemovedPerTrueClass) {
  ConfusionMatrix matrix;
  matrix.addScan({1, 1, 1, 1, 2, 2, 3, 4, 4, 5, 5, 5, 0, 0},
                 {1, 1, 1, 0, 1, 3, 1, 2, 1, 3, 2, 1, 1, 0});
  EXPECT_EQ(matrix.scans(), 1u);
  EXPECT_EQ(matrix.excludedNoReturnTruth(), 2u);
  EXPECT_EQ(matrix.noReturnMislabelled(), 1u);  // truth 0 labelled KEPT: mispaired or wrong
  EXPECT_EQ(matrix.scoredRays(), 12u);

  const ClassCounts& diffuse = matrix.row(0);
  EXPECT_EQ(diffuse.total, 4u);
  EXPECT_EQ(diffuse.kept, 3u);
  EXPECT_EQ(diffuse.removed_no_return, 1u);  // a true echo the mapper dropped
  EXPECT_DOUBLE_EQ(diffuse.keptPercent(), 75.0);
  EXPECT_DOUBLE_EQ(diffuse.removedPercent(), 25.0);

  EXPECT_EQ(matrix.row(1).kept, 1u);
  EXPECT_EQ(matrix.row(1).removed_reflection, 1u);
  EXPECT_EQ(matrix.row(2).total, 1u);
  EXPECT_DOUBLE_EQ(matrix.row(2).keptPercent(), 100.0);
  EXPECT_EQ(matrix.row(3).removed_motion, 1u);
  EXPECT_DOUBLE_EQ(matrix.row(3).removedPercent(), 50.0);
  const ClassCounts& reflection = matrix.row(4);
  EXPECT_EQ(reflection.total, 3u);
  EXPECT_EQ(reflection.removed(), 2u);  // as reflection and as motion both count as removed
  EXPECT_NEAR(reflection.removedPercent(), 200.0 / 3.0, 1e-9);
}

TEST(ConfusionMatrixTest, RejectsSizeMismatchAndSkipsInvalidValues) {
  ConfusionMatrix matrix;
  EXPECT_THROW(matrix.addScan({1, 2}, {1}), std::invalid_argument);
  matrix.addScan({1, 9, 2}, {1, 1, 7});
  EXPECT_EQ(matrix.invalidBeams(), 2u);
  EXPECT_EQ(matrix.scoredRays(), 1u);
}

TEST(ConfusionMatrixTest, MergeAddsAndJsonRoundTrips) {
  ConfusionMatrix a, b;
  a.addScan({1, 2, 5}, {1, 1, 3});
  b.addScan({1, 4, 5, 0}, {3, 2, 1, 1});
  a.merge(b);
  EXPECT_EQ(a.scans(), 2u);
  EXPECT_EQ(a.row(0).total, 2u);
  EXPECT_EQ(a.row(0).kept, 1u);
  EXPECT_EQ(a.row(4).total, 2u);
  EXPECT_EQ(a.row(4).kept, 1u);
  const ConfusionMatrix parsed = ConfusionMatrix::fromJson(a.toJson());
  EXPECT_TRUE(parsed == a);
  EXPECT_THROW(ConfusionMatrix::fromJson("{\"scans\": 1}"), std::runtime_error);
  EXPECT_THROW(ConfusionMatrix::fromJson("not json at all: ["), std::runtime_error);
}

TEST(ConfusionMatrixTest, MarkdownTableShowsPercentages) {
  ConfusionMatrix matrix;
  matrix.addScan({2, 2, 2, 2}, {1, 1, 1, 3});
  const std::string table = matrix.toMarkdownTable();
  EXPECT_NE(table.find("| glass | 4 | 75.0 | 25.0 | 0 | 1 | 0 |"), std::string::npos) << table;
}

TEST(EvaluationReportTest, AggregatesRayWeightedAcrossScenes) {
  ConfusionMatrix small, large;
  small.addScan({2, 2}, {3, 3});           // glass 0 % kept on 2 rays
  large.addScan({2, 2, 2, 2, 2, 2, 2, 2},  // glass 100 % kept on 8 rays
                {1, 1, 1, 1, 1, 1, 1, 1});
  const std::vector<EvaluationEntry> entries = {{"full", "scene_a", small, {}, "", ""},
                                                {"full", "scene_b", large, {}, "", ""},
                                                {"baseline", "scene_a", small, {}, "", ""}};
  const std::string report = buildEvaluationReport(entries, "Reproduce: `run it`\n");
  EXPECT_NE(report.find("Reproduce: `run it`"), std::string::npos);
  // Ray-weighted: 8 of 10 glass rays kept = 80.0 %, not the 50 % mean of the per-scene rates.
  EXPECT_NE(report.find("| full | - | 80.0 | - |"), std::string::npos) << report;
  EXPECT_NE(report.find("| baseline | - | 0.0 |"), std::string::npos) << report;
  EXPECT_LT(report.find("### full"), report.find("### baseline"));  // first-seen order
  EXPECT_NE(report.find("| scene_b | full |"), std::string::npos);
  EXPECT_EQ(report.find("Class metrics"), std::string::npos);  // no entry has cells
}

// Cells of a 1 m grid drawn glass over a glass pane along y = 0.5, x in [0, width).
CellConfusion glassCells(int width, int drawn_glass) {
  ClassGrid grid;
  grid.width = width;
  grid.height = 1;
  grid.resolution = 1.0;
  grid.cells.assign(width, 1);  // free
  for (int x = 0; x < drawn_glass; ++x)
    grid.cells[x] = 3;
  World world;
  world.addSegment({0.2, 0.5}, {width - 0.2, 0.5}, Material::kGlass);
  return CellConfusion::evaluate(grid, rasterizeSurfaces(world, grid), 0);
}

TEST(EvaluationReportTest, SumsCellsPerConfigurationAndListsThemPerScene) {
  ConfusionMatrix rays;
  rays.addScan({2, 2}, {1, 1});
  const std::vector<EvaluationEntry> entries = {{"full", "scene_a", rays, glassCells(4, 1), "", ""},
                                                {"full", "scene_b", rays, glassCells(4, 3), "", ""},
                                                {"baseline", "scene_a", rays, {}, "", ""}};
  const std::string report = buildEvaluationReport(entries, "");
  const size_t cells = report.find("## Class metrics (cells)");
  ASSERT_NE(cells, std::string::npos) << report;
  // Summed: 4 of 8 glass cells drawn glass, every cell drawn glass on glass.
  EXPECT_NE(report.find("| glass | 100.0 | 50.0 | 4 | 8 |", cells), std::string::npos) << report;
  EXPECT_NE(report.find("| scene_a | full | 100.0 | 25.0 | - | - |", cells), std::string::npos)
      << report;
  EXPECT_NE(report.find("| scene_b | full | 100.0 | 75.0 | - | - |", cells), std::string::npos)
      << report;
  EXPECT_EQ(report.find("| scene_a | baseline | 100.0", cells), std::string::npos);  // no cells
}

TEST(EvaluationReportTest, GroupsBySetupAndSplitAndSumsCells) {
  ConfusionMatrix rays;
  rays.addScan({2, 2, 2, 2}, {1, 1, 1, 3});  // glass 75 % kept
  std::vector<EvaluationEntry> entries = {
      {"RFM", "1001", rays, glassCells(4, 1), "sick180", "checking"},
      {"RFM", "1002", rays, glassCells(4, 3), "sick180", "checking"},
      {"RFM", "7", rays, glassCells(2, 2), "sick180", "tuning"},
      {"plain_grid", "1001", rays, glassCells(4, 0), "sick180", "checking"},
      {"RFM", "1001", rays, std::nullopt, "wheelchair", "checking"}};
  const std::string report = buildGroupedReport(entries, "Random scenes", "The split.\n");
  EXPECT_EQ(report.find("# Random scenes\n\nThe split."), 0u) << report;
  // Cell-weighted: 4 of 8 checking glass cells drawn glass.
  EXPECT_NE(report.find("| sick180 | checking (2) | RFM | - | 75.00 | - | - | - | 100.0 | 50.0 |"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| sick180 | tuning (1) | RFM |"), std::string::npos);
  EXPECT_NE(report.find("| sick180 | checking (1) | plain_grid |"), std::string::npos);
  EXPECT_NE(report.find("| wheelchair | checking (1) | RFM | - | 75.00 | - | - | - | - |"),
            std::string::npos)
      << report;
  EXPECT_LT(report.find("## sick180"), report.find("## wheelchair"));
  EXPECT_NE(report.find("| 7 | tuning | RFM |"), std::string::npos);
}

}  // namespace
}  // namespace rfm::sim
