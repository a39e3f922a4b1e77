// rfm_live_labels: labels every scan of a bag as the live node publishes them, for rfm_eval.
//
//   rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml] [--scan-topics /a,/b] [--fixed-frame F]
//
// The node's per-scan path (MapperRos::processScan): addScan, then labelAddedScan against the
// map so far, a part of the last pass's revert behind new glass, and a pass
// (classifyActiveRegion) every 1 / motion_removal_rate s of the scans' clock. Each beam is
// judged when its scan arrives, as AMCL or a costmap would see the filtered scan, not against the
// final map as rfm_offline does.
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/offline/bag_input.h"
#include "reflectance_field_map/offline/outputs.h"
#include "reflectance_field_map/offline/params.h"

#include <exception>
#include <iostream>
#include <string>
#include <vector>

namespace {

constexpr char kUsage[] =
    "usage: rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml] [--scan-topics /a,/b]"
    " [--fixed-frame FRAME]\n"
    "  topics default to /scan_front,/scan_rear (those present), the frame to odom, as "
    "rfm_offline\n";

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  rfm::offline::BagInputOptions input;
  input.scan_topics = {"/scan_front", "/scan_rear"};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--scan-topics" || arg == "--fixed-frame") && i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--scan-topics") {
        input.scan_topics = rfm::offline::splitTopicList(value);
      } else {
        input.fixed_frame = value;
      }
    } else if (arg.rfind("--", 0) == 0) {
      std::cerr << "rfm_live_labels: unknown or incomplete option " << arg << "\n" << kUsage;
      return 2;
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() < 2 || positional.size() > 3 || input.scan_topics.empty()) {
    std::cerr << kUsage;
    return 2;
  }
  try {
    rfm::MapperOptions options;
    if (positional.size() == 3) rfm::offline::loadParamsFile(positional[2], options);
    input.bag = positional[0];
    const rfm::offline::BagScans scans = rfm::offline::readBagScans(input);
    rfm::Mapper mapper(options);
    const double motion_removal_period = 1.0 / options.motion_removal.motion_removal_rate;
    double last_motion_removal = -1e300;
    std::vector<std::vector<rfm::RayLabel>> labels;
    labels.reserve(scans.scans.size());
    for (const rfm::TimedScan& scan : scans.scans) {
      labels.push_back(mapper.labelAddedScan(scan, mapper.addScan(scan)));
      mapper.revertPartBehindNewGlass();
      if (scan.stamp - last_motion_removal >= motion_removal_period) {
        mapper.classifyActiveRegion();  // its revert goes in parts, as in the node
        last_motion_removal = scan.stamp;
      }
    }
    rfm::offline::writeLabelsBag(positional[1], "/rfm/ray_labels", scans, labels);
  } catch (const std::exception& e) {
    std::cerr << "rfm_live_labels: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
