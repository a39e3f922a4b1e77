#pragma once

#include "reflectance_field_map/core/active_classes.h"
#include "reflectance_field_map/core/cell_class.h"
#include "reflectance_field_map/core/grid_geometry.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <cstdint>
#include <unordered_map>
#include <vector>

namespace rfm {

// The directions in which the static cells of the active region reflected at one moment, kept
// while the field is rebuilt: the glass check of a batch re-processing pass reads them
// (ReflectionRemover::freeze), so it depends on no scan of the pass.
class FrozenReflectivity {
 public:
  bool active() const { return active_; }

  // Copies the reflective masks of the window's cells whose class is static, and becomes active.
  void freeze(const ReflectanceField& field, const ActiveClasses& classes);

  // The cell's mask words as frozen; null for cells that were not static then.
  const uint64_t* maskOf(const CellIndex& cell) const {
    const auto found = offsets_.find(key(cell));
    return found == offsets_.end() ? nullptr : &masks_[found->second];
  }

  // Forgets the masks and becomes inactive.
  void clear();

 private:
  static int64_t key(const CellIndex& cell) {
    // x in the high word by a multiply: a left shift of a negative value is undefined.
    return (static_cast<int64_t>(cell.x()) * (int64_t{1} << 32)) | static_cast<uint32_t>(cell.y());
  }

  std::unordered_map<int64_t, size_t> offsets_;  // cell -> its first mask word in masks_
  std::vector<uint64_t> masks_;
  bool active_ = false;
};

}  // namespace rfm
