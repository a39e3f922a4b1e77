#include "reflectance_field_map/sim/navigation_grid.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace rfm::sim {
namespace {

constexpr float kInfinity = std::numeric_limits<float>::infinity();
// Stands for "no surface" in the distance transform: far beyond any squared distance in a grid.
constexpr double kFar = 1e18;

// One dimension of the exact squared Euclidean distance transform (Felzenszwalb & Huttenlocher):
// d[q] = min over p of (q - p)^2 + f[p].
void distanceTransform1d(const std::vector<double>& f, std::vector<double>& d, std::vector<int>& v,
                         std::vector<double>& z) {
  const int n = static_cast<int>(f.size());
  int k = 0;
  v[0] = 0;
  z[0] = -kFar;
  z[1] = kFar;
  auto intersection = [&](int q, int p) {
    return ((f[q] + double(q) * q) - (f[p] + double(p) * p)) / (2.0 * q - 2.0 * p);
  };
  for (int q = 1; q < n; ++q) {
    double s = intersection(q, v[k]);
    while (s <= z[k])
      s = intersection(q, v[--k]);  // z[0] is -kFar: stops at k = 0
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = kFar;
  }
  k = 0;
  for (int q = 0; q < n; ++q) {
    while (z[k + 1] < q)
      ++k;
    d[q] = double(q - v[k]) * (q - v[k]) + f[v[k]];
  }
}

}  // namespace

NavigationGrid::NavigationGrid(const World& world, const Eigen::Vector2d& low,
                               const Eigen::Vector2d& high, double resolution)
    : low_(low), resolution_(resolution) {
  width_ = std::max(1, static_cast<int>(std::ceil((high.x() - low.x()) / resolution)));
  height_ = std::max(1, static_cast<int>(std::ceil((high.y() - low.y()) / resolution)));
  std::vector<double> squared(static_cast<std::size_t>(width_) * height_, kFar);
  auto mark = [&](const Eigen::Vector2d& p) {
    if (const auto index = cellIndex(p)) squared[*index] = 0.0;
  };
  const double step = resolution / 4.0;
  for (const World::SegmentPrimitive& segment : world.segments()) {
    const double length = (segment.b - segment.a).norm();
    const int samples = std::max(1, static_cast<int>(std::ceil(length / step)));
    for (int i = 0; i <= samples; ++i)
      mark(segment.a + (segment.b - segment.a) * (static_cast<double>(i) / samples));
  }
  for (const World::ArcPrimitive& arc : world.arcs()) {
    const int samples = std::max(1, static_cast<int>(std::ceil(arc.radius * arc.sweep / step)));
    for (int i = 0; i <= samples; ++i) {
      const double angle = arc.start_angle + arc.sweep * i / samples;
      mark(arc.center + arc.radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    }
  }
  // Beyond the box counts as a surface: pad the border before the transform.
  for (int x = 0; x < width_; ++x) {
    squared[x] = 0.0;
    squared[static_cast<std::size_t>(height_ - 1) * width_ + x] = 0.0;
  }
  for (int y = 0; y < height_; ++y) {
    squared[static_cast<std::size_t>(y) * width_] = 0.0;
    squared[static_cast<std::size_t>(y) * width_ + width_ - 1] = 0.0;
  }
  const int longest = std::max(width_, height_);
  std::vector<double> f(longest), d(longest), z(longest + 1);
  std::vector<int> v(longest);
  for (int x = 0; x < width_; ++x) {  // columns
    f.resize(height_);
    d.resize(height_);
    for (int y = 0; y < height_; ++y)
      f[y] = squared[static_cast<std::size_t>(y) * width_ + x];
    distanceTransform1d(f, d, v, z);
    for (int y = 0; y < height_; ++y)
      squared[static_cast<std::size_t>(y) * width_ + x] = d[y];
  }
  for (int y = 0; y < height_; ++y) {  // rows
    f.assign(squared.begin() + static_cast<std::ptrdiff_t>(y) * width_,
             squared.begin() + static_cast<std::ptrdiff_t>(y + 1) * width_);
    d.resize(width_);
    distanceTransform1d(f, d, v, z);
    std::copy(d.begin(), d.end(), squared.begin() + static_cast<std::ptrdiff_t>(y) * width_);
  }
  clearance_.resize(squared.size());
  // Distances are between cell centres; a surface may lie anywhere in its cell, so half a cell
  // is taken off.
  for (std::size_t i = 0; i < squared.size(); ++i) {
    clearance_[i] =
        std::max(0.0f, static_cast<float>(std::sqrt(squared[i]) * resolution_ - 0.5 * resolution_));
  }
}

std::optional<int> NavigationGrid::cellIndex(const Eigen::Vector2d& point) const {
  const int x = static_cast<int>(std::floor((point.x() - low_.x()) / resolution_));
  const int y = static_cast<int>(std::floor((point.y() - low_.y()) / resolution_));
  if (x < 0 || y < 0 || x >= width_ || y >= height_) return std::nullopt;
  return y * width_ + x;
}

Eigen::Vector2d NavigationGrid::cellCentre(int index) const {
  return low_ + resolution_ * Eigen::Vector2d(index % width_ + 0.5, index / width_ + 0.5);
}

double NavigationGrid::clearance(const Eigen::Vector2d& point) const {
  const auto index = cellIndex(point);
  return index ? clearance_[*index] : 0.0;
}

bool NavigationGrid::lineClear(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                               double clearance) const {
  const double length = (b - a).norm();
  const int samples = std::max(1, static_cast<int>(std::ceil(length / (0.25 * resolution_))));
  for (int i = 0; i <= samples; ++i) {
    if (this->clearance(a + (b - a) * (static_cast<double>(i) / samples)) < clearance) return false;
  }
  return true;
}

std::optional<std::vector<Eigen::Vector2d>> NavigationGrid::path(
    const Eigen::Vector2d& start, const Eigen::Vector2d& goal, double clearance,
    const std::function<bool(const Eigen::Vector2d&)>& allowed) const {
  const auto start_index = cellIndex(start);
  const auto goal_index = cellIndex(goal);
  if (!start_index || !goal_index) return std::nullopt;
  auto passable = [&](int index) {
    return clearance_[index] >= clearance && (!allowed || allowed(cellCentre(index)));
  };
  if (!passable(*start_index) || !passable(*goal_index)) return std::nullopt;

  // A* over 8-connected cells.
  std::vector<float> cost(clearance_.size(), kInfinity);
  std::vector<int> parent(clearance_.size(), -1);
  using Entry = std::pair<float, int>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> open;
  const int gx = *goal_index % width_, gy = *goal_index / width_;
  auto heuristic = [&](int index) {
    const int dx = std::abs(index % width_ - gx), dy = std::abs(index / width_ - gy);
    return static_cast<float>(std::max(dx, dy) + (std::sqrt(2.0) - 1.0) * std::min(dx, dy));
  };
  cost[*start_index] = 0.0f;
  open.push({heuristic(*start_index), *start_index});
  while (!open.empty()) {
    const auto [priority, index] = open.top();
    open.pop();
    if (index == *goal_index) break;
    if (priority > cost[index] + heuristic(index) + 1e-3f) continue;  // stale entry
    const int x = index % width_, y = index / width_;
    for (int dy = -1; dy <= 1; ++dy) {
      for (int dx = -1; dx <= 1; ++dx) {
        if (!dx && !dy) continue;
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= width_ || ny >= height_) continue;
        const int next = ny * width_ + nx;
        if (!passable(next)) continue;
        const float step = (dx && dy) ? static_cast<float>(std::sqrt(2.0)) : 1.0f;
        if (cost[index] + step < cost[next]) {
          cost[next] = cost[index] + step;
          parent[next] = index;
          open.push({cost[next] + heuristic(next), next});
        }
      }
    }
  }
  if (cost[*goal_index] == kInfinity) return std::nullopt;
  std::vector<Eigen::Vector2d> cells;
  for (int index = *goal_index; index >= 0; index = parent[index])
    cells.push_back(cellCentre(index));
  std::reverse(cells.begin(), cells.end());
  cells.front() = start;
  cells.back() = goal;

  // Keep only the corners: from each kept point, jump to the farthest cell still in clear view.
  std::vector<Eigen::Vector2d> corners{cells.front()};
  std::size_t from = 0;
  while (from + 1 < cells.size()) {
    std::size_t to = cells.size() - 1;
    while (to > from + 1 && !lineClear(cells[from], cells[to], clearance))
      --to;
    corners.push_back(cells[to]);
    from = to;
  }
  return corners;
}

std::vector<Eigen::Vector2d> NavigationGrid::freeCells(const Eigen::Vector2d& low,
                                                       const Eigen::Vector2d& high,
                                                       double clearance) const {
  std::vector<Eigen::Vector2d> cells;
  for (int index = 0; index < width_ * height_; ++index) {
    if (clearance_[index] < clearance) continue;
    const Eigen::Vector2d centre = cellCentre(index);
    if ((centre.array() >= low.array()).all() && (centre.array() <= high.array()).all()) {
      cells.push_back(centre);
    }
  }
  return cells;
}

}  // namespace rfm::sim
