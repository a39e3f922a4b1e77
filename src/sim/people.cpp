#include "reflectance_field_map/sim/people.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rfm::sim {
namespace {

// The gait seen at a lidar's height (about a third of the way from the foot to the hip): each
// foot stands planted for 60 % of a stride, then swings to its next plant; the two feet alternate,
// a hip's width apart.
constexpr double kStanceShare = 0.6;
constexpr double kFootSpacing = 0.09;  // each foot's lateral offset from the path, m
constexpr double kLegHeightShare = 1.0 / 3.0;

Eigen::Vector2d leftOf(const Eigen::Vector2d& direction) {
  return {-direction.y(), direction.x()};
}

}  // namespace

Pedestrian::Pedestrian(PersonSpec spec) : spec_(std::move(spec)) {
  if (spec_.waypoints.empty()) throw std::invalid_argument("a person needs at least one waypoint");
  if (!(spec_.radius > 0.0)) throw std::invalid_argument("person radius must be positive");
  if (!(spec_.speed > 0.0)) throw std::invalid_argument("person speed must be positive");
  const std::size_t count = spec_.waypoints.size();
  // One leg per waypoint; the last leads back to the start when looping, else nowhere.
  for (std::size_t i = 0; i < count; ++i) {
    const PersonWaypoint& here = spec_.waypoints[i];
    const bool last = i + 1 == count;
    const Eigen::Vector2d next =
        last ? (spec_.loop ? spec_.waypoints.front().position : here.position)
             : spec_.waypoints[i + 1].position;
    const double walk = (next - here.position).norm() / spec_.speed;
    legs_.push_back({here.position, next, std::max(0.0, here.pause), walk});
    cycle_duration_ += legs_.back().pause + walk;
    path_length_ += (next - here.position).norm();
  }
  if (spec_.legs) {
    if (!(spec_.leg_radius > 0.0)) throw std::invalid_argument("leg radius must be positive");
    if (legReach() > spec_.radius + 1e-9) {
      throw std::invalid_argument("person radius " + std::to_string(spec_.radius) +
                                  " m is smaller than the legs' reach " +
                                  std::to_string(legReach()) + " m at this speed");
    }
  }
}

double Pedestrian::stride() const {
  // Two steps; a step lengthens with walking speed (0.66 m at 1.2 m/s).
  return 2.0 * std::clamp(0.3 + 0.3 * spec_.speed, 0.45, 0.8);
}

double Pedestrian::legReach() const {
  if (!spec_.legs) return 0.0;
  // A planted foot is at most half the stance from the body; the eased swing overshoots that by
  // under 5 % of a stride.
  const double foot_ahead = (0.5 * kStanceShare + 0.02) * stride();
  const double along = (1.0 - kLegHeightShare) * foot_ahead;
  return std::hypot(along, kFootSpacing) + spec_.leg_radius;
}

double Pedestrian::distanceAt(double t) const {
  double local = t - spec_.start_time;
  double completed = 0.0;  // path length of the loops already walked
  if (spec_.loop && cycle_duration_ > 0.0) {
    const double loops = std::floor(local / cycle_duration_);
    completed = loops * path_length_;
    local -= loops * cycle_duration_;
  }
  double distance = 0.0;
  for (const Leg& leg : legs_) {
    if (local <= leg.pause) return completed + distance;
    local -= leg.pause;
    const double length = (leg.to - leg.from).norm();
    if (local <= leg.walk)
      return completed + distance + (leg.walk > 0.0 ? local / leg.walk : 1.0) * length;
    local -= leg.walk;
    distance += length;
  }
  return completed + distance;
}

std::pair<Eigen::Vector2d, Eigen::Vector2d> Pedestrian::pathPointAt(double distance) const {
  if (spec_.loop && path_length_ > 0.0) {
    distance = std::fmod(distance, path_length_);
    if (distance < 0.0) distance += path_length_;
  } else {
    distance = std::clamp(distance, 0.0, path_length_);
  }
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();
  Eigen::Vector2d point = legs_.front().from;
  for (const Leg& leg : legs_) {
    const double length = (leg.to - leg.from).norm();
    if (length <= 1e-12) continue;
    direction = (leg.to - leg.from) / length;
    point = leg.to;
    if (distance <= length) return {leg.from + distance * direction, direction};
    distance -= length;
  }
  return {point, direction};
}

std::optional<Eigen::Vector2d> Pedestrian::positionAt(double t) const {
  if (t < spec_.start_time || t > spec_.end_time) return std::nullopt;
  double local = t - spec_.start_time;
  if (spec_.loop && cycle_duration_ > 0.0) {
    local = std::fmod(local, cycle_duration_);
  } else if (local > cycle_duration_) {
    return std::nullopt;  // reached the end of the path: left the scene
  }
  for (const Leg& leg : legs_) {
    if (local <= leg.pause) return leg.from;
    local -= leg.pause;
    if (local <= leg.walk) {
      const double fraction = leg.walk > 0.0 ? local / leg.walk : 1.0;
      return Eigen::Vector2d(leg.from + fraction * (leg.to - leg.from));
    }
    local -= leg.walk;
  }
  return legs_.back().to;
}

void Pedestrian::appendBody(double t, std::vector<Circle>& out) const {
  const std::optional<Eigen::Vector2d> center = positionAt(t);
  if (!center) return;
  if (!spec_.legs) {
    out.push_back({*center, spec_.radius});
    return;
  }
  const double walked = distanceAt(t);
  const auto [centre_point, centre_direction] = pathPointAt(walked);
  const double stride_length = stride();
  for (int foot = 0; foot < 2; ++foot) {
    const double side = foot == 0 ? 1.0 : -1.0;
    // This foot plants every stride; the other half a stride later. A plant lies half the stance
    // ahead of where the body is when the foot lands.
    const double phase = (walked - foot * 0.5 * stride_length) / stride_length;
    const double cycle = std::floor(phase);
    const double within = phase - cycle;
    const double plant = (cycle + 0.5 * kStanceShare) * stride_length + foot * 0.5 * stride_length;
    double foot_distance = plant;
    if (within > kStanceShare) {  // swinging to the next plant, easing in and out
      const double u = (within - kStanceShare) / (1.0 - kStanceShare);
      foot_distance += stride_length * u * u * (3.0 - 2.0 * u);
    }
    const auto [foot_point, foot_direction] = pathPointAt(foot_distance);
    const Eigen::Vector2d foot_position = foot_point + side * kFootSpacing * leftOf(foot_direction);
    const Eigen::Vector2d hip = centre_point + side * kFootSpacing * leftOf(centre_direction);
    out.push_back({foot_position + kLegHeightShare * (hip - foot_position), spec_.leg_radius});
  }
}

std::vector<Circle> peopleAt(const std::vector<Pedestrian>& people, double t) {
  std::vector<Circle> present;
  for (const Pedestrian& person : people)
    person.appendBody(t, present);
  return present;
}

std::optional<WallCollision> findWallCollision(const PersonSpec& person, const World& world) {
  constexpr int kDirections = 16;
  constexpr double kStep = 0.05;  // m along the path
  const std::size_t n = person.waypoints.size();
  if (n == 0) return std::nullopt;
  const std::size_t walks = person.loop && n > 1 ? n : n - 1;
  for (std::size_t k = 0; k < std::max<std::size_t>(walks, 1); ++k) {
    const Eigen::Vector2d from = person.waypoints[k].position;
    const Eigen::Vector2d to = person.waypoints[(k + 1) % n].position;
    const int samples = static_cast<int>(std::ceil((to - from).norm() / kStep));
    for (int j = 0; j <= samples; ++j) {
      const Eigen::Vector2d centre = from + (to - from) * (samples ? double(j) / samples : 0.0);
      for (int d = 0; d < kDirections; ++d) {
        const double angle = 2.0 * M_PI * d / kDirections;
        const Eigen::Vector2d direction(std::cos(angle), std::sin(angle));
        if (world.intersect(centre, direction, person.radius, {}, -1, 0.0)) {
          return WallCollision{k, from, to, centre};
        }
      }
    }
  }
  return std::nullopt;
}

}  // namespace rfm::sim
