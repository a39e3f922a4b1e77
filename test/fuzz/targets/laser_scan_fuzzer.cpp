// A sensor_msgs/LaserScan as the node takes it: toLaserScan2D, validate() and, for a scan that
// passes, the mapper's addScan and labelling, the filtered scan and the labels message. Angles,
// limits and ranges are the fuzzer's (any float); the sensor pose stays within 13 m of the
// origin (an implausible pose is the TF input's concern, not the scan's).
#include "fuzz_input.h"
#include "small_mapper.h"

#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/ros/conversions.h"

#include <sensor_msgs/LaserScan.h>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace {

rfm::Mapper& smallMapper() {
  static rfm::Mapper mapper(rfm::fuzz::smallMapperOptions());
  return mapper;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  rfm::fuzz::FuzzInput input(data, size);
  const uint8_t flags = input.take<uint8_t>();
  const bool upside_down = flags & 1;
  const bool reset = flags & 2;
  rfm::TimedScan timed;
  timed.sensor_pose.position = {input.take<int8_t>() * 0.1, input.take<int8_t>() * 0.1};
  timed.sensor_pose.yaw = input.take<int8_t>() * (M_PI / 128.0);
  timed.robot_pose = timed.sensor_pose;
  timed.stamp = input.take<uint16_t>() * 0.01;

  sensor_msgs::LaserScan msg;
  msg.header.frame_id = "laser";
  msg.angle_min = input.take<float>();
  msg.angle_max = input.take<float>();
  msg.angle_increment = input.take<float>();
  msg.range_min = input.take<float>();
  msg.range_max = input.take<float>();
  msg.ranges = input.takeRest<float>();
  msg.intensities.assign(msg.ranges.size() / 2, 1.0f);  // drivers may send fewer

  timed.scan = rfm::ros_glue::toLaserScan2D(msg, upside_down);
  if (!timed.scan.validate().empty()) return 0;
  rfm::Mapper& mapper = smallMapper();
  if (reset) mapper.reset();
  const rfm::ScanUpdate update = mapper.addScan(timed);
  if (!update.error.empty()) return 0;
  std::vector<rfm::RayLabel> labels = mapper.labelAddedScan(timed, update);
  labels = rfm::ros_glue::toMessageOrder(std::move(labels),
                                         rfm::ros_glue::reversesBeamOrder(msg, upside_down));
  if (labels.size() != msg.ranges.size()) __builtin_trap();  // one label per beam
  rfm::ros_glue::filterScan(msg, labels);
  rfm::ros_glue::toRayLabelsMsg(msg.header, "/scan", labels);
  if (flags & 4) mapper.removeMotion();
  return 0;
}
