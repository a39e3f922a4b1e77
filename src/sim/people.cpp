#include "reflectance_field_map/sim/people.h"

#include <cmath>
#include <stdexcept>

namespace rfm::sim {

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
  }
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

std::vector<Circle> peopleAt(const std::vector<Pedestrian>& people, double t) {
  std::vector<Circle> present;
  for (const Pedestrian& person : people) {
    if (const auto center = person.positionAt(t))
      present.push_back({*center, person.spec().radius});
  }
  return present;
}

}  // namespace rfm::sim
