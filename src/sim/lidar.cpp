#include "reflectance_field_map/sim/lidar.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rfm::sim {
namespace {

void require(bool condition, const std::string& what) {
  if (!condition) throw std::invalid_argument(what);
}

}  // namespace

void LidarSpec::validate() const {
  require(!topic.empty(), "topic must not be empty");
  require(!frame_id.empty(), "frame_id must not be empty");
  require(beam_count >= 1 && beam_count <= 100000, "beam_count must be in [1, 100000]");
  require(angle_increment > 0.0, "angle_increment must be positive");
  require(range_min >= 0.0 && range_max > range_min, "need 0 <= range_min < range_max");
  require(rate_hz > 0.0 && rate_hz <= 1000.0, "rate_hz must be in (0, 1000]");
  require(time_offset >= 0.0, "time_offset must not be negative");
  require(range_noise_sigma >= 0.0 && range_noise_sigma < 1.0,
          "range_noise_sigma must be in [0, 1)");
  require(dropout_probability >= 0.0 && dropout_probability <= 1.0,
          "dropout_probability must be in [0, 1]");
}

LidarSensor::LidarSensor(LidarSpec spec) : spec_(std::move(spec)) {
  spec_.validate();
  beam_cos_.resize(spec_.beam_count);
  beam_sin_.resize(spec_.beam_count);
  for (int i = 0; i < spec_.beam_count; ++i) {
    beam_cos_[i] = std::cos(spec_.beamAngle(i));
    beam_sin_[i] = std::sin(spec_.beamAngle(i));
  }
}

SimScan LidarSensor::scan(const BeamTracer& tracer, const Pose2& robot_pose, double time,
                          const std::vector<Circle>& people, double specular_window_rad,
                          std::mt19937& rng) const {
  const Pose2 laser = robot_pose.compose(spec_.mount());
  const Eigen::Vector2d origin = laser.position();
  const double c = std::cos(laser.yaw), s = std::sin(laser.yaw);
  std::normal_distribution<double> noise(0.0, spec_.range_noise_sigma);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);

  SimScan result;
  result.time = time;
  result.ranges.resize(spec_.beam_count);
  result.classes.resize(spec_.beam_count);
  for (int i = 0; i < spec_.beam_count; ++i) {
    const Eigen::Vector2d direction(c * beam_cos_[i] - s * beam_sin_[i],
                                    s * beam_cos_[i] + c * beam_sin_[i]);
    const BeamResult beam =
        tracer.trace(origin, direction, spec_.range_max, people, specular_window_rad, rng);
    // Noise and dropout are drawn for every beam, echo or not, to keep the random stream simple.
    const double range_noise = spec_.range_noise_sigma > 0.0 ? noise(rng) : 0.0;
    const bool dropped = uniform(rng) < spec_.dropout_probability;
    float range = std::numeric_limits<float>::infinity();
    BeamClass beam_class = BeamClass::kNoReturn;
    if (beam.beam_class != BeamClass::kNoReturn && !dropped) {
      const double measured = beam.range + range_noise;
      if (measured >= spec_.range_max) {
        range = std::numeric_limits<float>::infinity();
      } else if (measured < spec_.range_min) {
        range = -std::numeric_limits<float>::infinity();  // REP-117: object too close
      } else {
        range = static_cast<float>(measured);
        beam_class = beam.beam_class;
      }
    }
    result.ranges[i] = range;
    result.classes[i] = static_cast<std::uint8_t>(beam_class);
  }
  return result;
}

}  // namespace rfm::sim
