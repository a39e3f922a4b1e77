#include "reflectance_field_map/core/line_fit.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace rfm {
namespace {

TEST(LineFit, FindsTheMainAxisAndHowFarPointsLieAlongAndAcrossIt) {
  // Points along a 30 deg line from (1, 2), every 0.5 m, alternately 0.1 m off either side.
  const Eigen::Vector2d origin(1.0, 2.0), along(std::cos(M_PI / 6), std::sin(M_PI / 6));
  const Eigen::Vector2d normal(-along.y(), along.x());
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 9; ++i)
    points.push_back(origin + 0.5 * i * along + (i % 2 ? 0.1 : -0.1) * normal);
  const LineFit line = fitLine(points);
  EXPECT_NEAR(std::abs(line.direction.dot(along)), 1.0, 1e-3);
  EXPECT_NEAR(line.direction.norm(), 1.0, 1e-12);
  EXPECT_TRUE(line.centre.isApprox(origin + 2.0 * along - 0.1 / 9 * normal, 1e-9));
  EXPECT_NEAR(line.last - line.first, 4.0, 0.01);
  EXPECT_NEAR(line.across, 0.1 + 0.1 / 9, 0.01);
}

TEST(LineFit, ASinglePointIsALineOfNoExtent) {
  const LineFit line = fitLine({Eigen::Vector2d(3.0, -1.0)});
  EXPECT_TRUE(line.centre.isApprox(Eigen::Vector2d(3.0, -1.0)));
  EXPECT_EQ(line.across, 0.0);
  EXPECT_EQ(line.first, 0.0);
  EXPECT_EQ(line.last, 0.0);
}

}  // namespace
}  // namespace rfm
