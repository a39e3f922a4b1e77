#include "reflectance_field_map/core/laser_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rfm {

std::string LaserScan2D::validate() const {
  // Called for every scan of every pass: a message is composed only when something is wrong.
  auto why = [](const auto&... parts) {
    std::ostringstream out;
    (out << ... << parts);
    return out.str();
  };
  if (!std::isfinite(angle_min) || !std::isfinite(angle_max) || !std::isfinite(angle_increment)) {
    return why("non-finite angles");
  }
  if (angle_increment <= 0.0f) return why("angle_increment ", angle_increment, " must be > 0");
  if (!std::isfinite(range_min) || !std::isfinite(range_max) || range_min < 0.0f ||
      range_max <= range_min) {
    return why("range limits [", range_min, ", ", range_max, "] are not 0 <= min < max");
  }
  if (ranges.empty()) return why("no ranges");
  if (!sweep_shift.allFinite()) return why("non-finite sweep shift");
  // Drivers differ on whether angle_max is the last beam or one step past it.
  const double span_beams = (static_cast<double>(angle_max) - angle_min) / angle_increment;
  const double expected = span_beams + 1.0;
  const double count = static_cast<double>(ranges.size());
  if (count > expected + 0.5 || count < expected - 1.5) {
    return why(ranges.size(), " ranges but the angles [", angle_min, ", ", angle_max, "] step ",
               angle_increment, " give ", std::lround(expected));
  }
  return {};
}

namespace {

float lastBeamAngle(const LaserScan2D& scan) {
  const size_t beams = std::max<size_t>(scan.ranges.size(), 1);
  return scan.angle_min + scan.angle_increment * static_cast<float>(beams - 1);
}

}  // namespace

void reverseBeamOrder(LaserScan2D& scan) {
  const float span = scan.angle_max - scan.angle_min;  // negative, like the increment
  scan.angle_min = lastBeamAngle(scan);
  scan.angle_increment = -scan.angle_increment;
  scan.angle_max = scan.angle_min - span;
  std::reverse(scan.ranges.begin(), scan.ranges.end());
  scan.sweep_shift = -scan.sweep_shift;  // from the first listed beam to the last
}

bool compensateSweepMotion(LaserScan2D& scan, Pose2D& sensor_pose, const Pose2D& sweep_end_pose,
                           bool beam0_last) {
  const size_t beams = scan.ranges.size();
  if (beams < 2 || !(scan.angle_increment > 0.0f)) return false;
  const double turn = std::remainder(sweep_end_pose.yaw - sensor_pose.yaw, 2.0 * M_PI);
  const double per_beam = turn / static_cast<double>(beams - 1);
  const double increment = scan.angle_increment + (beam0_last ? -per_beam : per_beam);
  if (!(increment > 0.0) || !std::isfinite(increment)) return false;
  const double span_beams = (static_cast<double>(scan.angle_max) - scan.angle_min) /
                            static_cast<double>(scan.angle_increment);
  scan.angle_increment = static_cast<float>(increment);
  scan.angle_max = static_cast<float>(scan.angle_min + span_beams * increment);
  if (beam0_last) sensor_pose.yaw += turn;  // beam 0 was measured at the sweep's end
  const Eigen::Vector2d travel = sweep_end_pose.position - sensor_pose.position;
  sensor_pose.position += 0.5 * travel;
  scan.sweep_shift = beam0_last ? -travel : travel;
  return true;
}

double sweepSeconds(double time_increment, size_t beams) {
  if (beams < 2 || !std::isfinite(time_increment)) return 0.0;
  const double sweep = std::abs(time_increment) * static_cast<double>(beams - 1);
  return sweep <= kMaxSweepSeconds ? sweep : 0.0;
}

void mirrorScan(LaserScan2D& scan) {
  // Beam k at angle a_k in the upside-down frame points at -a_k seen from above.
  const float span = scan.angle_max - scan.angle_min;
  scan.angle_min = -lastBeamAngle(scan);
  scan.angle_max = scan.angle_min + span;
  std::reverse(scan.ranges.begin(), scan.ranges.end());
  scan.sweep_shift = -scan.sweep_shift;
}

void scanToRays(const LaserScan2D& scan, const Pose2D& sensor_pose, const InsertionOptions& options,
                std::vector<Ray>& rays) {
  rays.clear();
  rays.reserve(scan.ranges.size());
  forEachBeamRay(scan, sensor_pose, options, [&rays](const Ray& ray) { rays.push_back(ray); });
}

void beamsTowardsBox(const CellBox& box, double resolution, const Eigen::Vector2d& origin,
                     double first_beam_angle, double increment, double end_spread,
                     std::vector<BeamRange>& ranges) {
  ranges.clear();
  const Eigen::Vector2d spread = Eigen::Vector2d::Constant(std::max(end_spread, 0.0));
  const Eigen::Vector2d low = box.min.cast<double>() * resolution - spread;
  const Eigen::Vector2d high = box.max.cast<double>() * resolution + spread;
  const Eigen::Vector2d margin = Eigen::Vector2d::Constant(resolution);
  if ((origin.array() >= (low - margin).array()).all() &&
      (origin.array() <= (high + margin).array()).all()) {
    ranges.push_back({0, std::numeric_limits<uint32_t>::max()});
    return;
  }
  // Outside the box, its extent is under pi and spanned by its corners.
  const Eigen::Vector2d centre = 0.5 * (low + high) - origin;
  const double towards_centre = std::atan2(centre.y(), centre.x());
  double lo = 0.0, hi = 0.0;
  for (const Eigen::Vector2d& corner :
       {low, high, Eigen::Vector2d(low.x(), high.y()), Eigen::Vector2d(high.x(), low.y())}) {
    const Eigen::Vector2d d = corner - origin;
    const double offset = std::remainder(std::atan2(d.y(), d.x()) - towards_centre, kTwoPi);
    lo = std::min(lo, offset);
    hi = std::max(hi, offset);
  }
  const double slack = 2.0 * increment;
  double start = std::fmod(towards_centre + lo - slack - first_beam_angle, kTwoPi);
  if (start < 0.0) start += kTwoPi;
  const double end = start + (hi - lo) + 2.0 * slack;
  auto beam_at_or_after = [&](double angle) {
    return static_cast<uint32_t>(std::clamp(std::ceil(angle / increment), 0.0, 4e9));
  };
  auto beam_at_or_before = [&](double angle) {
    return static_cast<uint32_t>(std::clamp(std::floor(angle / increment), 0.0, 4e9));
  };
  // The extent and its copies a turn either side (a scan of over a turn repeats directions).
  for (const double turn : {-kTwoPi, 0.0, kTwoPi}) {
    if (end + turn >= 0.0) {
      ranges.push_back(
          {beam_at_or_after(std::max(0.0, start + turn)), beam_at_or_before(end + turn)});
    }
  }
}

}  // namespace rfm
