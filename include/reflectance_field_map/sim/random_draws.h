// Random draws of the procedural scene generator. ROS-free.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace rfm::sim {

// One named stream of draws: the floor plan, the physics, the robot and the people each draw
// from their own, so changing how one is drawn leaves the others of a seed as they were.
class Dice {
 public:
  Dice(std::uint32_t seed, std::uint32_t stream) {
    std::seed_seq sequence{seed, stream, 0x5CE4EU};
    engine_.seed(sequence);
  }
  double uniform(double low, double high) {
    return std::uniform_real_distribution<double>(low, high)(engine_);
  }
  int integer(int low, int high) {  // inclusive
    return std::uniform_int_distribution<int>(low, high)(engine_);
  }
  bool chance(double probability) { return uniform(0.0, 1.0) < probability; }
  double normal(double mean, double sigma) {
    return std::normal_distribution<double>(mean, sigma)(engine_);
  }
  template <class T>
  const T& pick(const std::vector<T>& items) {
    return items.at(static_cast<std::size_t>(integer(0, static_cast<int>(items.size()) - 1)));
  }

 private:
  std::mt19937 engine_;
};

// Rounds to a multiple of 1 / `divisions` (1000: millimetres), so that the scene file holds
// short numbers that read back exactly.
inline double rounded(double value, double divisions) {
  return std::round(value * divisions) / divisions;
}

}  // namespace rfm::sim
