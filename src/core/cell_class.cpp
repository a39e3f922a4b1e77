#include "reflectance_field_map/core/cell_class.h"

namespace rfm {

const char* toString(CellClass c) {
  switch (c) {
    case CellClass::kUnknown:
      return "unknown";
    case CellClass::kFree:
      return "free";
    case CellClass::kStatic:
      return "static";
    case CellClass::kGlass:
      return "glass";
    case CellClass::kMetal:
      return "metal";
    case CellClass::kMotion:
      return "motion";
    case CellClass::kOccupied:
      return "occupied";
  }
  return "invalid";
}

}  // namespace rfm
