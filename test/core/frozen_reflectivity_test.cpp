#include "reflectance_field_map/core/frozen_reflectivity.h"

#include "test_fields.h"

#include <gtest/gtest.h>

#include <vector>

namespace rfm {
namespace {

TEST(FrozenReflectivity, KeepsTheMasksOfStaticCellsAsTheyWere) {
  ReflectanceField field = testing::centredField(2.0);
  const CellIndex wall(3, 4), glass(-5, 2);
  for (int i = 0; i < 3; ++i) {
    field.applyHit(wall, 10);
    field.applyHit(wall, 130);  // a bin in the mask's third word
    field.applyHit(glass, 10);
  }
  GlobalMap2D map;
  ActiveClasses classes(field.window(), map, /*clearance_block_shift=*/2);
  ClassifiedRegion region;
  region.box = field.activeBox();
  region.classes.assign(static_cast<size_t>(region.box.width()) * region.box.height(),
                        CellClass::kFree);
  auto set = [&](const CellIndex& cell, CellClass c) {
    region.classes[region.box.indexOf(cell)] = c;
  };
  set(wall, CellClass::kStatic);
  set(glass, CellClass::kGlass);
  classes.replace(region, nullptr);

  FrozenReflectivity frozen;
  EXPECT_FALSE(frozen.active());
  frozen.freeze(field, classes);
  EXPECT_TRUE(frozen.active());
  // The field moves on (cleared, as a re-processing pass starts): the frozen masks do not.
  field.clear();
  field.recenter({0.0, 0.0});
  const uint64_t* mask = frozen.maskOf(wall);
  ASSERT_NE(mask, nullptr);
  int reflective = 0;
  for (int bin = 0; bin < field.geometry().thetaBins(); ++bin)
    reflective += maskBit(mask, bin);
  EXPECT_EQ(reflective, 2);
  EXPECT_TRUE(maskBit(mask, 10));
  EXPECT_TRUE(maskBit(mask, 130));
  // Only static cells are kept (the glass check asks for no others).
  EXPECT_EQ(frozen.maskOf(glass), nullptr);
  EXPECT_EQ(frozen.maskOf({0, 0}), nullptr);

  frozen.clear();
  EXPECT_FALSE(frozen.active());
  EXPECT_EQ(frozen.maskOf(wall), nullptr);
}

}  // namespace
}  // namespace rfm
