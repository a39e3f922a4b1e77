// A circle fitted to points on a convex surface that returns a lidar's beam only along its
// normal (a polished round column): each point p is seen along the unit ray direction u that
// points into the surface there, so p = c - r u for the circle's centre c and radius r.
#pragma once

namespace rfm {

class NormalCircleFit {
 public:
  struct Circle {
    double radius = 0.0;  // > 0: the centre lies beyond the points along their rays (convex)
    double rms = 0.0;     // root mean square distance of the points from c - r u
  };

  // A point (x, y) seen along the unit direction (ux, uy), with a weight > 0.
  void add(double x, double y, double ux, double uy, double weight) {
    weight_ += weight;
    x_ += weight * x;
    y_ += weight * y;
    squares_ += weight * (x * x + y * y);
    ux_ += weight * ux;
    uy_ += weight * uy;
    along_ += weight * (x * ux + y * uy);
  }
  double weight() const { return weight_; }
  // 1 - |mean direction|^2: 0 when every direction is the same (no circle to fit), about
  // turn^2 / 12 for directions spread evenly over a small turn (rad).
  double spread() const;
  // The weighted least-squares circle; spread() > 0 and weight() > 0 required.
  Circle fit() const;

 private:
  double weight_ = 0.0, x_ = 0.0, y_ = 0.0, squares_ = 0.0, ux_ = 0.0, uy_ = 0.0, along_ = 0.0;
};

// spread() of directions turning evenly through `turn` (rad).
double spreadOfTurn(double turn);

}  // namespace rfm
