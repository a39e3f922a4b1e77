// Writes the binary seeds of test/fuzz/corpus: scans for laser_scan (the layout its target
// reads) and saved states for mapper_load (Mapper::save with the target's options). Usage:
// rfm_fuzz_make_seeds CORPUS_DIR (the directory holding laser_scan/ and mapper_load/); built by
// `make rfm_fuzz_make_seeds` in a workspace's build directory.
#include "small_mapper.h"

#include "reflectance_field_map/core/mapper.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

namespace {

template <typename T>
void put(std::ofstream& out, T value) {
  out.write(reinterpret_cast<const char*>(&value), sizeof(value));
}

// flags, pose (x, y, yaw as int8), stamp, angles, limits, then the ranges.
void writeScanSeed(const std::string& path, uint8_t flags, float angle_min, float increment,
                   const std::vector<float>& ranges) {
  std::ofstream out(path, std::ios::binary);
  put<uint8_t>(out, flags);
  put<int8_t>(out, 5);
  put<int8_t>(out, -3);
  put<int8_t>(out, 16);
  put<uint16_t>(out, 100);
  put<float>(out, angle_min);
  put<float>(out, angle_min + increment * static_cast<float>(ranges.size() - 1));
  put<float>(out, increment);
  put<float>(out, 0.05f);
  put<float>(out, 30.0f);
  for (float range : ranges)
    put<float>(out, range);
}

// A robot driving along a corridor (walls at y = +-1.5 m) for `scans` scans, saved.
void writeStateSeed(const std::string& path, int scans, double step) {
  rfm::Mapper mapper(rfm::fuzz::smallMapperOptions());
  for (int i = 0; i < scans; ++i) {
    rfm::TimedScan timed;
    timed.stamp = 0.1 * i;
    timed.sensor_pose.position = {step * i, 0.0};
    timed.robot_pose = timed.sensor_pose;
    timed.scan.angle_min = static_cast<float>(-M_PI / 2);
    timed.scan.angle_increment = static_cast<float>(M_PI / 63);
    timed.scan.angle_max = static_cast<float>(M_PI / 2);
    timed.scan.range_min = 0.05f;
    timed.scan.range_max = 20.0f;
    for (int beam = 0; beam < 64; ++beam) {
      const double angle = -M_PI / 2 + beam * M_PI / 63;
      timed.scan.ranges.push_back(
          static_cast<float>(1.5 / std::max(std::abs(std::sin(angle)), 0.05)));
    }
    mapper.addScan(timed);
  }
  mapper.removeMotion();
  std::ofstream out(path, std::ios::binary);
  mapper.save(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::cerr << "usage: make_seeds CORPUS_DIR\n";
    return 2;
  }
  const std::string corpus = argv[1];
  const std::vector<float> wall(32, 2.5f);
  std::vector<float> mixed = {1.0f, INFINITY, NAN, -INFINITY, 0.01f, 29.0f, 31.0f, 2.0f};
  writeScanSeed(corpus + "/laser_scan/wall.bin", 0, -1.0f, 2.0f / 31.0f, wall);
  writeScanSeed(corpus + "/laser_scan/upside_down_rep117.bin", 1 | 4, -0.5f, 0.125f, mixed);
  writeScanSeed(corpus + "/laser_scan/full_turn.bin", 2, -3.1f, 6.2f / 31.0f, wall);
  writeStateSeed(corpus + "/mapper_load/standing.rfm", 3, 0.0);
  writeStateSeed(corpus + "/mapper_load/corridor_drive.rfm", 16, 0.5);
  std::cout << "seeds written under " << corpus << "\n";
  return 0;
}
