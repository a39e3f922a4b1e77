#pragma once

#include <Eigen/Core>

#include <cmath>
#include <cstdint>

namespace rfm {

// Global integer cell index: cell (i, j) covers [i, i+1) x [j, j+1) times the resolution.
using CellIndex = Eigen::Vector2i;
// Global integer tile index: tile (i, j) holds cells [i*T, (i+1)*T) x [j*T, (j+1)*T).
using TileIndex = Eigen::Vector2i;

constexpr double kPi = 3.141592653589793;
constexpr double kTwoPi = 2.0 * kPi;

// Angle wrapped into [0, 2*pi).
inline double wrapTwoPi(double angle) {
  double wrapped = std::fmod(angle, kTwoPi);
  if (wrapped < 0.0) wrapped += kTwoPi;
  // fmod of a value just below a multiple of 2*pi can round up to 2*pi exactly.
  return wrapped >= kTwoPi ? 0.0 : wrapped;
}

// static_cast<int>(std::floor(value)) for values in int's range. std::floor is a library call
// or a long inline sequence on baseline x86-64 (no SSE4.1); this is a few instructions.
inline int floorToInt(double value) {
  const int truncated = static_cast<int>(value);
  return truncated - (value < truncated);
}

// floor(a / b) for integers, b > 0.
inline int floorDiv(int a, int b) {
  return a >= 0 ? a / b : -((-a + b - 1) / b);
}
// a mod b in [0, b), b > 0.
inline int positiveMod(int a, int b) {
  const int m = a % b;
  return m < 0 ? m + b : m;
}

// A rigid 2D pose (REP-103: metres, radians, counter-clockwise yaw).
struct Pose2D {
  Eigen::Vector2d position{0.0, 0.0};
  double yaw = 0.0;

  Eigen::Vector2d transform(const Eigen::Vector2d& point) const {
    const double c = std::cos(yaw), s = std::sin(yaw);
    return position + Eigen::Vector2d(c * point.x() - s * point.y(), s * point.x() + c * point.y());
  }
  // this * other: `other` expressed in this pose's frame, returned in the parent frame.
  Pose2D compose(const Pose2D& other) const { return {transform(other.position), yaw + other.yaw}; }
};

// Owns resolution and theta binning: world <-> cell <-> bin conversions.
class GridGeometry {
 public:
  GridGeometry(double resolution, int theta_bins)
      : resolution_(resolution),
        inverse_resolution_(1.0 / resolution),
        theta_bins_(theta_bins),
        bin_width_(kTwoPi / theta_bins) {}

  double resolution() const { return resolution_; }
  double inverseResolution() const { return inverse_resolution_; }
  int thetaBins() const { return theta_bins_; }
  double binWidth() const { return bin_width_; }

  CellIndex cellOf(const Eigen::Vector2d& point) const {
    return {floorToInt(point.x() * inverse_resolution_),
            floorToInt(point.y() * inverse_resolution_)};
  }
  Eigen::Vector2d cellCenter(const CellIndex& cell) const {
    return {(cell.x() + 0.5) * resolution_, (cell.y() + 0.5) * resolution_};
  }
  // Bin of a direction of travel; any angle, wrapped into [0, 2*pi).
  int binOf(double angle) const {
    const int bin = static_cast<int>(wrapTwoPi(angle) / bin_width_);
    return bin >= theta_bins_ ? theta_bins_ - 1 : bin;
  }
  double binCenter(int bin) const { return (wrapBin(bin) + 0.5) * bin_width_; }
  int wrapBin(int bin) const { return positiveMod(bin, theta_bins_); }

 private:
  double resolution_;
  double inverse_resolution_;
  int theta_bins_;
  double bin_width_;
};

// Axis-aligned half-open box of cells [min, max).
struct CellBox {
  CellIndex min{0, 0};
  CellIndex max{0, 0};

  bool contains(const CellIndex& cell) const {
    return cell.x() >= min.x() && cell.y() >= min.y() && cell.x() < max.x() && cell.y() < max.y();
  }
  bool contains(const CellBox& other) const {
    return other.min.x() >= min.x() && other.min.y() >= min.y() && other.max.x() <= max.x() &&
           other.max.y() <= max.y();
  }
  bool empty() const { return max.x() <= min.x() || max.y() <= min.y(); }
  int width() const { return max.x() - min.x(); }
  int height() const { return max.y() - min.y(); }
  // Row-major index (x fastest) of a cell inside the box, and the cell at such an index.
  int indexOf(const CellIndex& cell) const {
    return (cell.y() - min.y()) * width() + (cell.x() - min.x());
  }
  CellIndex cellAt(int index) const {
    return {min.x() + index % width(), min.y() + index / width()};
  }
  CellBox intersect(const CellBox& other) const {
    return {min.cwiseMax(other.min), max.cwiseMin(other.max)};
  }
  CellBox unite(const CellBox& other) const {
    if (empty()) return other;
    if (other.empty()) return *this;
    return {min.cwiseMin(other.min), max.cwiseMax(other.max)};
  }
};

}  // namespace rfm
