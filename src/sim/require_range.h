// Parameter checks shared by the simulator's models: an error that names the parameter.
#pragma once

#include <stdexcept>
#include <string>

namespace rfm::sim::detail {

inline void requireRange(double value, double low, double high, const char* name) {
  if (!(value >= low && value <= high)) {
    throw std::invalid_argument(std::string(name) + " must be in [" + std::to_string(low) + ", " +
                                std::to_string(high) + "], got " + std::to_string(value));
  }
}

}  // namespace rfm::sim::detail
