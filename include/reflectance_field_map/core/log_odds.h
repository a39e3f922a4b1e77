#pragma once

#include "reflectance_field_map/core/options.h"

#include <array>
#include <cmath>
#include <cstdint>

namespace rfm {

// Log-odds quantised to int8 so the (x, y, theta) field stays one byte per bin.
// Value 0 is the prior p = 0.5 (also "never observed").
class LogOddsModel {
 public:
  static constexpr double kQuantum = 1.0 / 16.0;  // log-odds per integer step

  explicit LogOddsModel(const LogOddsOptions& options)
      : hit_step_(quantise(options.log_odds_hit)),
        miss_step_(quantise(options.log_odds_miss)),
        min_value_(quantise(options.log_odds_min)),
        max_value_(quantise(options.log_odds_max)) {
    for (int v = -128; v < 128; ++v)
      odds_[v + 128] = static_cast<float>(std::exp(v * kQuantum));
  }

  int8_t hit(int8_t value) const {
    const int updated = value + hit_step_;
    return static_cast<int8_t>(updated > max_value_ ? max_value_ : updated);
  }
  int8_t miss(int8_t value) const {
    const int updated = value + miss_step_;
    return static_cast<int8_t>(updated < min_value_ ? min_value_ : updated);
  }

  static bool isReflective(int8_t value) { return value > 0; }  // p > 0.5
  static bool isMissed(int8_t value) { return value < 0; }
  static double toLogOdds(int8_t value) { return value * kQuantum; }
  static double toProbability(int8_t value) {
    return 1.0 - 1.0 / (1.0 + std::exp(value * kQuantum));
  }
  float odds(int8_t value) const { return odds_[value + 128]; }

  int hitStep() const { return hit_step_; }
  int missStep() const { return miss_step_; }
  int minValue() const { return min_value_; }
  int maxValue() const { return max_value_; }

  static int quantise(double log_odds) {
    return static_cast<int>(std::lround(log_odds / kQuantum));
  }

 private:
  int hit_step_;
  int miss_step_;
  int min_value_;
  int max_value_;
  std::array<float, 256> odds_{};
};

}  // namespace rfm
