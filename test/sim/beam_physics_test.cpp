// Beam physics: what one beam returns from diffuse walls, glass, frames, mirrors, metal and people.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/beam_physics.h"

namespace rfm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;
constexpr double kWindow = 3.0 * kDeg;  // specular return half-width used in these tests

Eigen::Vector2d direction(double angle_deg) {
  return {std::cos(angle_deg * kDeg), std::sin(angle_deg * kDeg)};
}

MaterialModel deterministicModel() {
  MaterialModel model;
  model.glass_reflect_probability = 0.0;
  model.metal_scatter_probability = 0.0;
  return model;
}

class BeamPhysicsTest : public ::testing::Test {
 protected:
  BeamResult trace(double angle_deg, const std::vector<Circle>& people = {}) {
    BeamTracer tracer(world_, model_);
    return tracer.trace(Eigen::Vector2d::Zero(), direction(angle_deg), 30.0, people, kWindow, rng_);
  }
  World world_;
  MaterialModel model_ = deterministicModel();
  std::mt19937 rng_{42};
};

// Glass pane on x = 5 (y in [-5, 5]) with frames, a diffuse wall behind it on x = 10.
class GlassTest : public BeamPhysicsTest {
 protected:
  void SetUp() override {
    world_.addFramedSegment({5, -5}, {5, 5}, Material::kGlass, 0.1, 0.0);
    world_.addSegment({10, -30}, {10, 30}, Material::kDiffuse);
  }
};

TEST_F(GlassTest, ReturnsNearNormal) {
  for (const double angle : {0.0, 1.5, -2.5}) {
    const BeamResult beam = trace(angle);
    EXPECT_EQ(beam.beam_class, BeamClass::kGlass) << angle;
    EXPECT_NEAR(beam.range, 5.0 / std::cos(angle * kDeg), 1e-9) << angle;
  }
}

TEST_F(GlassTest, TransmitsOffNormalAndReturnsWhatIsBehindAsReflection) {
  for (const double angle : {3.5, 10.0, -20.0, 40.0}) {
    const BeamResult beam = trace(angle);
    EXPECT_EQ(beam.beam_class, BeamClass::kReflection) << angle;
    EXPECT_NEAR(beam.range, 10.0 / std::cos(angle * kDeg), 1e-9) << angle;  // the wall behind
    EXPECT_EQ(beam.interactions, 1);
  }
}

TEST_F(GlassTest, FramesScatterAtAnyAngle) {
  // Aim at the middle of the lower frame piece (5, -4.95) from several positions.
  const Eigen::Vector2d frame_point(5.0, -4.95);
  BeamTracer tracer(world_, model_);
  for (const Eigen::Vector2d& origin : {Eigen::Vector2d(0, -4.95), Eigen::Vector2d(0, 0),
                                        Eigen::Vector2d(0, 3), Eigen::Vector2d(4.5, 2)}) {
    const Eigen::Vector2d toward = (frame_point - origin).normalized();
    const BeamResult beam = tracer.trace(origin, toward, 30.0, {}, kWindow, rng_);
    EXPECT_EQ(beam.beam_class, BeamClass::kDiffuse) << origin.transpose();
    EXPECT_NEAR(beam.range, (frame_point - origin).norm(), 1e-9);
  }
}

TEST_F(GlassTest, OccasionalSpecularReflectionWhenConfigured) {
  model_.glass_reflect_probability = 1.0;
  world_.addSegment({-30, 8}, {30, 8}, Material::kDiffuse);
  // Reflected at 30 degrees off x = 5 toward the wall y = 8: virtual image at distance 8 / sin 30.
  const BeamResult beam = trace(30.0);
  EXPECT_EQ(beam.beam_class, BeamClass::kReflection);
  EXPECT_NEAR(beam.range, 16.0, 1e-9);
}

TEST_F(GlassTest, PersonBehindGlassIsReflectionPersonInFrontIsMotion) {
  const double angle = 20.0;
  const Eigen::Vector2d behind = 7.0 * direction(angle);
  const BeamResult through = trace(angle, {{behind, 0.25}});
  EXPECT_EQ(through.beam_class, BeamClass::kReflection);
  EXPECT_NEAR(through.range, 7.0 - 0.25, 1e-9);

  const Eigen::Vector2d in_front = 3.0 * direction(angle);
  const BeamResult direct = trace(angle, {{in_front, 0.25}});
  EXPECT_EQ(direct.beam_class, BeamClass::kMotion);
  EXPECT_NEAR(direct.range, 3.0 - 0.25, 1e-9);
}

TEST_F(GlassTest, SecondPaneSeenThroughFirstIsReflection) {
  // A beam passing the first pane off-normal meets a second pane at its normal: the second pane's
  // echo is seen through glass, so it is a reflection, not glass.
  World tilted;
  tilted.addSegment({5, -5}, {5, 5}, Material::kGlass);
  const Eigen::Vector2d n = direction(10.0);
  const Eigen::Vector2d t(-n.y(), n.x());
  const Eigen::Vector2d center = 7.0 * n;
  tilted.addSegment(center - 2.0 * t, center + 2.0 * t, Material::kGlass);
  BeamTracer tracer(tilted, model_);
  const BeamResult beam = tracer.trace({0, 0}, n, 30.0, {}, kWindow, rng_);
  EXPECT_EQ(beam.beam_class, BeamClass::kReflection);
  EXPECT_NEAR(beam.range, 7.0, 1e-9);
}

TEST_F(BeamPhysicsTest, MirrorReturnsNearNormalAndFoldedPathOtherwise) {
  world_.addSegment({5, -5}, {5, 5}, Material::kMirror);
  world_.addSegment({-30, 8}, {30, 8}, Material::kDiffuse);
  world_.addSegment({-30, -8}, {30, -8}, Material::kDiffuse);

  const BeamResult normal = trace(1.0);
  EXPECT_EQ(normal.beam_class, BeamClass::kMetal);
  EXPECT_NEAR(normal.range, 5.0 / std::cos(1.0 * kDeg), 1e-9);

  for (const double angle : {30.0, -25.0, 40.0}) {
    const double a = angle * kDeg;
    // Folded path: to the mirror at (5, 5 tan a), then mirrored direction to the wall |y| = 8.
    const Eigen::Vector2d hit(5.0, 5.0 * std::tan(a));
    const Eigen::Vector2d reflected(-std::cos(a), std::sin(a));
    const double to_wall = (8.0 - std::abs(hit.y())) / std::abs(reflected.y());
    const double expected = hit.norm() + to_wall;
    const BeamResult beam = trace(angle);
    EXPECT_EQ(beam.beam_class, BeamClass::kReflection) << angle;
    EXPECT_NEAR(beam.range, expected, 1e-9) << angle;
    // Equivalently the virtual wall behind the mirror: y = +-8 reached along the original ray.
    EXPECT_NEAR(beam.range, 8.0 / std::abs(std::sin(a)), 1e-9) << angle;
  }
}

TEST_F(BeamPhysicsTest, MetalReturnsOverWideLobeAndMirrorsElsewhere) {
  world_.addSegment({5, -10}, {5, 10}, Material::kMetal);
  world_.addSegment({-30, 12}, {30, 12}, Material::kDiffuse);
  world_.addSegment({-30, -12}, {30, -12}, Material::kDiffuse);
  for (const double angle : {0.0, 5.0, -10.0, 14.5}) {
    EXPECT_EQ(trace(angle).beam_class, BeamClass::kMetal) << angle;
  }
  for (const double angle : {30.0, -45.0, 60.0}) {  // folded paths 24, 17 and 13.9 m
    const BeamResult beam = trace(angle);
    EXPECT_EQ(beam.beam_class, BeamClass::kReflection) << angle;
    EXPECT_NEAR(beam.range, 12.0 / std::abs(std::sin(angle * kDeg)), 1e-9);
  }
  model_.metal_scatter_probability = 1.0;  // always scatters back outside the lobe
  EXPECT_EQ(trace(30.0).beam_class, BeamClass::kMetal);
}

TEST_F(BeamPhysicsTest, DiffuseReturnsUpToGrazingOnly) {
  world_.addSegment({-30, 1}, {30, 1}, Material::kDiffuse);
  const BeamResult steep = trace(90.0);
  EXPECT_EQ(steep.beam_class, BeamClass::kDiffuse);
  EXPECT_NEAR(steep.range, 1.0, 1e-9);
  EXPECT_EQ(trace(5.0).beam_class, BeamClass::kDiffuse);   // 85 degrees incidence
  EXPECT_EQ(trace(0.5).beam_class, BeamClass::kNoReturn);  // 89.5 degrees: too grazing
}

TEST_F(BeamPhysicsTest, NothingInRangeIsNoReturnWithInfiniteRange) {
  world_.addSegment({40, -5}, {40, 5}, Material::kDiffuse);  // beyond range_max = 30
  const BeamResult beam = trace(0.0);
  EXPECT_EQ(beam.beam_class, BeamClass::kNoReturn);
  EXPECT_TRUE(std::isinf(beam.range) && beam.range > 0);
}

TEST_F(BeamPhysicsTest, FoldedPathBeyondRangeMaxIsNoReturn) {
  world_.addSegment({5, -5}, {5, 5}, Material::kMirror);
  world_.addSegment({-30, 20}, {30, 20}, Material::kDiffuse);
  // 20 / sin(30 deg) = 40 m folded path > 30 m.
  EXPECT_EQ(trace(30.0).beam_class, BeamClass::kNoReturn);
}

TEST_F(BeamPhysicsTest, InteractionCapStopsTheBeam) {
  // Two facing mirrors: a slanted beam bounces between them forever without the cap.
  world_.addSegment({-1, -100}, {-1, 100}, Material::kMirror);
  world_.addSegment({1, -100}, {1, 100}, Material::kMirror);
  world_.addSegment({-5, 3}, {5, 3}, Material::kDiffuse);
  model_.max_interactions = 4;
  // At 10 degrees the beam climbs 0.35 m per crossing: 8 bounces to reach the wall at y = 3.
  const BeamResult capped = trace(10.0);
  EXPECT_EQ(capped.beam_class, BeamClass::kNoReturn);
  model_.max_interactions = 16;
  const BeamResult uncapped = trace(10.0);
  EXPECT_EQ(uncapped.beam_class, BeamClass::kReflection);
  EXPECT_NEAR(uncapped.range, 3.0 / std::sin(10.0 * kDeg), 1e-9);
}

TEST(WorldTest, ArcIntersectionAndFramedArcPieces) {
  World world;
  world.addFramedArc({0, 0}, 3.0, 0.0, M_PI, Material::kGlass, 0.1, 1.0);
  // Frames at both ends and round(3 pi / 1) - 1 = 8 mullions -> 9 glass + 10 diffuse arcs.
  EXPECT_EQ(world.arcCount(), 19u);
  const auto hit = world.intersect({0, 0}, direction(60.0), 30.0, {});
  ASSERT_TRUE(hit.has_value());
  EXPECT_NEAR(hit->distance, 3.0, 1e-9);
  EXPECT_NEAR(hit->normal.dot(direction(60.0)), -1.0, 1e-9);                      // faces the beam
  EXPECT_FALSE(world.intersect({0, 0}, direction(-60.0), 30.0, {}).has_value());  // open half
  // From outside, the convex face is hit first.
  const auto outside = world.intersect({0, 10}, {0, -1}, 30.0, {});
  ASSERT_TRUE(outside.has_value());
  EXPECT_NEAR(outside->distance, 7.0, 1e-9);
}

}  // namespace
}  // namespace rfm::sim
