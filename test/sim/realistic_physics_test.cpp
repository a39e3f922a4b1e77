// The realistic physics of procedural scenes: the 3D return cone, Fresnel panes, dirt, the weak
// echo of glass with nothing behind it, metal lobes and their tails, glossy grazing bounces and
// faint returns.
#include <gtest/gtest.h>

#include <cmath>

#include "reflectance_field_map/sim/beam_physics.h"

namespace rfm::sim {
namespace {

constexpr double kDeg = M_PI / 180.0;

Eigen::Vector2d direction(double angle_deg) {
  return {std::cos(angle_deg * kDeg), std::sin(angle_deg * kDeg)};
}

// Everything random switched off: each test turns on what it checks.
RealisticPhysics quietPhysics() {
  RealisticPhysics p;
  p.enabled = true;
  p.return_cone_deg = 2.5;
  p.bump_tilt_deg = 0.0;
  p.refractive_index = 1.0;  // a pane that reflects nothing
  p.empty_echo_probability = 0.0;
  p.metal_tail_probability = 0.0;
  p.diffuse_max_incidence_deg = 85.0;
  p.grazing_dropout = 0.0;
  p.range_dropout = 0.0;
  p.gloss_probability = 0.0;
  return p;
}

class RealisticPhysicsTest : public ::testing::Test {
 protected:
  BeamResult trace(double angle_deg, double elevation_deg = 0.0,
                   const Eigen::Vector2d& origin = Eigen::Vector2d::Zero()) {
    BeamTracer tracer(world_, MaterialModel{}, physics_);
    return tracer.traceRealistic(origin, direction(angle_deg), 30.0, {}, elevation_deg * kDeg,
                                 rng_);
  }
  // Share of `beams` traces at `angle_deg` that end with `expected`.
  double share(double angle_deg, BeamClass expected, int beams = 4000) {
    int count = 0;
    for (int i = 0; i < beams; ++i)
      count += trace(angle_deg).beam_class == expected;
    return static_cast<double>(count) / beams;
  }
  World world_;
  RealisticPhysics physics_ = quietPhysics();
  std::mt19937 rng_{7};
};

// A pane on x = 5 (y in [-5, 5]) and a wall behind it on x = 10.
class PaneTest : public RealisticPhysicsTest {
 protected:
  void SetUp() override {
    world_.addSegment({5, -5}, {5, 5}, Material::kGlass, finish_);
    world_.addSegment({10, -30}, {10, 30}, Material::kDiffuse);
  }
  SurfaceFinish finish_;
};

TEST_F(PaneTest, ReturnsInsideTheConeCountingTheOutOfPlaneAngle) {
  EXPECT_EQ(trace(2.0).beam_class, BeamClass::kGlass);
  EXPECT_EQ(trace(3.0).beam_class, BeamClass::kReflection);
  // 2 deg in plane and 2 deg out of it: 2.8 deg from the normal, outside a 2.5 deg cone.
  EXPECT_EQ(trace(2.0, 2.0).beam_class, BeamClass::kReflection);
  EXPECT_EQ(trace(1.0, 2.0).beam_class, BeamClass::kGlass);  // 2.2 deg
}

TEST_F(PaneTest, APaneLeaningOutOfPlumbMeetsATiltedBeam) {
  world_ = World();
  finish_.tilt = 3.0 * kDeg;
  SetUp();
  EXPECT_EQ(trace(1.0).beam_class, BeamClass::kReflection);  // 3.2 deg off a level beam
  EXPECT_EQ(trace(1.0, 3.0).beam_class, BeamClass::kGlass);  // the beam tilts with the pane
}

TEST_F(PaneTest, DirtScattersBackAtAnyAngle) {
  world_ = World();
  finish_.dirt = 0.2;
  SetUp();
  EXPECT_NEAR(share(15.0, BeamClass::kGlass), 0.2 * std::cos(15 * kDeg), 0.02);
  EXPECT_NEAR(share(40.0, BeamClass::kGlass), 0.2 * std::cos(40 * kDeg), 0.02);
}

TEST(PaneReflectanceTest, FresnelReflectanceOfAPane) {
  EXPECT_NEAR(paneReflectance(0.0, 1.5), 2 * 0.04 / 1.04, 1e-9);  // two faces, 4 % each
  EXPECT_LT(paneReflectance(40 * kDeg, 1.5), 0.10);
  EXPECT_GT(paneReflectance(80 * kDeg, 1.5), 0.5);
  EXPECT_GT(paneReflectance(89 * kDeg, 1.5), paneReflectance(85 * kDeg, 1.5));
  EXPECT_NEAR(paneReflectance(30 * kDeg, 1.0), 0.0, 1e-12);
}

TEST_F(RealisticPhysicsTest, GrazingBeamsBounceOffPanesAsFresnelSays) {
  // A pane on x = 1 and a wall behind it on x = 2: a transmitted beam returns the wall, a
  // reflected one leaves into empty space and returns nothing.
  world_.addSegment({1, -10}, {1, 10}, Material::kGlass);
  world_.addSegment({2, -20}, {2, 20}, Material::kDiffuse);
  physics_.refractive_index = 1.5;
  EXPECT_NEAR(share(80.0, BeamClass::kNoReturn), paneReflectance(80 * kDeg, 1.5), 0.03);
  EXPECT_NEAR(share(20.0, BeamClass::kNoReturn), paneReflectance(20 * kDeg, 1.5), 0.02);
}

TEST_F(RealisticPhysicsTest, GlassWithNothingBehindEchoesWeakly) {
  world_.addSegment({5, -5}, {5, 5}, Material::kGlass);
  physics_.empty_echo_probability = 0.5;
  physics_.empty_echo_decay_deg = 20.0;
  EXPECT_NEAR(share(20.0, BeamClass::kGlass), 0.5 * std::exp(-1.0), 0.03);
  const BeamResult beam = [&] {
    for (int i = 0; i < 100; ++i) {
      const BeamResult b = trace(20.0);
      if (b.beam_class == BeamClass::kGlass) return b;
    }
    return BeamResult{};
  }();
  EXPECT_NEAR(beam.range, 5.0 / std::cos(20 * kDeg), 1e-9);  // at the pane, not beyond
  // With a wall behind, the wall answers: no echo of the pane.
  world_.addSegment({10, -30}, {10, 30}, Material::kDiffuse);
  EXPECT_EQ(share(20.0, BeamClass::kGlass), 0.0);
}

// Metal on x = 5, a wall on y = 12 catching what the metal mirrors.
class MetalTest : public RealisticPhysicsTest {
 protected:
  void SetUp() override {
    world_.addSegment({5, -20}, {5, 20}, Material::kMetal);
    world_.addSegment({-30, 12}, {30, 12}, Material::kDiffuse);
    physics_.metal_lobe_deg = 10.0;
  }
};

TEST_F(MetalTest, ReturnsInItsLobeAndMirrorsBeyond) {
  EXPECT_EQ(trace(9.0).beam_class, BeamClass::kMetal);
  const BeamResult mirrored = trace(30.0);
  EXPECT_EQ(mirrored.beam_class, BeamClass::kReflection);
  EXPECT_EQ(mirrored.interactions, 1);
}

TEST_F(MetalTest, WeakReturnsFadeBeyondTheLobe) {
  physics_.metal_tail_probability = 0.4;
  physics_.metal_tail_decay_deg = 10.0;
  EXPECT_NEAR(share(15.0, BeamClass::kMetal), 0.4 * std::exp(-0.5), 0.03);
  EXPECT_NEAR(share(40.0, BeamClass::kMetal), 0.4 * std::exp(-3.0), 0.015);
}

// A wall on y = 1 seen along its length from the origin, a wall on x = 25 that catches what it
// reflects, and a far wall on y = -8.
class GrazingTest : public RealisticPhysicsTest {
 protected:
  void SetUp() override {
    world_.addSegment({-30, 1}, {30, 1}, Material::kDiffuse);
    world_.addSegment({25, -30}, {25, 0.99}, Material::kDiffuse);
    world_.addSegment({-30, -8}, {24, -8}, Material::kDiffuse);
  }
};

TEST_F(GrazingTest, PastTheLimitBeamsAreLostOrBounceOffGlossyPaint) {
  // 3 deg above the wall's direction: 87 deg incidence, past the 85 deg limit.
  EXPECT_EQ(share(3.0, BeamClass::kNoReturn), 1.0);
  physics_.gloss_probability = 0.3;
  EXPECT_NEAR(share(3.0, BeamClass::kReflection), 0.3, 0.03);
  EXPECT_EQ(trace(20.0).beam_class, BeamClass::kDiffuse);  // 70 deg: an ordinary return
}

TEST_F(GrazingTest, FaintReturnsAreLostAtGrazingAndFarAway) {
  physics_.grazing_dropout = 0.5;
  // 70 deg of an 85 deg limit: lost with 0.5 * (70 / 85)^6.
  EXPECT_NEAR(share(20.0, BeamClass::kNoReturn), 0.5 * std::pow(70.0 / 85.0, 6), 0.025);
  EXPECT_NEAR(share(90.0, BeamClass::kNoReturn), 0.0, 1e-12);  // head-on at 1 m
  physics_.grazing_dropout = 0.0;
  physics_.range_dropout = 0.8;
  // Straight down to y = -8: 8 m of a 30 m range.
  EXPECT_NEAR(share(-90.0, BeamClass::kNoReturn), 0.8 * std::pow(8.0 / 30.0, 2), 0.02);
}

TEST(RealisticPhysicsValidationTest, NamesTheBadParameter) {
  RealisticPhysics p;
  p.return_cone_deg = -1.0;
  try {
    p.validate();
    FAIL() << "a negative cone passed";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("return_cone_deg"), std::string::npos);
  }
  p = RealisticPhysics();
  p.range_dropout = 2.0;
  EXPECT_THROW(p.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace rfm::sim
