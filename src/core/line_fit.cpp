#include "reflectance_field_map/core/line_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

LineFit fitLine(const std::vector<Eigen::Vector2d>& points) {
  LineFit line;
  for (const Eigen::Vector2d& p : points)
    line.centre += p;
  line.centre /= static_cast<double>(points.size());
  double xx = 0.0, xy = 0.0, yy = 0.0;
  for (const Eigen::Vector2d& point : points) {
    const Eigen::Vector2d p = point - line.centre;
    xx += p.x() * p.x();
    xy += p.x() * p.y();
    yy += p.y() * p.y();
  }
  const double angle = 0.5 * std::atan2(2.0 * xy, xx - yy);
  line.direction = Eigen::Vector2d(std::cos(angle), std::sin(angle));
  const Eigen::Vector2d normal(-line.direction.y(), line.direction.x());
  for (const Eigen::Vector2d& point : points) {
    const Eigen::Vector2d p = point - line.centre;
    line.across = std::max(line.across, std::abs(p.dot(normal)));
    line.first = std::min(line.first, p.dot(line.direction));
    line.last = std::max(line.last, p.dot(line.direction));
  }
  return line;
}

}  // namespace rfm
