// rfm_live_labels: labels every scan of a bag as the live node publishes them, for rfm_eval.
//
//   rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml]
//
// The node's per-scan path (MapperRos::processScan): addScan, then labelAddedScan against the
// map so far, and removeMotion every 1 / motion_removal_rate s of the scans' clock. Each beam is
// judged when its scan arrives, as AMCL or a costmap would see the filtered scan, not against the
// final map as rfm_offline does.
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/offline/bag_input.h"
#include "reflectance_field_map/offline/outputs.h"
#include "reflectance_field_map/offline/params.h"

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  if (argc < 3 || argc > 4) {
    std::cerr << "usage: rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml]\n";
    return 2;
  }
  try {
    rfm::MapperOptions options;
    if (argc == 4) rfm::offline::loadParamsFile(argv[3], options);
    rfm::offline::BagInputOptions input;
    input.bag = argv[1];
    input.scan_topics = {"/scan_front", "/scan_rear"};
    const rfm::offline::BagScans scans = rfm::offline::readBagScans(input);
    rfm::Mapper mapper(options);
    const double motion_removal_period = 1.0 / options.motion_removal.motion_removal_rate;
    double last_motion_removal = -1e300;
    std::vector<std::vector<rfm::RayLabel>> labels;
    labels.reserve(scans.scans.size());
    for (const rfm::TimedScan& scan : scans.scans) {
      labels.push_back(mapper.labelAddedScan(scan, mapper.addScan(scan)));
      if (scan.stamp - last_motion_removal >= motion_removal_period) {
        mapper.removeMotion();
        last_motion_removal = scan.stamp;
      }
    }
    rfm::offline::writeLabelsBag(argv[2], "/rfm/ray_labels", scans, labels);
  } catch (const std::exception& e) {
    std::cerr << "rfm_live_labels: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
