#include "reflectance_field_map/tools/grid_map_file.h"

#include <yaml-cpp/yaml.h>

#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

namespace rfm::tools {
namespace {

// Skips whitespace and '#' comments between PGM header fields.
void skipSpaceAndComments(std::istream& in) {
  while (in) {
    const int c = in.peek();
    if (c == '#') {
      in.ignore(std::numeric_limits<std::streamsize>::max(), '\n');
    } else if (c != EOF && std::isspace(c)) {
      in.get();
    } else {
      return;
    }
  }
}

int headerNumber(std::istream& in, const std::string& path, const char* what) {
  skipSpaceAndComments(in);
  long value = -1;
  if (!(in >> value) || value < 0 || value > std::numeric_limits<int>::max()) {
    throw MapFileError(path + ": the PGM header's " + what + " is not a number");
  }
  return static_cast<int>(value);
}

template <typename T>
T yamlValue(const YAML::Node& root, const char* key, const std::string& path) {
  const YAML::Node node = root[key];
  if (!node) throw MapFileError(path + ": no '" + std::string(key) + "'");
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw MapFileError(path + ": '" + std::string(key) + "' is not a valid value");
  }
}

}  // namespace

PgmImage readPgm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MapFileError("cannot read " + path);
  char magic[2] = {0, 0};
  in.read(magic, 2);
  if (!in || magic[0] != 'P' || magic[1] != '5') {
    throw MapFileError(path + ": not a binary PGM (P5)");
  }
  PgmImage image;
  image.width = headerNumber(in, path, "width");
  image.height = headerNumber(in, path, "height");
  image.max_value = headerNumber(in, path, "maxval");
  if (image.width == 0 || image.height == 0) throw MapFileError(path + ": the image is empty");
  if (image.max_value == 0 || image.max_value > 255) {
    throw MapFileError(path + ": maxval " + std::to_string(image.max_value) +
                       " (only 8-bit PGMs, maxval 1-255, are read)");
  }
  const std::size_t cells =
      static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height);
  if (cells > kMaxMapCells) {
    throw MapFileError(path + ": " + std::to_string(image.width) + " x " +
                       std::to_string(image.height) + " pixels is more than a map may have");
  }
  if (!std::isspace(in.get())) throw MapFileError(path + ": no whitespace after the PGM header");
  image.pixels.resize(cells);
  in.read(reinterpret_cast<char*>(image.pixels.data()), static_cast<std::streamsize>(cells));
  if (static_cast<std::size_t>(in.gcount()) != cells) {
    throw MapFileError(path + ": " + std::to_string(in.gcount()) +
                       " pixel bytes, the header says " + std::to_string(cells));
  }
  return image;
}

GridMap readMapServerMap(const std::string& yaml_path) {
  YAML::Node root;
  try {
    root = YAML::LoadFile(yaml_path);
  } catch (const YAML::Exception& e) {
    throw MapFileError("cannot read " + yaml_path + ": " + e.what());
  }
  GridMap map;
  map.resolution = yamlValue<double>(root, "resolution", yaml_path);
  if (!(map.resolution > 0.0) || !std::isfinite(map.resolution)) {
    throw MapFileError(yaml_path + ": resolution must be positive");
  }
  const std::vector<double> origin = yamlValue<std::vector<double>>(root, "origin", yaml_path);
  if (origin.size() != 3 || !std::isfinite(origin[0]) || !std::isfinite(origin[1])) {
    throw MapFileError(yaml_path + ": origin must be [x, y, yaw]");
  }
  if (origin[2] != 0.0) throw MapFileError(yaml_path + ": a rotated origin (yaw != 0) is not read");
  map.origin_x = origin[0];
  map.origin_y = origin[1];
  const bool negate = root["negate"] ? yamlValue<int>(root, "negate", yaml_path) != 0 : false;
  const double occupied = yamlValue<double>(root, "occupied_thresh", yaml_path);
  const double free = yamlValue<double>(root, "free_thresh", yaml_path);
  if (root["mode"] && yamlValue<std::string>(root, "mode", yaml_path) != "trinary") {
    throw MapFileError(yaml_path + ": only mode trinary is read");
  }
  std::filesystem::path image_path = yamlValue<std::string>(root, "image", yaml_path);
  if (image_path.is_relative()) {
    image_path = std::filesystem::path(yaml_path).parent_path() / image_path;
  }
  const PgmImage image = readPgm(image_path.string());
  map.width = image.width;
  map.height = image.height;
  map.occupancy.resize(image.pixels.size());
  for (int row = 0; row < image.height; ++row) {
    const int y = image.height - 1 - row;  // the image's top row is the highest y
    for (int x = 0; x < image.width; ++x) {
      const double v = image.pixels[static_cast<std::size_t>(row) * image.width + x];
      const double p = negate ? v / 255.0 : (255.0 - v) / 255.0;
      map.occupancy[map.index(x, y)] =
          p > occupied ? Occupancy::kOccupied : (p < free ? Occupancy::kFree : Occupancy::kUnknown);
    }
  }
  return map;
}

GridMap readMapDirectory(const std::string& dir) {
  const std::filesystem::path root(dir);
  GridMap map = readMapServerMap((root / "map.yaml").string());
  const std::filesystem::path classes_path = root / "classes.pgm";
  if (!std::filesystem::exists(classes_path)) return map;
  const PgmImage classes = readPgm(classes_path.string());
  if (classes.width != map.width || classes.height != map.height) {
    throw MapFileError(classes_path.string() + " is " + std::to_string(classes.width) + " x " +
                       std::to_string(classes.height) + ", map.pgm " + std::to_string(map.width) +
                       " x " + std::to_string(map.height));
  }
  map.classes.resize(classes.pixels.size());
  for (int row = 0; row < classes.height; ++row) {
    const int y = classes.height - 1 - row;
    for (int x = 0; x < classes.width; ++x) {
      const uint8_t code = classes.pixels[static_cast<std::size_t>(row) * classes.width + x];
      if (code > 5) {
        throw MapFileError(classes_path.string() + ": class code " + std::to_string(code) +
                           " at column " + std::to_string(x) + ", row " + std::to_string(row) +
                           " (codes are 0-5)");
      }
      map.classes[map.index(x, y)] = code;
    }
  }
  return map;
}

}  // namespace rfm::tools
