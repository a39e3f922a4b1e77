// rfm_compare_maps: an RFM map against the plain grid of the same recording (both written by
// rfm_offline): walls kept, what the RFM made of the walls it dropped, its classes, a picture.

#include "reflectance_field_map/render/png_io.h"
#include "reflectance_field_map/tools/comparison_picture.h"
#include "reflectance_field_map/tools/grid_map_file.h"
#include "reflectance_field_map/tools/map_comparison.h"

#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>
#include <vector>

namespace {

const char* const kUsage =
    "Usage: rosrun reflectance_field_map rfm_compare_maps RFM_DIR PLAIN_DIR [--picture OUT.png]\n"
    "           [--max-width PIXELS] [--max-bytes BYTES]\n"
    "\n"
    "Reads DIR/map.yaml (+ map.pgm) and DIR/classes.pgm of both maps (rfm_offline, then\n"
    "rfm_offline --baseline), aligned by their origins, and prints one 'key value' a line:\n"
    "  walls_kept_percent  share of the plain grid's occupied cells that the RFM has occupied\n"
    "                      within one cell (Chebyshev distance 1)\n"
    "  plain_occupied, kept, dropped, dropped_<class>  (the RFM's class at a dropped cell)\n"
    "  rfm_<class>         the RFM map's cells of each class\n"
    "With --picture: RFM | plain grid as a PNG (at most 1600 pixels wide and 300000 bytes by\n"
    "default; coarser scales are taken until it fits).\n";

long positive(const std::string& flag, const char* text) {
  char* end = nullptr;
  const long value = std::strtol(text, &end, 10);
  if (*text == '\0' || *end != '\0' || value <= 0) {
    throw std::invalid_argument(flag + ": '" + text + "' is not a positive whole number");
  }
  return value;
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<std::string> dirs;
  std::string picture;
  long max_width = 1600, max_bytes = 300000;
  try {
    for (int i = 1; i < argc; ++i) {
      const std::string arg = argv[i];
      if (arg == "-h" || arg == "--help") {
        std::cout << kUsage;
        return 0;
      }
      if (arg == "--picture" || arg == "--max-width" || arg == "--max-bytes") {
        if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
        const char* value = argv[++i];
        if (arg == "--picture") picture = value;
        if (arg == "--max-width") max_width = positive(arg, value);
        if (arg == "--max-bytes") max_bytes = positive(arg, value);
      } else if (arg.size() > 1 && arg[0] == '-') {
        throw std::invalid_argument("unknown option " + arg);
      } else {
        dirs.push_back(arg);
      }
    }
    if (dirs.size() != 2) throw std::invalid_argument("expected RFM_DIR and PLAIN_DIR");
  } catch (const std::invalid_argument& e) {
    std::cerr << "rfm_compare_maps: " << e.what() << "\n\n" << kUsage;
    return 2;
  }

  using namespace rfm::tools;
  try {
    const GridMap rfm = readMapDirectory(dirs[0]);
    const GridMap plain = readMapDirectory(dirs[1]);
    if (!rfm.hasClasses()) {
      std::cerr << "rfm_compare_maps: warning: " << dirs[0]
                << " has no classes.pgm: classes are read from map.pgm (occupied: static)\n";
    }
    const WallsKept walls = measureWallsKept(rfm, plain);
    char percent[32];
    std::snprintf(percent, sizeof(percent), "%.2f", walls.percent());
    std::cout << "walls_kept_percent " << percent << "\n"
              << "plain_occupied " << walls.plain_occupied << "\n"
              << "kept " << walls.kept << "\n"
              << "dropped " << walls.dropped() << "\n";
    for (uint8_t code = 0; code < kClassCodes; ++code)
      std::cout << "dropped_" << classCodeName(code) << " " << walls.dropped_by_class[code] << "\n";
    const auto classes = countClasses(rfm);
    for (uint8_t code = 0; code < kClassCodes; ++code)
      std::cout << "rfm_" << classCodeName(code) << " " << classes[code] << "\n";
    if (!picture.empty()) {
      const int k = writeComparisonPicture(picture, rfm, plain, static_cast<int>(max_width),
                                           static_cast<std::size_t>(max_bytes));
      std::cout << "picture " << picture << "\n"
                << "picture_cells_per_pixel " << k << "\n";
    }
    return 0;
  } catch (const MapFileError& e) {
    std::cerr << "rfm_compare_maps: " << e.what() << "\n";
  } catch (const rfm::render::PngError& e) {
    std::cerr << "rfm_compare_maps: " << e.what() << "\n";
  }
  return 1;
}
