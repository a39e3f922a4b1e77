#include "reflectance_field_map/core/circle_fit.h"

#include <algorithm>
#include <cmath>

namespace rfm {

double NormalCircleFit::spread() const {
  const double mx = ux_ / weight_, my = uy_ / weight_;
  return 1.0 - (mx * mx + my * my);
}

NormalCircleFit::Circle NormalCircleFit::fit() const {
  // Minimising sum w |p - c + r u|^2: c = mean(p) + r mean(u), and r from the normal equation
  // sum w u.(p - c + r u) = 0, with |u| = 1.
  const double px = x_ / weight_, py = y_ / weight_;
  const double spread = this->spread();
  Circle circle;
  circle.radius = (px * ux_ + py * uy_ - along_) / weight_ / spread;
  // The residual at the minimum: the points' scatter less what the circle explains.
  const double scatter = squares_ / weight_ - (px * px + py * py);
  circle.rms = std::sqrt(std::max(0.0, scatter - circle.radius * circle.radius * spread));
  return circle;
}

double spreadOfTurn(double turn) {
  if (turn <= 0.0) return 0.0;
  const double mean_length = std::sin(0.5 * turn) / (0.5 * turn);
  return 1.0 - mean_length * mean_length;
}

}  // namespace rfm
