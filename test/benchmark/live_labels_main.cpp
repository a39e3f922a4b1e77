// rfm_live_labels: labels every scan of a bag as the live node publishes them, for rfm_eval.
//
//   rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml] [--scan-topics /a,/b] [--fixed-frame F]
//                   [--classes-log FILE] [--map-out DIR]
//
// The node's per-scan path (MapperRos::processScan): addScan, then labelAddedScan against the
// map so far, a part of the last pass's revert behind new glass, and a pass
// (classifyActiveRegion) every 1 / motion_removal_rate s of the scans' clock. Each beam is
// judged when its scan arrives, as AMCL or a costmap would see the filtered scan, not against the
// final map as rfm_offline does.
//
// --classes-log FILE records the classes each pass leaves, for scripts/live_reflection_gap.py:
// per pass, in the host's byte order, the scans' clock (float64, s), the window's box in cells
// (int32 min x, min y, width, height) and its cells' class codes (uint8 each, CellClass,
// row-major, x fastest).
//
// --map-out DIR writes the map the node holds at the end of the replay, after the pass its timer
// runs once scans stop: DIR/map.yaml + map.pgm and DIR/classes.pgm, as rfm_offline writes them
// (rfm_compare_maps reads them).
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/offline/bag_input.h"
#include "reflectance_field_map/offline/outputs.h"
#include "reflectance_field_map/offline/params.h"

#include <cstdint>
#include <exception>
#include <fstream>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

namespace {

constexpr char kUsage[] =
    "usage: rfm_live_labels IN.bag OUT_labels.bag [PARAMS.yaml] [--scan-topics /a,/b]"
    " [--fixed-frame FRAME] [--classes-log FILE] [--map-out DIR]\n"
    "  topics default to /scan_front,/scan_rear (those present), the frame to odom, as "
    "rfm_offline\n";

// Appends the window's classes after a pass (the format is in the comment at the top).
void logClasses(const rfm::Mapper& mapper, double stamp, std::ostream& out) {
  const rfm::CellBox box = mapper.field().activeBox();
  std::vector<rfm::CellClass> classes;
  mapper.map().extract(box, classes);
  const int32_t header[4] = {box.min.x(), box.min.y(), box.max.x() - box.min.x(),
                             box.max.y() - box.min.y()};
  out.write(reinterpret_cast<const char*>(&stamp), sizeof(stamp));
  out.write(reinterpret_cast<const char*>(header), sizeof(header));
  out.write(reinterpret_cast<const char*>(classes.data()),
            static_cast<std::streamsize>(classes.size()));
  if (!out) throw std::runtime_error("cannot write the classes log");
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> positional;
  rfm::offline::BagInputOptions input;
  std::string classes_log_path, map_out;
  input.scan_topics = {"/scan_front", "/scan_rear"};
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if ((arg == "--scan-topics" || arg == "--fixed-frame" || arg == "--classes-log" ||
         arg == "--map-out") &&
        i + 1 < argc) {
      const std::string value = argv[++i];
      if (arg == "--scan-topics") {
        input.scan_topics = rfm::offline::splitTopicList(value);
      } else if (arg == "--fixed-frame") {
        input.fixed_frame = value;
      } else if (arg == "--map-out") {
        map_out = value;
      } else {
        classes_log_path = value;
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
    std::ofstream classes_log;
    if (!classes_log_path.empty()) {
      classes_log.open(classes_log_path, std::ios::binary);
      if (!classes_log) throw std::runtime_error("cannot write " + classes_log_path);
    }
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
        if (classes_log.is_open()) logClasses(mapper, scan.stamp, classes_log);
      }
    }
    rfm::offline::writeLabelsBag(positional[1], "/rfm/ray_labels", scans, labels);
    if (!map_out.empty()) {
      mapper.classifyActiveRegion();
      rfm::offline::makeOutputDirectory(map_out);
      rfm::offline::writeMapServerFiles(map_out, "map", mapper.map(), options.grid.resolution);
      rfm::offline::writeClassesPgm(map_out, mapper.map());
    }
  } catch (const std::exception& e) {
    std::cerr << "rfm_live_labels: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
