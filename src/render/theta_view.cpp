#include "reflectance_field_map/render/theta_view.h"

#include "reflectance_field_map/core/ray_traversal.h"
#include "reflectance_field_map/render/map_image.h"

#include <algorithm>
#include <stdexcept>

namespace rfm {
namespace render {
namespace {

// Which class a column shows when several cells are gathered: the most telling first.
int classPriority(CellClass c) {
  switch (c) {
    case CellClass::kGlass:
      return 6;
    case CellClass::kMetal:
      return 5;
    case CellClass::kStatic:
      return 4;
    case CellClass::kOccupied:
      return 3;
    case CellClass::kMotion:
      return 2;
    case CellClass::kFree:
      return 1;
    case CellClass::kUnknown:
      return 0;
  }
  return 0;
}

}  // namespace

int ThetaSlice::reflectiveCount(int column) const {
  int count = 0;
  for (int bin = 0; bin < bins; ++bin)
    count += at(column, bin) == Bin::kReflective;
  return count;
}

int ThetaSlice::outsideColumns() const {
  int count = 0;
  for (int column = 0; column < columns; ++column) {
    count += bins > 0 && at(column, 0) == Bin::kOutside;
  }
  return count;
}

std::vector<std::vector<CellIndex>> segmentColumns(const GridGeometry& geometry,
                                                   const Eigen::Vector2d& p0,
                                                   const Eigen::Vector2d& p1) {
  std::vector<std::vector<CellIndex>> columns;
  forEachCellOnRay(p0, p1, geometry.inverseResolution(),
                   [&columns](const CellIndex& cell) { columns.push_back({cell}); });
  return columns;
}

std::vector<std::vector<CellIndex>> rectangleColumns(const GridGeometry& geometry,
                                                     const Eigen::Vector2d& corner0,
                                                     const Eigen::Vector2d& corner1) {
  const CellIndex a = geometry.cellOf(corner0.cwiseMin(corner1));
  const CellIndex b = geometry.cellOf(corner0.cwiseMax(corner1));
  const bool along_x = (b.x() - a.x()) >= (b.y() - a.y());
  const int along = along_x ? 0 : 1, across = 1 - along;
  std::vector<std::vector<CellIndex>> columns;
  for (int i = a[along]; i <= b[along]; ++i) {
    std::vector<CellIndex> column;
    for (int j = a[across]; j <= b[across]; ++j) {
      CellIndex cell;
      cell[along] = i;
      cell[across] = j;
      column.push_back(cell);
    }
    columns.push_back(std::move(column));
  }
  return columns;
}

ThetaSlice sampleThetaSlice(const ReflectanceField& field,
                            const std::vector<std::vector<CellIndex>>& columns,
                            const GlobalMap2D* map) {
  ThetaSlice slice;
  slice.columns = static_cast<int>(columns.size());
  slice.bins = field.geometry().thetaBins();
  slice.states.assign(columns.size() * static_cast<size_t>(slice.bins), ThetaSlice::Bin::kOutside);
  slice.column_class.assign(columns.size(), CellClass::kUnknown);
  slice.column_cell.assign(columns.size(), CellIndex(0, 0));
  for (size_t c = 0; c < columns.size(); ++c) {
    if (columns[c].empty()) continue;
    slice.column_cell[c] = columns[c].front();
    ThetaSlice::Bin* states = &slice.states[c * static_cast<size_t>(slice.bins)];
    CellClass shown = map ? CellClass::kUnknown : CellClass::kOccupied;
    for (const CellIndex& cell : columns[c]) {
      if (map && classPriority(map->get(cell)) > classPriority(shown)) shown = map->get(cell);
      if (!field.inActiveRegion(cell)) continue;
      for (int bin = 0; bin < slice.bins; ++bin) {
        const int8_t value = field.value(cell, bin);
        ThetaSlice::Bin state = ThetaSlice::Bin::kUnobserved;
        if (value > 0) {
          state = ThetaSlice::Bin::kReflective;
        } else if (value < 0) {
          state = ThetaSlice::Bin::kMissed;
        }
        states[bin] = std::max(states[bin], state);
      }
    }
    slice.column_class[c] = shown;
  }
  return slice;
}

RgbImage renderThetaSlice(const ThetaSlice& slice, int column_px, int bin_px) {
  if (column_px < 1 || bin_px < 1) throw std::invalid_argument("renderThetaSlice: scale < 1");
  if (slice.columns <= 0 || slice.bins <= 0) return {};
  RgbImage image(slice.columns, slice.bins);
  for (int column = 0; column < slice.columns; ++column) {
    const CellClass cls = slice.column_class[static_cast<size_t>(column)];
    const Rgb reflective = (cls == CellClass::kUnknown || cls == CellClass::kFree)
                               ? classColor(CellClass::kOccupied)
                               : classColor(cls);
    for (int bin = 0; bin < slice.bins; ++bin) {
      Rgb colour;
      switch (slice.at(column, bin)) {
        case ThetaSlice::Bin::kOutside:
          colour = {110, 110, 110};
          break;
        case ThetaSlice::Bin::kUnobserved:
          colour = {215, 215, 215};
          break;
        case ThetaSlice::Bin::kMissed:
          colour = {255, 255, 255};
          break;
        case ThetaSlice::Bin::kReflective:
          colour = reflective;
          break;
      }
      image.set(column, slice.bins - 1 - bin, colour);  // theta up
    }
  }
  return image.scaled(column_px, bin_px);
}

}  // namespace render
}  // namespace rfm
