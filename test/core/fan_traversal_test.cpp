#include "reflectance_field_map/core/fan_traversal.h"
#include "reflectance_field_map/core/ray_insertion.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

namespace rfm {
namespace {

// 1/16 m: cell edges are exact in binary, so origins can sit exactly on edges and corners,
// where the traversal's tie-breaking decides.
constexpr double kResolution = 0.0625;
constexpr double kInverseResolution = 16.0;

std::set<int> walkedSlots(const std::vector<Ray>& rays, const RollingWindow& window) {
  std::set<int> slots;
  for (const Ray& ray : rays) {
    walkWindowCells(ray.origin, ray.end, kInverseResolution, window, true, [&](int slot, int, int) {
      slots.insert(slot);
      return true;
    });
  }
  return slots;
}

std::vector<int> sweptSlots(const std::vector<Ray>& rays, const RollingWindow& window) {
  std::vector<uint32_t> order(rays.size());
  for (size_t i = 0; i < order.size(); ++i)
    order[i] = static_cast<uint32_t>(i);
  std::vector<int> slots;
  visitCellsOfRays(rays, order.data(), order.size(), kInverseResolution, window,
                   [&](int slot) { slots.push_back(slot); });
  return slots;
}

// A window whose storage wraps inside its box, so sweeps cross the wrap.
RollingWindow wrappedWindow(std::mt19937& rng) {
  RollingWindow window(16, 12);
  std::uniform_int_distribution<int> tile(-40, 40);
  window.setOrigin({tile(rng), tile(rng)});
  return window;
}

// A fan as a scan's theta bin holds it: one origin, directions in order, any lengths, clipped to
// the window.
std::vector<Ray> randomFan(std::mt19937& rng, const RollingWindow& window) {
  const CellBox box = window.box();
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const Eigen::Vector2d size = (box.max - box.min).cast<double>();
  Eigen::Vector2d origin =
      (box.min.cast<double>() +
       Eigen::Vector2d(size.x() * (0.2 + 0.6 * unit(rng)), size.y() * (0.2 + 0.6 * unit(rng)))) *
      kResolution;
  // Origins on cell edges and corners, or rays along the grid axes, not both: a ray along an
  // edge passes within rounding of it, where either traversal may take either side (so may a
  // diagonal through corners). Real rays do not run within 1e-12 of a cell edge.
  double angle = unit(rng) * 2 * kPi;
  if (unit(rng) < 0.5) {
    if (unit(rng) < 0.5) origin.x() = std::round(origin.x() * kInverseResolution) * kResolution;
    if (unit(rng) < 0.5) origin.y() = std::round(origin.y() * kInverseResolution) * kResolution;
  } else if (unit(rng) < 0.3) {
    angle = std::floor(unit(rng) * 4) * kPi / 2;
  }
  const int count = 1 + static_cast<int>(unit(rng) * 40);
  const double increment = unit(rng) < 0.5 ? 0.0044 : unit(rng) * 0.05;
  const double length = unit(rng) * 12.0;
  std::vector<Ray> fan;
  for (int k = 0; k < count; ++k, angle += increment) {
    Ray ray;
    ray.origin = origin;
    const double range = unit(rng) < 0.1 ? 0.0 : length * (0.5 + unit(rng));
    ray.end = origin + range * Eigen::Vector2d(std::cos(angle), std::sin(angle));
    ray.angle = angle;
    ray.hit = true;
    if (clipRayToBox(box, kResolution, ray)) fan.push_back(ray);
  }
  return fan;
}

TEST(FanTraversal, VisitsEveryCellOfEveryRayAndNoOther) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 3000; ++trial) {
    const RollingWindow window = wrappedWindow(rng);
    const std::vector<Ray> fan = randomFan(rng, window);
    const std::vector<int> swept = sweptSlots(fan, window);
    ASSERT_EQ(std::set<int>(swept.begin(), swept.end()), walkedSlots(fan, window))
        << "trial " << trial;
  }
}

TEST(FanTraversal, RaysOfAnyOriginDirectionAndOrder) {
  std::mt19937 rng(12);
  for (int trial = 0; trial < 300; ++trial) {
    const RollingWindow window = wrappedWindow(rng);
    std::vector<Ray> rays;
    for (int f = 0; f < 4; ++f) {
      const std::vector<Ray> fan = randomFan(rng, window);
      rays.insert(rays.end(), fan.begin(), fan.end());
    }
    std::shuffle(rays.begin(), rays.end(), rng);
    const std::vector<int> swept = sweptSlots(rays, window);
    ASSERT_EQ(std::set<int>(swept.begin(), swept.end()), walkedSlots(rays, window))
        << "trial " << trial;
  }
}

TEST(FanTraversal, VisitsTheCellsOfABinsBeamsAboutOnce) {
  // The 8 beams of a UTM-30LX (0.25 deg apart) in one 2 deg bin, 8 m long, 5 cm cells.
  RollingWindow window(16, 24);
  window.setOrigin({-12, -12});
  std::vector<Ray> fan;
  for (int k = 0; k < 8; ++k) {
    Ray ray;
    ray.origin = {0.013, 0.021};
    ray.angle = 0.3 + k * 0.0043633;
    ray.end = ray.origin + 8.0 * Eigen::Vector2d(std::cos(ray.angle), std::sin(ray.angle));
    fan.push_back(ray);
  }
  std::vector<uint32_t> order{0, 1, 2, 3, 4, 5, 6, 7};
  std::vector<int> swept;
  visitCellsOfRays(fan, order.data(), order.size(), 20.0, window,
                   [&](int slot) { swept.push_back(slot); });
  size_t walked = 0;
  std::set<int> cells;
  for (const Ray& ray : fan) {
    walkWindowCells(ray.origin, ray.end, 20.0, window, true, [&](int slot, int, int) {
      ++walked;
      cells.insert(slot);
      return true;
    });
  }
  EXPECT_EQ(std::set<int>(swept.begin(), swept.end()), cells);
  EXPECT_GT(walked, 2 * cells.size());  // ray by ray, most cells are walked several times
  EXPECT_LE(swept.size(), cells.size() + cells.size() / 20);
}

}  // namespace
}  // namespace rfm
