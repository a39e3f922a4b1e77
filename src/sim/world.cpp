#include "reflectance_field_map/sim/world.h"

#include <algorithm>
#include <cmath>

namespace rfm::sim {
namespace {

constexpr double kTwoPi = 2.0 * M_PI;

double cross(const Eigen::Vector2d& p, const Eigen::Vector2d& q) {
  return p.x() * q.y() - p.y() * q.x();
}

double wrapPositive(double angle) {
  angle = std::fmod(angle, kTwoPi);
  return angle < 0.0 ? angle + kTwoPi : angle;
}

Eigen::Vector2d facing(Eigen::Vector2d normal, const Eigen::Vector2d& direction) {
  return normal.dot(direction) > 0.0 ? Eigen::Vector2d(-normal) : normal;
}

// Splits [0, length] into alternating diffuse frame pieces and `material` panes: a frame of
// frame_length at each end and evenly spaced mullions about every mullion_spacing. Returns
// (start, end, material) in order.
struct Piece {
  double start, end;
  Material material;
};
std::vector<Piece> framedPieces(double length, Material material, double frame_length,
                                double mullion_spacing) {
  std::vector<Piece> pieces;
  if (material == Material::kDiffuse || length <= 0.0 ||
      (frame_length <= 0.0 && mullion_spacing <= 0.0)) {
    pieces.push_back({0.0, length, material});
    return pieces;
  }
  const double frame = std::clamp(frame_length, 0.0, length / 4.0);
  int panes = 1;
  if (mullion_spacing > 0.0)
    panes = std::max(1, static_cast<int>(std::lround(length / mullion_spacing)));
  double cursor = 0.0;
  if (frame > 0.0) {
    pieces.push_back({0.0, frame, Material::kDiffuse});
    cursor = frame;
  }
  for (int k = 1; k < panes; ++k) {
    const double mullion_center = length * k / panes;
    const double half = std::max(frame, 0.02) / 2.0;
    pieces.push_back({cursor, mullion_center - half, material});
    pieces.push_back({mullion_center - half, mullion_center + half, Material::kDiffuse});
    cursor = mullion_center + half;
  }
  pieces.push_back({cursor, length - frame, material});
  if (frame > 0.0) pieces.push_back({length - frame, length, Material::kDiffuse});
  return pieces;
}

}  // namespace

const char* materialName(Material material) {
  switch (material) {
    case Material::kDiffuse:
      return "diffuse";
    case Material::kGlass:
      return "glass";
    case Material::kMirror:
      return "mirror";
    case Material::kMetal:
      return "metal";
  }
  return "unknown";
}

void World::addSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material material,
                       const SurfaceFinish& finish) {
  if ((b - a).norm() <= 1e-9) return;
  segments_.push_back({a, b, material, finish});
}

void World::addArc(const Eigen::Vector2d& center, double radius, double start_angle,
                   double end_angle, Material material, const SurfaceFinish& finish) {
  double sweep = end_angle - start_angle;
  if (radius <= 0.0 || std::abs(sweep) <= 1e-12) return;
  if (sweep < 0.0) {  // store counter-clockwise
    std::swap(start_angle, end_angle);
    sweep = -sweep;
  }
  sweep = std::min(sweep, kTwoPi);
  arcs_.push_back({center, radius, wrapPositive(start_angle), sweep, material, finish});
}

void World::addFramedSegment(const Eigen::Vector2d& a, const Eigen::Vector2d& b, Material material,
                             double frame_length, double mullion_spacing,
                             const SurfaceFinish& finish) {
  const double length = (b - a).norm();
  if (length <= 1e-9) return;
  const Eigen::Vector2d along = (b - a) / length;
  for (const Piece& piece : framedPieces(length, material, frame_length, mullion_spacing)) {
    addSegment(a + along * piece.start, a + along * piece.end, piece.material, finish);
  }
}

void World::addFramedArc(const Eigen::Vector2d& center, double radius, double start_angle,
                         double end_angle, Material material, double frame_length,
                         double mullion_spacing, const SurfaceFinish& finish) {
  if (end_angle < start_angle) std::swap(start_angle, end_angle);
  const double arc_length = radius * (end_angle - start_angle);
  for (const Piece& piece : framedPieces(arc_length, material, frame_length, mullion_spacing)) {
    addArc(center, radius, start_angle + piece.start / radius, start_angle + piece.end / radius,
           piece.material, finish);
  }
}

std::optional<Hit> World::intersect(const Eigen::Vector2d& origin, const Eigen::Vector2d& direction,
                                    double max_distance, const std::vector<Circle>& people,
                                    int ignore_surface, double min_distance) const {
  Hit best;
  best.distance = max_distance;
  bool found = false;

  for (std::size_t i = 0; i < segments_.size(); ++i) {
    if (static_cast<int>(i) == ignore_surface) continue;
    const SegmentPrimitive& segment = segments_[i];
    const Eigen::Vector2d edge = segment.b - segment.a;
    const double denominator = cross(direction, edge);
    if (std::abs(denominator) < 1e-12) continue;  // parallel: a zero-thickness wall is missed
    const Eigen::Vector2d to_start = segment.a - origin;
    const double s = cross(to_start, edge) / denominator;
    if (s <= min_distance || s > best.distance) continue;
    const double u = cross(to_start, direction) / denominator;
    if (u < 0.0 || u > 1.0) continue;
    best.distance = s;
    best.normal = facing(Eigen::Vector2d(-edge.y(), edge.x()).normalized(), direction);
    best.material = segment.material;
    best.is_person = false;
    best.surface_id = static_cast<int>(i);
    found = true;
  }

  const int arc_id_offset = static_cast<int>(segments_.size());
  for (std::size_t i = 0; i < arcs_.size(); ++i) {
    const int id = arc_id_offset + static_cast<int>(i);
    const ArcPrimitive& arc = arcs_[i];
    const Eigen::Vector2d offset = origin - arc.center;
    const double half_b = offset.dot(direction);
    const double c = offset.squaredNorm() - arc.radius * arc.radius;
    const double discriminant = half_b * half_b - c;
    if (discriminant < 0.0) continue;
    const double root = std::sqrt(discriminant);
    for (const double s : {-half_b - root, -half_b + root}) {
      // A concave arc may be left and re-hit by the same ray, so only the exact exit point of the
      // ignored surface is skipped (s tiny), not the whole arc.
      if (s <= min_distance || s > best.distance) continue;
      if (id == ignore_surface && s < 1e-6) continue;
      const Eigen::Vector2d point = origin + s * direction;
      const Eigen::Vector2d radial = point - arc.center;
      const double relative = wrapPositive(std::atan2(radial.y(), radial.x()) - arc.start_angle);
      if (relative > arc.sweep) continue;
      best.distance = s;
      best.normal = facing(radial / arc.radius, direction);
      best.material = arc.material;
      best.is_person = false;
      best.surface_id = id;
      found = true;
      break;
    }
  }

  for (const Circle& person : people) {
    const Eigen::Vector2d offset = origin - person.center;
    const double half_b = offset.dot(direction);
    const double c = offset.squaredNorm() - person.radius * person.radius;
    const double discriminant = half_b * half_b - c;
    if (discriminant < 0.0) continue;
    const double s = -half_b - std::sqrt(discriminant);  // outside face only: people are opaque
    if (s <= min_distance || s > best.distance) continue;
    best.distance = s;
    best.normal = facing((origin + s * direction - person.center) / person.radius, direction);
    best.material = Material::kDiffuse;
    best.is_person = true;
    best.surface_id = -1;
    found = true;
  }

  if (!found) return std::nullopt;
  best.point = origin + best.distance * direction;
  return best;
}

const SurfaceFinish& World::finish(int surface_id) const {
  const auto id = static_cast<std::size_t>(surface_id);
  return id < segments_.size() ? segments_.at(id).finish : arcs_.at(id - segments_.size()).finish;
}

std::pair<Eigen::Vector2d, Eigen::Vector2d> World::bounds() const {
  if (surfaceCount() == 0) return {Eigen::Vector2d::Zero(), Eigen::Vector2d::Zero()};
  Eigen::Vector2d low = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d high = -low;
  for (const SegmentPrimitive& segment : segments_) {
    low = low.cwiseMin(segment.a).cwiseMin(segment.b);
    high = high.cwiseMax(segment.a).cwiseMax(segment.b);
  }
  for (const ArcPrimitive& arc : arcs_) {  // conservative: the whole circle
    low = low.cwiseMin(arc.center - Eigen::Vector2d::Constant(arc.radius));
    high = high.cwiseMax(arc.center + Eigen::Vector2d::Constant(arc.radius));
  }
  return {low, high};
}

}  // namespace rfm::sim
