#include "reflectance_field_map/core/laser_scan.h"

#include "reflectance_field_map/core/ray_insertion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <utility>

namespace rfm {
namespace {

LaserScan2D fourBeamScan(std::vector<float> ranges) {
  LaserScan2D scan;
  scan.angle_min = 0.0f;
  scan.angle_increment = static_cast<float>(kPi / 2);
  scan.angle_max = static_cast<float>(1.5 * kPi);
  scan.range_min = 0.1f;
  scan.range_max = 10.0f;
  scan.ranges = std::move(ranges);
  return scan;
}

TEST(ClassifyBeam, FollowsRep117) {
  const float inf = std::numeric_limits<float>::infinity();
  EXPECT_EQ(classifyBeam(5.0f, 0.1f, 10.0f), BeamReading::kReturn);
  EXPECT_EQ(classifyBeam(0.1f, 0.1f, 10.0f), BeamReading::kReturn);
  EXPECT_EQ(classifyBeam(inf, 0.1f, 10.0f), BeamReading::kNoReturn);
  EXPECT_EQ(classifyBeam(10.0f, 0.1f, 10.0f), BeamReading::kNoReturn);
  EXPECT_EQ(classifyBeam(12.0f, 0.1f, 10.0f), BeamReading::kNoReturn);
  EXPECT_EQ(classifyBeam(-inf, 0.1f, 10.0f), BeamReading::kInvalid);
  EXPECT_EQ(classifyBeam(std::nanf(""), 0.1f, 10.0f), BeamReading::kInvalid);
  EXPECT_EQ(classifyBeam(0.05f, 0.1f, 10.0f), BeamReading::kInvalid);
}

TEST(ScanToRays, HitsClearingAndSkippedBeams) {
  const float inf = std::numeric_limits<float>::infinity();
  const LaserScan2D scan = fourBeamScan({2.0f, inf, std::nanf(""), 0.01f});
  InsertionOptions options;
  options.clearing_distance = 3.0;
  std::vector<Ray> rays;
  scanToRays(scan, Pose2D{{1.0, 1.0}, kPi / 2}, options, rays);
  ASSERT_EQ(rays.size(), 2u);
  EXPECT_TRUE(rays[0].hit);
  EXPECT_EQ(rays[0].beam, 0u);
  EXPECT_LT((rays[0].end - Eigen::Vector2d(1.0, 3.0)).norm(), 1e-5);  // beam 0 points along +y
  EXPECT_FALSE(rays[1].hit);
  EXPECT_EQ(rays[1].beam, 1u);
  EXPECT_LT((rays[1].end - Eigen::Vector2d(-2.0, 1.0)).norm(), 1e-5);  // cleared 3 m along -x
}

TEST(ScanToRays, ClearingDistanceNeverExceedsRangeMax) {
  LaserScan2D scan = fourBeamScan({std::numeric_limits<float>::infinity(), 1.0f, 1.0f, 1.0f});
  scan.range_max = 2.0f;
  InsertionOptions options;
  options.clearing_distance = 5.0;
  std::vector<Ray> rays;
  scanToRays(scan, Pose2D(), options, rays);
  EXPECT_NEAR((rays[0].end - rays[0].origin).norm(), 2.0, 1e-6);
}

// Directions come from a rotation recurrence between exact anchors: every beam of a long scan,
// sweeping either way, still ends where its own angle points.
TEST(ScanToRays, EveryBeamOfALongScanPointsAlongItsAngle) {
  for (const float increment : {0.25f * static_cast<float>(kPi) / 180, -0.0061f}) {
    LaserScan2D scan;
    scan.angle_min = 2.1f;
    scan.angle_increment = increment;
    scan.range_min = 0.1f;
    scan.range_max = 30.0f;
    scan.ranges.assign(1081, 25.0f);
    scan.angle_max = scan.angle_min + 1080 * increment;
    std::vector<Ray> rays;
    const Pose2D sensor{{3.0, -2.0}, -0.7};
    scanToRays(scan, sensor, InsertionOptions(), rays);
    ASSERT_EQ(rays.size(), 1081u);
    for (const Ray& ray : rays) {
      const double angle = sensor.yaw + scan.angle_min + ray.beam * static_cast<double>(increment);
      EXPECT_DOUBLE_EQ(ray.angle, angle);
      const Eigen::Vector2d expected =
          sensor.position + 25.0 * Eigen::Vector2d(std::cos(angle), std::sin(angle));
      EXPECT_LT((ray.end - expected).norm(), 1e-12) << "beam " << ray.beam;
    }
  }
}
// Every beam whose ray crosses the box lies in one of the ranges (online reflection removal
// looks only at those), and the ranges are far narrower than the scan for a small, far box.
TEST(BeamsTowardsBox, HoldEveryBeamCrossingTheBox) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> coordinate(-3.0, 3.0), angle(-10.0, 10.0), shift(-1, 1);
  std::uniform_int_distribution<int> cell(-60, 60), size(1, 30);
  constexpr double kResolution = 0.05;
  const InsertionOptions insertion;
  std::vector<Ray> rays;
  std::vector<BeamRange> ranges;
  size_t narrow = 0;
  for (int trial = 0; trial < 300; ++trial) {
    const CellIndex min(cell(rng), cell(rng));
    const CellBox box{min, min + CellIndex(size(rng), size(rng))};
    LaserScan2D scan;
    const bool full_turn = trial % 3 == 0;  // 1440 beams of 0.25 deg plus some: over a turn
    const int beams = full_turn ? 1450 : 1081;
    scan.angle_increment = static_cast<float>(0.25 * M_PI / 180.0);
    scan.angle_min = static_cast<float>(-0.75 * M_PI);
    scan.angle_max = scan.angle_min + (beams - 1) * scan.angle_increment;
    scan.range_min = 0.1f;
    scan.range_max = 30.0f;
    scan.ranges.assign(beams, 8.0f);
    // Every other trial a swept scan, its returns up to 15 cm off their beams' lines.
    if (trial % 2 == 1) scan.sweep_shift = {0.3 * shift(rng), 0.3 * shift(rng)};
    const Pose2D sensor{{coordinate(rng), coordinate(rng)}, angle(rng)};
    scanToRays(scan, sensor, insertion, rays);
    beamsTowardsBox(box, kResolution, sensor.position, sensor.yaw + scan.angle_min,
                    scan.angle_increment, 0.5 * scan.sweep_shift.norm(), ranges);
    ASSERT_LE(ranges.size(), 3u);
    for (size_t k = 1; k < ranges.size(); ++k)
      ASSERT_GT(ranges[k].first, ranges[k - 1].last) << "ranges ascend and are disjoint";
    size_t listed = 0;
    for (const BeamRange& range : ranges)
      listed += std::min<size_t>(range.last, beams - 1) + 1 - std::min<size_t>(range.first, beams);
    narrow += listed < 200;
    for (const Ray& ray : rays) {
      Ray clipped = ray;
      if (!clipRayToBox(box, kResolution, clipped)) continue;
      const bool listed_beam =
          std::any_of(ranges.begin(), ranges.end(), [&](const BeamRange& range) {
            return ray.beam >= range.first && ray.beam <= range.last;
          });
      ASSERT_TRUE(listed_beam) << "trial " << trial << " beam " << ray.beam;
    }
  }
  EXPECT_GT(narrow, 150u);
}

TEST(LaserScanValidate, RejectsMalformedScans) {
  EXPECT_EQ(fourBeamScan({1, 1, 1, 1}).validate(), "");
  // angle_max may be the last beam or one step past it (drivers differ); more is malformed.
  EXPECT_EQ(fourBeamScan({1, 1, 1}).validate(), "");
  EXPECT_NE(fourBeamScan({1, 1}).validate().find("2 ranges"), std::string::npos);
  EXPECT_NE(fourBeamScan({1, 1, 1, 1, 1}).validate().find("5 ranges"), std::string::npos);
  LaserScan2D negative = fourBeamScan({1, 1, 1, 1});
  negative.angle_increment = -negative.angle_increment;
  EXPECT_NE(negative.validate().find("angle_increment"), std::string::npos);
  LaserScan2D limits = fourBeamScan({1, 1, 1, 1});
  limits.range_max = 0.0f;
  EXPECT_NE(limits.validate().find("range"), std::string::npos);
  LaserScan2D nan_angle = fourBeamScan({1, 1, 1, 1});
  nan_angle.angle_min = std::nanf("");
  EXPECT_FALSE(nan_angle.validate().empty());
  EXPECT_FALSE(fourBeamScan({}).validate().empty());
}

// The direction of every beam with a range, keyed by its range (the ranges below are unique).
std::vector<std::pair<float, double>> beamDirections(const LaserScan2D& scan, double yaw) {
  InsertionOptions options;
  std::vector<Ray> rays;
  scanToRays(scan, Pose2D{{0.0, 0.0}, yaw}, options, rays);
  std::vector<std::pair<float, double>> directions;
  for (const Ray& ray : rays)
    directions.push_back({scan.ranges[ray.beam], std::remainder(ray.angle, 2 * kPi)});
  std::sort(directions.begin(), directions.end());
  return directions;
}

// A scan swept clockwise (negative increment) with a beam count that its angles may or may
// not account for.
LaserScan2D clockwiseScan(std::vector<float> ranges) {
  LaserScan2D scan = fourBeamScan(std::move(ranges));
  scan.angle_min = 1.0f;
  scan.angle_increment = -0.25f;
  scan.angle_max = 0.25f;  // 4 beams: 1, 0.75, 0.5, 0.25
  return scan;
}

TEST(ReverseBeamOrder, KeepsEveryBeamsDirectionAndTheCountCheck) {
  const LaserScan2D clockwise = clockwiseScan({1, 2, 3, 4});
  LaserScan2D reversed = clockwise;
  reverseBeamOrder(reversed);
  EXPECT_GT(reversed.angle_increment, 0.0f);
  EXPECT_EQ(reversed.validate(), "");
  EXPECT_EQ(reversed.ranges, (std::vector<float>{4, 3, 2, 1}));
  // Beam i of the original heads angle_min + i * increment, clockwise (unvalidated geometry).
  for (size_t i = 0; i < clockwise.ranges.size(); ++i) {
    const double original = 1.0 - 0.25 * static_cast<double>(i);
    const size_t j = clockwise.ranges.size() - 1 - i;
    EXPECT_NEAR(reversed.angle_min + reversed.angle_increment * j, original, 1e-6);
  }
  // Too few or too many beams for the angles stay malformed once reversed.
  for (const std::vector<float>& ranges : {std::vector<float>{1, 2}, {1, 2, 3, 4, 5}}) {
    LaserScan2D wrong = clockwiseScan(ranges);
    reverseBeamOrder(wrong);
    EXPECT_NE(wrong.validate().find(std::to_string(ranges.size()) + " ranges"), std::string::npos)
        << wrong.validate();
  }
}

TEST(MirrorScan, NegatesEveryBeamsDirectionAndKeepsTheCountCheck) {
  LaserScan2D scan = fourBeamScan({1, 2, 3, 4});
  scan.angle_min = 0.1f;
  scan.angle_increment = 0.3f;
  scan.angle_max = 1.0f;
  LaserScan2D mirrored = scan;
  mirrorScan(mirrored);
  EXPECT_EQ(mirrored.validate(), "");
  const auto before = beamDirections(scan, 0.0), after = beamDirections(mirrored, 0.0);
  ASSERT_EQ(before.size(), after.size());
  for (size_t i = 0; i < before.size(); ++i) {
    EXPECT_EQ(before[i].first, after[i].first);
    EXPECT_NEAR(after[i].second, -before[i].second, 1e-6) << "range " << before[i].first;
  }
  LaserScan2D truncated = scan;
  truncated.ranges.resize(2);
  mirrorScan(truncated);
  EXPECT_NE(truncated.validate().find("2 ranges"), std::string::npos) << truncated.validate();
}

// A sensor moving at constant speed and turn rate while it sweeps: beam k is measured at time
// k * dt from the pose reached then. `sweep_sign` -1 measures the beams from the last angle down
// (a clockwise sensor), as the message lists them.
struct SweepingSensor {
  Pose2D start{{1.0, 2.0}, 0.3};
  Eigen::Vector2d velocity{0.9, -0.3};  // m/s
  double turn_rate = 1.0;               // rad/s
  double dt = 1e-4;                     // s between beams: a 0.1 s sweep of 1001 beams

  Pose2D at(double t) const { return {start.position + t * velocity, start.yaw + t * turn_rate}; }
  // The true end point of each beam of `scan` (ranges as given; beam i measured at i * dt).
  std::vector<Eigen::Vector2d> endPoints(const LaserScan2D& scan) const {
    std::vector<Eigen::Vector2d> ends;
    for (size_t i = 0; i < scan.ranges.size(); ++i) {
      const Pose2D pose = at(static_cast<double>(i) * dt);
      const double angle = pose.yaw + scan.angle_min + scan.angle_increment * i;
      ends.push_back(pose.position +
                     scan.ranges[i] * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
    return ends;
  }
};

// The largest distance between the rays' ends and the true end points of their beams
// (`beam_of(ray.beam)`: the measured beam's index).
template <typename BeamOf>
double largestEndError(const LaserScan2D& scan, const Pose2D& pose,
                       const std::vector<Eigen::Vector2d>& truth, BeamOf beam_of) {
  std::vector<Ray> rays;
  scanToRays(scan, pose, InsertionOptions(), rays);
  EXPECT_EQ(rays.size(), truth.size());
  double largest = 0.0;
  for (const Ray& ray : rays)
    largest = std::max(largest, (ray.end - truth[beam_of(ray.beam)]).norm());
  return largest;
}

LaserScan2D sweptScan(size_t beams, float angle_min, float increment) {
  LaserScan2D scan;
  scan.angle_min = angle_min;
  scan.angle_increment = increment;
  scan.angle_max = angle_min + increment * static_cast<float>(beams - 1);
  scan.range_min = 0.1f;
  scan.range_max = 30.0f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> range(1.0f, 12.0f);
  for (size_t i = 0; i < beams; ++i)
    scan.ranges.push_back(range(rng));
  return scan;
}

TEST(CompensateSweepMotion, PutsEveryBeamWhereTheMovingSensorMeasuredIt) {
  const SweepingSensor sensor;
  const size_t beams = 1001;
  const double sweep = sensor.dt * (beams - 1);
  const double half_path = 0.5 * sweep * sensor.velocity.norm();  // the shared origin's offset
  const auto same = [](uint32_t beam) { return beam; };

  LaserScan2D scan = sweptScan(beams, -2.0f, 0.004f);
  const std::vector<Eigen::Vector2d> truth = sensor.endPoints(scan);
  // At the pose of the first beam alone, the last beams are off by the sweep's turn (0.1 rad).
  EXPECT_GT(largestEndError(scan, sensor.start, truth, same), 0.5);
  Pose2D pose = sensor.start;
  ASSERT_TRUE(compensateSweepMotion(scan, pose, sensor.at(sweep), false));
  EXPECT_EQ(scan.validate(), "");
  // From the sweep's middle, each return is moved by where its beam was measured from.
  EXPECT_NEAR((pose.position - sensor.at(0.5 * sweep).position).norm(), 0.0, 1e-12);
  EXPECT_LE(largestEndError(scan, pose, truth, same), 1e-5) << "against " << half_path;
}

TEST(CompensateSweepMotion, TurnsReversedBeamsFromTheSweepsEnd) {
  // A clockwise sensor: the message's beam i (measured at i * dt) heads 1.5 - 0.004 i.
  const SweepingSensor sensor;
  const size_t beams = 1001;
  const double sweep = sensor.dt * (beams - 1);
  const auto same = [](uint32_t beam) { return beam; };
  LaserScan2D scan = sweptScan(beams, 1.5f, -0.004f);
  const std::vector<Eigen::Vector2d> truth = sensor.endPoints(scan);
  reverseBeamOrder(scan);  // as the mapper takes it: beam j was measured (beams - 1 - j)-th
  const auto measured = [&](uint32_t beam) { return beams - 1 - beam; };
  Pose2D pose = sensor.start;
  EXPECT_GT(largestEndError(scan, pose, truth, measured), 0.5);
  ASSERT_TRUE(compensateSweepMotion(scan, pose, sensor.at(sweep), true));
  EXPECT_EQ(scan.validate(), "");
  EXPECT_LE(largestEndError(scan, pose, truth, measured), 1e-5);
  // Listed in the message's order again, the beams keep their ends.
  LaserScan2D relisted = scan;
  reverseBeamOrder(relisted);
  EXPECT_LE(largestEndError(relisted, pose, truth, same), 1e-5);
}

TEST(CompensateSweepMotion, LeavesScansItCannotTurnUnchanged) {
  LaserScan2D scan = sweptScan(101, -1.0f, 0.01f);
  const LaserScan2D before = scan;
  const Pose2D start{{0.0, 0.0}, 0.0};
  // Turning back by more than the sweep covers would reverse the beams' order.
  Pose2D pose = start;
  EXPECT_FALSE(compensateSweepMotion(scan, pose, Pose2D{{0.1, 0.0}, -1.5}, false));
  EXPECT_EQ(scan.angle_increment, before.angle_increment);
  EXPECT_EQ(scan.angle_max, before.angle_max);
  EXPECT_EQ(pose.position, start.position);
  LaserScan2D single = sweptScan(1, 0.0f, 0.01f);
  EXPECT_FALSE(compensateSweepMotion(single, pose, Pose2D{{0.1, 0.0}, 0.1}, false));
}

TEST(SweepSeconds, CountsTheSweepOnlyWhenTheMessageGivesOne) {
  EXPECT_DOUBLE_EQ(sweepSeconds(1e-4, 1001), 0.1);
  EXPECT_DOUBLE_EQ(sweepSeconds(-1e-4, 1001), 0.1);  // a clockwise sensor's sign
  EXPECT_EQ(sweepSeconds(0.0, 1001), 0.0);
  EXPECT_EQ(sweepSeconds(std::numeric_limits<double>::quiet_NaN(), 1001), 0.0);
  EXPECT_EQ(sweepSeconds(std::numeric_limits<double>::infinity(), 1001), 0.0);
  EXPECT_EQ(sweepSeconds(0.01, 1001), 0.0);  // a 10 s sweep: not a lidar's
  EXPECT_EQ(sweepSeconds(1e-4, 1), 0.0);
}

}  // namespace
}  // namespace rfm
