// The first leaps of the reflection check, shared by neighbouring beams (ReflectionRemover).
#pragma once

#include "reflectance_field_map/core/clearance_map.h"
#include "reflectance_field_map/core/detail/pass_through_detector.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/laser_scan.h"

#include <Eigen/Core>

#include <algorithm>
#include <limits>
#include <optional>

namespace rfm::detail {

// The first leaps of neighbouring beams of a scan, taken together: they diverge slowly, so while
// they are close, one clearance lookup on the middle ray clears the stretch ahead of all of them.
// At distance d along each ray, a ray's point lies within d * spread of the middle ray's
// (Chebyshev); a leap of l moves it at most l * fastest further; and a clearance of c about the
// middle ray's point frees (c - 1) cells around it (ClearanceMap).
class SharedLeap {
 public:
  // For the rays [begin, end) that have cells to check; false (and reached() 0) unless there
  // are two or more, all from one origin.
  bool start(const Ray* rays, const std::optional<PassThroughDetector>* detectors, int begin,
             int end) {
    along_ = 0.0;
    stop_ = std::numeric_limits<double>::infinity();
    int members = 0;
    const int middle = (begin + end) / 2;
    origin_ = rays[middle].origin;
    middle_ = detectors[middle]->direction();
    spread_ = 0.0;
    fastest_ = 0.0;
    for (int i = begin; i < end; ++i) {
      const PassThroughDetector& detector = *detectors[i];
      if (detector.lastCandidate() <= 0.0) continue;  // nothing to check on it
      if (rays[i].origin != origin_) return fail();
      spread_ = std::max(spread_, (detector.direction() - middle_).cwiseAbs().maxCoeff());
      fastest_ = std::max(fastest_, detector.direction().cwiseAbs().maxCoeff());
      stop_ = std::min(stop_, detector.lastCandidate());
      ++members;
    }
    return members >= 2 || fail();
  }
  // One leap; false once the group can leap no further.
  bool leap(const ClearanceMap& clearance, const GridGeometry& geometry) {
    const int clear = clearance.at(geometry.cellOf(origin_ + middle_ * along_));
    if (clear < 2) return false;  // next to structure: the rays go on alone
    const double resolution = geometry.resolution();
    const double length = ((clear - 1) * resolution - along_ * spread_) / fastest_;
    if (length < resolution) return false;  // too wide apart to gain on leaping alone
    along_ += length;
    return along_ < stop_;
  }
  // Distance (m, the same along each ray) up to which no ray of the group passes a blocking
  // cell; at most the first of their last candidates.
  double reached() const { return std::min(along_, stop_); }

 private:
  bool fail() {
    along_ = 0.0;
    stop_ = 0.0;
    return false;
  }
  Eigen::Vector2d origin_, middle_;
  double spread_ = 0.0, fastest_ = 0.0, stop_ = 0.0, along_ = 0.0;
};

}  // namespace rfm::detail
