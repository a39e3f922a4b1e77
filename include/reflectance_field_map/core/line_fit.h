// The principal line of a set of points, and how the points lie along and across it.
#pragma once

#include <Eigen/Core>

#include <vector>

namespace rfm {

struct LineFit {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();      // the points' centroid
  Eigen::Vector2d direction = Eigen::Vector2d::UnitX();  // unit, along their main axis
  double across = 0.0;             // the largest distance of a point from the line
  double first = 0.0, last = 0.0;  // the points' extent along `direction` from `centre`
};

// The line through the centroid of `points` (not empty) along their principal axis.
LineFit fitLine(const std::vector<Eigen::Vector2d>& points);

}  // namespace rfm
