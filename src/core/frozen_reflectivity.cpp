#include "reflectance_field_map/core/frozen_reflectivity.h"

namespace rfm {

void FrozenReflectivity::freeze(const ReflectanceField& field, const ActiveClasses& classes) {
  clear();
  const int words = field.maskWords();
  field.window().forEachCell(field.activeBox(), [&](int x, int y, int slot) {
    if (classes.atSlot(slot) != CellClass::kStatic) return;
    offsets_.emplace(key({x, y}), masks_.size());
    const uint64_t* mask = field.reflectiveMaskAt(slot);
    masks_.insert(masks_.end(), mask, mask + words);
  });
  active_ = true;
}

void FrozenReflectivity::clear() {
  offsets_.clear();
  masks_.clear();
  active_ = false;
}

}  // namespace rfm
