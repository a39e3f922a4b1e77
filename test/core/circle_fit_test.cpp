#include "reflectance_field_map/core/circle_fit.h"

#include <gtest/gtest.h>

#include <cmath>

namespace rfm {
namespace {

// Adds points of the circle of `radius` about (cx, cy) at angles [from, to) (deg), each seen
// along the ray that would return from it: into the surface, opposite to the outward normal.
void addRim(NormalCircleFit& fit, double cx, double cy, double radius, int from, int to) {
  for (int deg = from; deg < to; deg += 5) {
    const double a = deg * M_PI / 180.0;
    fit.add(cx + radius * std::cos(a), cy + radius * std::sin(a), -std::cos(a), -std::sin(a), 1.0);
  }
}

TEST(NormalCircleFit, FindsTheCircleOfAConvexRim) {
  NormalCircleFit fit;
  addRim(fit, 120.0, -40.0, 4.0, -60, 60);
  ASSERT_GT(fit.spread(), 0.0);
  const NormalCircleFit::Circle circle = fit.fit();
  EXPECT_NEAR(circle.radius, 4.0, 1e-9);
  EXPECT_NEAR(circle.rms, 0.0, 1e-6);
}

TEST(NormalCircleFit, RaysLeavingTheCentreGiveANegativeRadius) {
  // The rim of a room seen from its middle: concave, not a column.
  NormalCircleFit fit;
  for (int deg = 0; deg < 90; deg += 5) {
    const double a = deg * M_PI / 180.0;
    fit.add(3.0 * std::cos(a), 3.0 * std::sin(a), std::cos(a), std::sin(a), 2.0);
  }
  EXPECT_NEAR(fit.fit().radius, -3.0, 1e-9);
}

TEST(NormalCircleFit, OneDirectionHasNoSpread) {
  NormalCircleFit fit;
  for (int i = 0; i < 10; ++i)
    fit.add(i, 5.0, 0.0, 1.0, 1.0);  // a stroke seen face on: a pane, a person crossing
  EXPECT_NEAR(fit.spread(), 0.0, 1e-12);
}

TEST(NormalCircleFit, CellsFillingADiscLieFarFromTheFittedRim) {
  // Points spread evenly over a disc of radius 6, each seen towards its centre: what a blob
  // filled with returns looks like to the fit. Their distance from the centre has a standard
  // deviation of 6 / sqrt(18) about its mean of 4, 0.35 of it.
  NormalCircleFit fit;
  for (double x = -6.0; x <= 6.0; x += 0.05) {
    for (double y = -6.0; y <= 6.0; y += 0.05) {
      const double d = std::hypot(x, y);
      if (d > 6.0 || d < 1e-9) continue;
      fit.add(x, y, -x / d, -y / d, 1.0);
    }
  }
  const NormalCircleFit::Circle circle = fit.fit();
  EXPECT_NEAR(circle.radius, 4.0, 0.02);
  EXPECT_NEAR(circle.rms / circle.radius, 1.0 / std::sqrt(8.0), 0.01);
}

TEST(NormalCircleFit, SpreadOfATurn) {
  NormalCircleFit fit;
  addRim(fit, 0.0, 0.0, 1.0, 0, 360);
  EXPECT_NEAR(fit.spread(), 1.0, 1e-9);  // seen all round
  EXPECT_NEAR(spreadOfTurn(2.0 * M_PI), 1.0, 1e-12);
  EXPECT_NEAR(spreadOfTurn(0.1), 0.1 * 0.1 / 12.0, 1e-6);
  EXPECT_EQ(spreadOfTurn(0.0), 0.0);
}

}  // namespace
}  // namespace rfm
