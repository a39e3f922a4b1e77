#include "reflectance_field_map/ros/map_files.h"

#include "reflectance_field_map/core/state_file.h"
#include "reflectance_field_map/ros/conversions.h"

#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>
#include <utility>

namespace rfm::ros_glue {
namespace {

bool fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

std::string reason() {
  return errno != 0 ? std::strerror(errno) : "write error";
}

std::string baseName(const std::string& path) {
  const size_t slash = path.rfind('/');
  return slash == std::string::npos ? path : path.substr(slash + 1);
}

// A file written beside its final name and renamed over it once complete, so that an earlier file
// of that name survives a failed write or a crash mid-way whole.
class ReplacingFile {
 public:
  explicit ReplacingFile(std::string path)
      : path_(std::move(path)),
        part_(path_ + ".part" + std::to_string(static_cast<long>(::getpid()))),
        out_(part_, std::ios::binary | std::ios::trunc) {}
  ~ReplacingFile() {
    if (!committed_) std::remove(part_.c_str());
  }
  std::ofstream& stream() { return out_; }
  bool open() const { return static_cast<bool>(out_); }
  // Flushes, closes and renames the file into place. False with `error` set on failure.
  bool commit(std::string* error) {
    out_.flush();
    out_.close();
    if (!out_) return fail(error, "cannot write " + path_ + ": " + reason());
    if (std::rename(part_.c_str(), path_.c_str()) != 0) {
      return fail(error, "cannot write " + path_ + ": " + reason());
    }
    committed_ = true;
    return true;
  }

 private:
  std::string path_, part_;
  std::ofstream out_;
  bool committed_ = false;
};

bool endsWith(const std::string& text, const std::string& suffix) {
  return text.size() >= suffix.size() &&
         text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

}  // namespace

bool writeMapServerFiles(const std::string& prefix, const nav_msgs::OccupancyGrid& grid,
                         std::string* error) {
  const uint32_t width = grid.info.width, height = grid.info.height;
  if (prefix.empty()) return fail(error, "empty path");
  if (width == 0 || height == 0) return fail(error, "the map is empty: nothing to save");
  if (grid.data.size() != static_cast<size_t>(width) * height) {
    return fail(error, "grid data size does not match width * height");
  }
  const std::string pgm_path = prefix + ".pgm";
  const std::string yaml_path = prefix + ".yaml";
  {
    errno = 0;
    ReplacingFile file(pgm_path);
    if (!file.open()) return fail(error, "cannot write " + pgm_path + ": " + reason());
    std::ofstream& pgm = file.stream();
    pgm << "P5\n# CREATOR: reflectance_field_map " << grid.info.resolution << " m/pix\n"
        << width << ' ' << height << "\n255\n";
    std::string row(width, '\0');
    for (uint32_t y = 0; y < height; ++y) {
      const size_t base = static_cast<size_t>(height - 1 - y) * width;  // top row = highest y
      for (uint32_t x = 0; x < width; ++x) {
        const int8_t value = grid.data[base + x];
        unsigned char pixel = 205;  // unknown
        if (value == 0) {
          pixel = 254;
        } else if (value >= 65) {  // occupied_thresh 0.65
          pixel = 0;
        } else if (value > 0) {
          pixel = static_cast<unsigned char>(255 - (255 * value) / 100);
        }
        row[x] = static_cast<char>(pixel);
      }
      pgm.write(row.data(), static_cast<std::streamsize>(row.size()));
    }
    if (!file.commit(error)) return false;
  }
  {
    errno = 0;
    ReplacingFile file(yaml_path);
    if (!file.open()) return fail(error, "cannot write " + yaml_path + ": " + reason());
    std::ofstream& yaml = file.stream();
    const double yaw = yawFromQuaternion(grid.info.origin.orientation);
    // resolution is a float32 in the message: 6 significant digits print 0.05 as 0.05.
    yaml << "image: " << baseName(pgm_path) << "\n"
         << "resolution: " << std::setprecision(std::numeric_limits<float>::digits10)
         << grid.info.resolution << "\n"
         << std::setprecision(10) << "origin: [" << grid.info.origin.position.x << ", "
         << grid.info.origin.position.y << ", " << yaw << "]\n"
         << "negate: 0\n"
         << "occupied_thresh: 0.65\n"
         << "free_thresh: 0.196\n";
    if (!file.commit(error)) return false;
  }
  return true;
}

std::string stateFilePath(const std::string& prefix) {
  return endsWith(prefix, ".rfm") ? prefix : prefix + ".rfm";
}

bool writeMapperState(const std::string& prefix, const rfm::Mapper& mapper, std::string* error) {
  const std::string path = stateFilePath(prefix);
  std::ostringstream payload;
  mapper.save(payload);
  errno = 0;
  ReplacingFile file(path);
  if (!file.open()) return fail(error, "cannot write " + path + ": " + reason());
  rfm::writeStateFile(file.stream(), payload.str());
  return file.commit(error);
}

bool saveMapFiles(const std::string& prefix, const rfm::Mapper& mapper, const std::string& frame,
                  std::string* error) {
  const rfm::GlobalMap2D& map = mapper.map();
  const nav_msgs::OccupancyGrid grid =
      toOccupancyGrid(map, map.bounds(), mapper.options().grid.resolution, frame, ros::Time(0, 0));
  return writeMapServerFiles(prefix, grid, error) && writeMapperState(prefix, mapper, error);
}

bool loadMapperState(const std::string& path, rfm::Mapper& mapper, std::string* error) {
  const std::string file = stateFilePath(path);
  errno = 0;
  std::ifstream in(file, std::ios::binary);
  if (!in) return fail(error, "cannot read " + file + ": " + reason());
  std::string payload, why;
  if (!rfm::readStateFile(in, kMaxStateFileBytes, payload, &why)) {
    return fail(error, file + " refused: " + why);
  }
  std::istringstream state(std::move(payload));
  if (!mapper.load(state)) {
    return fail(error, file + " is intact but not a state of this mapper (different options?)");
  }
  return true;
}

}  // namespace rfm::ros_glue
