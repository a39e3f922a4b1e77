#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/mapper.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <set>

namespace rfm {
namespace {

// Every field, set to values outside its range, is rejected with its own name in the message.
TEST(MapperOptions, EveryBadValueIsRejectedNamingTheField) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::vector<double>>> bad = {
      {"resolution", {0.0, -0.05, 2.0, nan}},
      {"theta_bins", {0, 3, 5000}},
      {"tile_cells", {0, 2, 1000, 24}},
      {"log_odds_hit", {0.0, -0.5, 9.0, nan}},
      {"log_odds_miss", {0.0, 0.5, -9.0}},
      {"log_odds_min", {0.0, 1.0, -9.0}},
      {"log_odds_max", {0.0, -1.0, 9.0}},
      {"clearing_distance", {-1.0, 1000.0, nan}},
      {"insertion_threads", {0, -1, 17}},
      {"active_region_radius", {0.0, -3.0, 1000.0, 1.2}},
      {"alpha", {-0.1, 7.0}},
      {"beta", {0.0, 6.0, -1.0}},
      {"metal_min_angle", {-1.0, 7.0}},
      {"motion_removal_rate", {0.0, -2.0, 1000.0}},
      {"persistence_time", {-1.0, 1e7}},
      {"persistence_min_length", {-0.1, 1000.0}},
      {"departure_min_angle", {-0.1, 7.0}},
      {"departure_vacant_time", {-0.1, 2e6}},
      {"solid_max_missed_ratio", {-0.1, 1001.0, nan}},
      {"solid_min_share", {-0.1, 1.1, nan}},
      {"solid_anchor_min_angle", {-0.1, 7.0, nan}},
      {"glass_max_static_neighbours", {-2, 9}},
      {"column_max_radius", {-0.1, 10.5, nan}},
      {"static_blocking_min_angle", {-0.1, 7.0, nan}},
      {"penetration_tolerance", {-0.1, 10.0}},
      {"glass_completion_max_gap", {-0.1, 25.0, nan}},
      {"scan_buffer_size", {-1, 1e7}},
  };
  std::set<std::string> covered;
  for (const auto& [name, values] : bad) {
    for (double value : values) {
      MapperOptions options;
      ASSERT_TRUE(setOption(options, name, value)) << name;
      try {
        options.validate();
        ADD_FAILURE() << name << " = " << value << " was accepted";
      } catch (const InvalidOption& error) {
        EXPECT_EQ(error.field(), name);
        EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
        EXPECT_NE(std::string(error.what()).find("allowed"), std::string::npos) << error.what();
      }
      EXPECT_THROW(Mapper mapper(options), InvalidOption);
    }
    covered.insert(name);
  }
  // Every numeric option with a range is covered above.
  for (const OptionField& field : optionFields()) {
    if (field.type == OptionField::Type::kBool) continue;
    EXPECT_TRUE(covered.count(field.name)) << field.name << " has no rejection test";
  }
}

// The batch's own options are rejected the same way, naming the parameter.
TEST(Options, BadBatchOptionsAreRejectedByName) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::vector<double>>> bad = {
      {"batch_beta", {0.0, 6.0, -1.0, 20000.0, nan}},
      {"max_reflection_iterations", {0, 1000}},
      {"first_pass_scan_stride", {0, 1001}},
      {"search_pass_scan_stride", {0, 1001}},
  };
  std::set<std::string> covered;
  for (const auto& [name, values] : bad) {
    for (double value : values) {
      BatchOptions batch;
      ASSERT_TRUE(setOption(batch, name, value)) << name;
      try {
        batch.validate();
        ADD_FAILURE() << name << " = " << value << " was accepted";
      } catch (const InvalidOption& error) {
        EXPECT_EQ(error.field(), name);
      }
      EXPECT_THROW(processBatch({}, MapperOptions{}, batch, BatchMode::kFull), InvalidOption);
    }
    covered.insert(name);
  }
  for (const OptionField& field : batchOptionFields()) {
    EXPECT_TRUE(covered.count(field.name)) << field.name << " has no rejection test";
  }
  // The two tables are apart: a batch option is no mapper option.
  MapperOptions mapper;
  EXPECT_FALSE(setOption(mapper, "batch_beta", 50.0));
}

// The layout is not a parameter (the batch sets it), and is checked all the same.
void expectLayoutRejected(const std::string& field, const MapperLayout& layout) {
  try {
    Mapper mapper(MapperOptions{}, layout);
    ADD_FAILURE() << field << " was accepted";
  } catch (const InvalidOption& error) {
    EXPECT_EQ(error.field(), field);
  }
}

TEST(MapperLayout, BadWindowRadiusIsRejected) {
  for (double radius :
       {-1.0, MapperLayout::kMaxWindowRadius + 1.0, std::numeric_limits<double>::quiet_NaN()}) {
    MapperLayout layout;
    layout.window_radius = radius;
    expectLayoutRejected("window_radius", layout);
  }
}

// Single cells by default, at most blocks of 16.
TEST(MapperLayout, BadClearanceBlockShiftIsRejected) {
  for (int shift : {-1, 5}) {
    MapperLayout layout;
    layout.clearance_block_shift = shift;
    expectLayoutRejected("clearance_block_shift", layout);
  }
  for (int shift : {0, 4}) {
    MapperLayout layout;
    layout.clearance_block_shift = shift;
    EXPECT_NO_THROW(Mapper(MapperOptions{}, layout));
  }
}

TEST(MapperOptions, DefaultsAreValidAndMatchThePaper) {
  const MapperOptions options;
  EXPECT_NO_THROW(options.validate());
  EXPECT_DOUBLE_EQ(options.grid.resolution, 0.05);
  EXPECT_EQ(options.grid.theta_bins, 180);
  EXPECT_DOUBLE_EQ(options.active_region.active_region_radius, 10.0);
  EXPECT_NEAR(options.occupancy.alpha, kPi / 180.0, 1e-12);
}

TEST(OptionTable, SetAndGetEveryField) {
  MapperOptions options;
  for (const OptionField& field : optionFields()) {
    const double value = field.type == OptionField::Type::kBool ? 0.0 : 3.0;
    ASSERT_TRUE(setOption(options, field.name, value)) << field.name;
    EXPECT_DOUBLE_EQ(getOption(options, field.name), value) << field.name;
    EXPECT_FALSE(field.description.empty());
  }
  EXPECT_FALSE(setOption(options, "no_such_option", 1.0));
  EXPECT_THROW(getOption(options, "no_such_option"), std::invalid_argument);
}

}  // namespace
}  // namespace rfm
