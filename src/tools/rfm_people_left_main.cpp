// rfm_people_left: how many occupied cells of each map most of the recording's scans saw
// through (people left in the map; see transient_evidence.h).

#include "reflectance_field_map/offline/bag_input.h"
#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/tools/grid_map_file.h"
#include "reflectance_field_map/tools/measure_pictures.h"
#include "reflectance_field_map/tools/transient_evidence.h"

#include <ros/time.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace {

const char* const kUsage =
    "Usage: rosrun reflectance_field_map rfm_people_left --bag IN.bag [--scan-topics /a,/b]\n"
    "           [--fixed-frame FRAME] [--base-frame FRAME] [--margin CELLS] [--picture OUT.png]\n"
    "           MAP_DIR...\n"
    "\n"
    "For each map (DIR/map.yaml, in the fixed frame, as rfm_offline writes it) prints\n"
    "  people_left DIR occupied N transient M\n"
    "where M of its N occupied cells were seen through by more of the bag's scans observing\n"
    "them than hit them: a return from more than CELLS cells beyond a cell (default 2) sees\n"
    "through it, one ending in it hits it. Flags as rfm_offline's (defaults /scan_front,\n"
    "/scan_rear, odom, base_link). --picture: the maps side by side, those cells red.\n";

}  // namespace

int main(int argc, char** argv) {
  using rfm::tools::TransientEvidence;
  rfm::offline::BagInputOptions input;
  input.scan_topics = {"/scan_front", "/scan_rear"};
  std::vector<std::string> dirs;
  int margin = TransientEvidence::kDefaultMarginCells;
  std::string picture;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      std::cout << kUsage;
      return 0;
    }
    if (arg == "--bag" || arg == "--scan-topics" || arg == "--fixed-frame" ||
        arg == "--base-frame" || arg == "--margin" || arg == "--picture") {
      if (i + 1 >= argc) {
        std::cerr << "rfm_people_left: " << arg << " needs a value\n\n" << kUsage;
        return 2;
      }
      const std::string value = argv[++i];
      if (arg == "--bag") input.bag = value;
      if (arg == "--scan-topics") input.scan_topics = rfm::offline::splitTopicList(value);
      if (arg == "--fixed-frame") input.fixed_frame = value;
      if (arg == "--base-frame") input.base_frame = value;
      if (arg == "--margin") {
        char* end = nullptr;
        const long cells = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || cells < 0 || cells > 100) {
          std::cerr << "rfm_people_left: --margin: '" << value << "' is not 0-100 cells\n";
          return 2;
        }
        margin = static_cast<int>(cells);
      }
      if (arg == "--picture") picture = value;
    } else if (arg.size() > 1 && arg[0] == '-') {
      std::cerr << "rfm_people_left: unknown option " << arg << "\n\n" << kUsage;
      return 2;
    } else {
      dirs.push_back(arg);
    }
  }
  if (input.bag.empty() || dirs.empty()) {
    std::cerr << "rfm_people_left: --bag and at least one MAP_DIR are needed\n\n" << kUsage;
    return 2;
  }
  ros::Time::init();

  using namespace rfm::tools;
  try {
    std::vector<GridMap> maps;
    for (const std::string& dir : dirs)
      maps.push_back(readMapDirectory(dir));
    // The evidence over the union of the maps.
    int min_x = INT_MAX, min_y = INT_MAX, max_x = INT_MIN, max_y = INT_MIN;
    for (const GridMap& map : maps) {
      if (std::abs(map.resolution - maps[0].resolution) > 1e-9) {
        throw MapFileError("the maps' resolutions differ");
      }
      int ox = 0, oy = 0;
      mapCellOrigin(map, ox, oy);
      min_x = std::min(min_x, ox);
      min_y = std::min(min_y, oy);
      max_x = std::max(max_x, ox + map.width);
      max_y = std::max(max_y, oy + map.height);
    }
    const rfm::offline::BagScans bag = rfm::offline::readBagScans(input);
    TransientEvidence evidence(maps[0].resolution, min_x, min_y, max_x - min_x, max_y - min_y,
                               margin);
    for (const rfm::TimedScan& scan : bag.scans)
      evidence.addScan(scan);
    std::cerr << "rfm_people_left: " << bag.scans.size() << " scans of " << input.bag << "\n";
    for (std::size_t m = 0; m < maps.size(); ++m) {
      const PeopleLeft left = measurePeopleLeft(maps[m], evidence);
      std::cout << "people_left " << dirs[m] << " occupied " << left.occupied << " transient "
                << left.transient << "\n";
    }
    if (!picture.empty()) rfm::render::writePng(picture, renderPeopleLeft(maps, evidence, 3));
    return 0;
  } catch (const MapFileError& e) {
    std::cerr << "rfm_people_left: " << e.what() << "\n";
  } catch (const rfm::offline::BagInputError& e) {
    std::cerr << "rfm_people_left: " << e.what() << "\n";
  } catch (const rfm::render::PngError& e) {
    std::cerr << "rfm_people_left: " << e.what() << "\n";
  }
  return 1;
}
