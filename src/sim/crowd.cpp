#include "reflectance_field_map/sim/crowd.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

namespace rfm::sim {
namespace {

using Vec = Eigen::Vector2d;

constexpr double kSampleStep = 0.05;  // s between the checks of who is where
constexpr double kPersonGap = 0.05;   // m kept between two footprints
constexpr double kSideBySide = 0.78;  // m between the centres of people walking abreast
constexpr int kAttemptsPerPerson = 25;

class CrowdBuilder {
 public:
  CrowdBuilder(Dice& dice, const CrowdSetting& setting) : dice_(dice), setting_(setting) {
    for (const FloorPlanArea& area : setting.plan.areas) {
      (area.outside ? street_areas_ : indoor_areas_).push_back(area);
    }
    samples_ = static_cast<std::size_t>(std::ceil(setting.duration / kSampleStep)) + 1;
    for (std::size_t k = 0; k < samples_; ++k) {
      robot_positions_.push_back(setting.robot.stateAt(k * kSampleStep).pose.position());
    }
  }

  std::vector<PersonSpec> build() {
    double floor_area = 0.0;
    for (const FloorPlanArea& area : indoor_areas_) {
      floor_area += (area.high - area.low).prod();
    }
    const int indoor =
        std::clamp(static_cast<int>(floor_area / 30.0 * dice_.uniform(0.5, 1.3)), 2, 16);
    for (int k = 0; k < indoor; ++k) {
      const double roll = dice_.uniform(0.0, 1.0);
      if (roll < 0.5) {
        addWithRetries([&] { return walker("walker"); });
      } else if (roll < 0.65) {
        addWithRetries([&] { return stander(); });
      } else if (roll < 0.87) {
        addWithRetries([&] { return walkingGroup(); });
      } else {
        addWithRetries([&] { return conversation(); });
      }
    }
    if (!street_areas_.empty()) {
      const int passers = dice_.integer(1, 4);
      for (int k = 0; k < passers; ++k)
        addWithRetries([&] { return walker("street", true); });
    }
    return accepted_;
  }

 private:
  // --- bodies and places ----------------------------------------------------------------------

  // A person's body: usually legs (what a lidar at 0.3 m sees), sometimes one disc (a long coat,
  // a bag, a child).
  PersonSpec body(const std::string& kind, double speed) {
    PersonSpec person;
    person.name = kind + std::to_string(next_id_++);
    person.speed = rounded(speed, 100);
    if (dice_.chance(0.8)) {
      person.legs = true;
      person.leg_radius = rounded(dice_.uniform(0.05, 0.08), 1000);
      PersonSpec probe = person;  // the legs' reach depends on the gait, hence the speed
      probe.radius = 1.0;
      probe.waypoints = {{Vec::Zero(), 0.0}};
      person.radius = rounded(Pedestrian(probe).legReach() + 0.005, 100);
    } else {
      person.radius = rounded(dice_.uniform(0.18, 0.28), 100);
    }
    return person;
  }

  const FloorPlanArea& area(bool street) {
    return dice_.pick(street ? street_areas_ : indoor_areas_);
  }

  // A random spot with `clearance` in `where`.
  std::optional<Vec> spot(const FloorPlanArea& where, double clearance) {
    for (int attempt = 0; attempt < 20; ++attempt) {
      const Vec p(rounded(dice_.uniform(where.low.x(), where.high.x()), 100),
                  rounded(dice_.uniform(where.low.y(), where.high.y()), 100));
      if (setting_.grid.clearance(p) >= clearance) return p;
    }
    return std::nullopt;
  }

  std::optional<std::vector<Vec>> route(const Vec& from, const Vec& to, double clearance) {
    auto path = setting_.grid.path(from, to, clearance);
    if (!path) return std::nullopt;
    for (Vec& p : *path)
      p = Vec(rounded(p.x(), 100), rounded(p.y(), 100));
    return path;
  }

  // Appends a route's points to `waypoints` (its first point is already the last waypoint).
  static void extend(std::vector<PersonWaypoint>& waypoints, const std::vector<Vec>& points) {
    for (std::size_t i = 1; i < points.size(); ++i)
      waypoints.push_back({points[i], 0.0});
  }

  double startTime(double latest_share = 0.85) {
    return rounded(dice_.uniform(0.0, latest_share * setting_.duration), 10);
  }

  // --- behaviours -----------------------------------------------------------------------------

  // Walks from a random spot through one to three goals, pausing at some, and leaves; now and
  // then walks a loop until a time.
  std::vector<PersonSpec> walker(const std::string& kind, bool street = false) {
    PersonSpec person = body(kind, dice_.uniform(0.8, 1.5));
    const double clearance = person.radius + 0.08;
    const auto start = spot(area(street), clearance);
    if (!start) return {};
    person.waypoints.push_back({*start, 0.0});
    const int goals = dice_.integer(1, 3);
    for (int g = 0; g < goals; ++g) {
      const auto goal = spot(area(street), clearance);
      if (!goal) return {};
      const auto path = route(person.waypoints.back().position, *goal, clearance);
      if (!path) return {};
      extend(person.waypoints, *path);
      if (g + 1 < goals && dice_.chance(0.35)) {
        person.waypoints.back().pause = rounded(dice_.uniform(1.0, 6.0), 10);
      }
    }
    person.start_time = startTime();
    if (person.waypoints.size() > 2 && dice_.chance(0.15)) {  // back to the start, and again
      const auto back = route(person.waypoints.back().position, *start, clearance);
      if (!back) return {};
      extend(person.waypoints, *back);
      person.waypoints.pop_back();  // the loop closes on the first waypoint itself
      person.loop = true;
      person.end_time = rounded(person.start_time + dice_.uniform(15.0, 60.0), 10);
    }
    return {person};
  }

  // Walks to a spot (or is there already), stands for a while, and walks away.
  std::vector<PersonSpec> stander() {
    PersonSpec person = body("stander", dice_.uniform(0.8, 1.3));
    const double clearance = person.radius + 0.08;
    const FloorPlanArea& where = area(false);
    const auto place = spot(where, clearance + 0.3);
    const auto leave = spot(area(false), clearance);
    if (!place || !leave) return {};
    if (dice_.chance(0.5)) {
      const auto start = spot(area(false), clearance);
      if (!start) return {};
      const auto arrive = route(*start, *place, clearance);
      if (!arrive) return {};
      person.waypoints.push_back({*start, 0.0});
      extend(person.waypoints, *arrive);
    } else {
      person.waypoints.push_back({*place, 0.0});
    }
    person.waypoints.back().pause = rounded(dice_.uniform(5.0, 30.0), 10);
    const auto away = route(*place, *leave, clearance);
    if (!away) return {};
    extend(person.waypoints, *away);
    person.start_time = startTime(0.7);
    return {person};
  }

  // Two or three people walking abreast along one route, pausing together.
  std::vector<PersonSpec> walkingGroup() {
    const int size = dice_.integer(2, 3);
    const double speed = dice_.uniform(0.8, 1.3);
    std::vector<PersonSpec> group;
    for (int k = 0; k < size; ++k)
      group.push_back(body("group", speed));
    double radius = 0.0;
    for (const PersonSpec& person : group)
      radius = std::max(radius, person.radius);
    const double half_width = 0.5 * (size - 1) * kSideBySide;
    const double clearance = radius + half_width + 0.1;
    const auto start = spot(area(false), clearance);
    const auto goal = spot(area(false), clearance);
    if (!start || !goal) return {};
    const auto path = route(*start, *goal, clearance);
    if (!path || path->size() < 2) return {};
    const double pause = dice_.chance(0.4) ? rounded(dice_.uniform(2.0, 8.0), 10) : 0.0;
    const std::size_t pause_at = path->size() > 2 ? 1 : 0;
    const double start_time = startTime();
    for (int k = 0; k < size; ++k) {
      const double offset = -half_width + k * kSideBySide;
      for (std::size_t i = 0; i < path->size(); ++i) {
        const Vec p = offsetPoint(*path, i, offset);
        group[k].waypoints.push_back(
            {Vec(rounded(p.x(), 100), rounded(p.y(), 100)), i == pause_at ? pause : 0.0});
      }
      group[k].start_time = start_time;
    }
    return group;
  }

  // Vertex i of `path` moved `offset` m to its left (mitred at corners).
  static Vec offsetPoint(const std::vector<Vec>& path, std::size_t i, double offset) {
    auto leftNormal = [&](std::size_t a, std::size_t b) {
      const Vec d = (path[b] - path[a]).normalized();
      return Vec(-d.y(), d.x());
    };
    const Vec before = i > 0 ? leftNormal(i - 1, i) : leftNormal(0, 1);
    const Vec after = i + 1 < path.size() ? leftNormal(i, i + 1) : before;
    Vec miter = before + after;
    if (miter.norm() < 1e-6) miter = after;
    miter.normalize();
    return path[i] + miter * (offset / std::max(0.5, miter.dot(after)));
  }

  // Two to four people standing in a circle, talking, then each going their own way.
  std::vector<PersonSpec> conversation() {
    const int size = dice_.integer(2, 4);
    std::vector<PersonSpec> group;
    for (int k = 0; k < size; ++k)
      group.push_back(body("talker", dice_.uniform(0.8, 1.3)));
    double radius = 0.0;
    for (const PersonSpec& person : group)
      radius = std::max(radius, person.radius);
    const double ring = (radius + 0.5 * kPersonGap + 0.02) / std::sin(M_PI / size);
    const auto centre = spot(area(false), ring + radius + 0.3);
    if (!centre) return {};
    const double talk = rounded(dice_.uniform(5.0, 25.0), 10);
    const double start_time = startTime(0.6);
    const double turn = dice_.uniform(0.0, 2.0 * M_PI);
    for (int k = 0; k < size; ++k) {
      PersonSpec& person = group[k];
      const double angle = turn + 2.0 * M_PI * k / size;
      const Vec place = *centre + ring * Vec(std::cos(angle), std::sin(angle));
      const Vec standing(rounded(place.x(), 100), rounded(place.y(), 100));
      const double clearance = person.radius + 0.08;
      const auto leave = spot(area(false), clearance);
      if (!leave) return {};
      const auto away = route(standing, *leave, clearance);
      if (!away) return {};
      // Each leaves a moment after the last, so they do not walk into one another.
      person.waypoints.push_back({standing, rounded(talk + 1.5 * k, 10)});
      extend(person.waypoints, *away);
      person.start_time = start_time;
    }
    return group;
  }

  // --- keeping people apart -------------------------------------------------------------------

  template <class MakeGroup>
  void addWithRetries(MakeGroup make) {
    for (int attempt = 0; attempt < kAttemptsPerPerson; ++attempt) {
      std::vector<PersonSpec> candidates = make();
      if (candidates.empty()) continue;
      if (acceptable(candidates)) {
        for (PersonSpec& person : candidates)
          accepted_.push_back(std::move(person));
        return;
      }
    }
  }

  // Every walk keeps clear of walls (as the scene loader checks), of the robot and of everyone.
  bool acceptable(const std::vector<PersonSpec>& candidates) {
    std::vector<Pedestrian> walkers;
    for (const PersonSpec& person : candidates) {
      if (person.waypoints.size() < 1) return false;
      if (person.start_time >= setting_.duration) return false;
      if (findWallCollision(person, setting_.world)) return false;
      walkers.emplace_back(person);
    }
    for (std::size_t k = 0; k < samples_; ++k) {
      const double t = k * kSampleStep;
      for (std::size_t i = 0; i < walkers.size(); ++i) {
        const auto position = walkers[i].positionAt(t);
        if (!position) continue;
        const double radius = walkers[i].spec().radius;
        if ((*position - robot_positions_[k]).norm() < radius + kRobotFootprintRadius) return false;
        auto apart = [&](const Pedestrian& other) {
          const auto there = other.positionAt(t);
          return !there || (*position - *there).norm() >= radius + other.spec().radius + kPersonGap;
        };
        for (std::size_t j = i + 1; j < walkers.size(); ++j)
          if (!apart(walkers[j])) return false;
        for (const Pedestrian& other : placed_)
          if (!apart(other)) return false;
      }
    }
    for (const Pedestrian& walker : walkers)
      placed_.push_back(walker);
    return true;
  }

  Dice& dice_;
  const CrowdSetting& setting_;
  std::vector<FloorPlanArea> indoor_areas_, street_areas_;
  std::size_t samples_ = 0;
  std::vector<Vec> robot_positions_;
  std::vector<PersonSpec> accepted_;
  std::vector<Pedestrian> placed_;
  int next_id_ = 1;
};

}  // namespace

std::vector<PersonSpec> generateCrowd(Dice& dice, const CrowdSetting& setting) {
  return CrowdBuilder(dice, setting).build();
}

}  // namespace rfm::sim
