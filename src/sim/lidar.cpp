#include "reflectance_field_map/sim/lidar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rfm::sim {
namespace {

void require(bool condition, const std::string& what) {
  if (!condition) throw std::invalid_argument(what);
}

// What the sensor reports for a traced beam (REP-117: +inf no echo, -inf closer than range_min)
// and its truth class (NO_RETURN unless a range is reported).
void encodeBeam(const LidarSpec& spec, const BeamResult& beam, double range_noise, bool dropped,
                float& range, std::uint8_t& truth_class) {
  range = std::numeric_limits<float>::infinity();
  BeamClass beam_class = BeamClass::kNoReturn;
  if (beam.beam_class != BeamClass::kNoReturn && !dropped) {
    const double measured = beam.range + range_noise;
    if (measured >= spec.range_max) {
      range = std::numeric_limits<float>::infinity();
    } else if (measured < spec.range_min) {
      range = -std::numeric_limits<float>::infinity();  // REP-117: object too close
    } else {
      range = static_cast<float>(measured);
      beam_class = beam.beam_class;
    }
  }
  truth_class = static_cast<std::uint8_t>(beam_class);
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
  require(range_noise_per_m >= 0.0 && range_noise_per_m < 0.1,
          "range_noise_per_m must be in [0, 0.1)");
  require(mirror_hz >= 0.0 && mirror_hz <= 1000.0, "mirror_hz must be in [0, 1000]");
  require(!sweep || (beam_count - 1) * angle_increment * rate_hz <=
                        2.0 * M_PI * (mirror_hz > 0.0 ? mirror_hz : rate_hz) + 1e-9,
          "a sweeping scan must end before the next one starts (mirror_hz too low)");
  require(std::abs(mount_pitch) <= 0.2 && std::abs(mount_roll) <= 0.2,
          "mount_pitch and mount_roll must be within 0.2 rad");
}

double LidarSpec::timeIncrement() const {
  if (!sweep) return 0.0;
  return angle_increment / (2.0 * M_PI * (mirror_hz > 0.0 ? mirror_hz : rate_hz));
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
    double range_noise = spec_.range_noise_sigma > 0.0 ? noise(rng) : 0.0;
    if (spec_.range_noise_per_m > 0.0 && range_noise != 0.0 && std::isfinite(beam.range)) {
      range_noise *= 1.0 + spec_.range_noise_per_m * beam.range / spec_.range_noise_sigma;
    }
    const bool dropped = uniform(rng) < spec_.dropout_probability;
    encodeBeam(spec_, beam, range_noise, dropped, result.ranges[i], result.classes[i]);
  }
  return result;
}

SimScan LidarSensor::scanRealistic(const BeamTracer& tracer, const MovingScene& motion, double time,
                                   std::mt19937& rng) const {
  std::normal_distribution<double> standard_normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  // While sweeping, the robot and people are moved every few beams (a fraction of a millimetre
  // of motion between updates), not every beam.
  constexpr int kSweepBlock = 8;
  const double time_increment = spec_.timeIncrement();
  const int block = time_increment > 0.0 ? kSweepBlock : spec_.beam_count;

  SimScan result;
  result.time = time;
  result.ranges.resize(spec_.beam_count);
  result.classes.resize(spec_.beam_count);
  for (int first = 0; first < spec_.beam_count; first += block) {
    const int last = std::min(spec_.beam_count, first + block);
    const double t = time + 0.5 * (first + last - 1) * time_increment;
    const Pose2 laser = motion.robotPose(t).compose(spec_.mount());
    const Tilt tilt = motion.chassisTilt(t);
    const std::vector<Circle> people = motion.people(t);
    const Eigen::Vector2d origin = laser.position();
    const double c = std::cos(laser.yaw), s = std::sin(laser.yaw);
    for (int i = first; i < last; ++i) {
      const Eigen::Vector2d direction(c * beam_cos_[i] - s * beam_sin_[i],
                                      s * beam_cos_[i] + c * beam_sin_[i]);
      // Out-of-plane angle of the beam: the chassis tilt seen along the beam's direction on the
      // robot, plus the sensor's own mount tilt along its direction in the laser frame.
      const double on_robot = spec_.mount_yaw + spec_.beamAngle(i);
      const double elevation = tilt.pitch * std::cos(on_robot) + tilt.roll * std::sin(on_robot) +
                               spec_.mount_pitch * beam_cos_[i] + spec_.mount_roll * beam_sin_[i];
      const BeamResult beam =
          tracer.traceRealistic(origin, direction, spec_.range_max, people, elevation, rng);
      const double sigma = spec_.range_noise_sigma +
                           (std::isfinite(beam.range) ? spec_.range_noise_per_m * beam.range : 0.0);
      const double range_noise = sigma * standard_normal(rng);
      const bool dropped = uniform(rng) < spec_.dropout_probability;
      encodeBeam(spec_, beam, range_noise, dropped, result.ranges[i], result.classes[i]);
    }
  }
  return result;
}

}  // namespace rfm::sim
