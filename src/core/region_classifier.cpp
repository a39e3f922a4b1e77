#include "reflectance_field_map/core/region_classifier.h"

#include <utility>

namespace rfm {

RegionClassifier::RegionClassifier(const OccupancyRule& rule, MotionRemover* motion,
                                   GlassCompletion completion)
    : rule_(rule), motion_(motion), completion_(std::move(completion)) {}

MotionRemovalCounts RegionClassifier::classify(const ReflectanceField& field,
                                               const AnchorHistory& history, const GlobalMap2D& map,
                                               ParallelRunner* runner) {
  MotionRemovalCounts counts;
  region_.box = field.activeBox();
  if (motion_) {
    counts = motion_->classify(
        field, history, region_.box, [&map](const CellIndex& cell) { return map.get(cell); },
        region_.classes, runner);
  } else {
    region_.classes.resize(static_cast<size_t>(region_.box.width()) * region_.box.height());
    size_t i = 0;
    field.window().forEachCell(region_.box, [&](int, int, int slot) {
      const CellClass c = rule_.classify(field.reflectiveBinsAt(slot), field.missedBinsAt(slot));
      region_.classes[i++] = c;
      counts.free_cells += c == CellClass::kFree;
      counts.static_cells += c == CellClass::kOccupied;
    });
  }

  // Glass the robot has not faced yet, on the lines of glass it has.
  const RollingWindow& window = field.window();
  const CellBox& box = region_.box;
  std::vector<TileIndex> redrawn_tiles;
  auto tile_of = [&](int i) { return window.tileOf(box.cellAt(i)); };
  for (int i : completion_.complete(field, box, region_.classes)) {
    redrawn_tiles.push_back(tile_of(i));
    ++counts.glass_cells;
  }
  counts.motion_cells -= completion_.turnedFromMotion();
  // Glass and metal on no pane, or not facing it: static.
  auto faces_normal = [&](int i, const Eigen::Vector2d& normal, double max_off) {
    const int slot = window.storageIndex(box.cellAt(i));
    return !field.anyReflectiveAt(slot) || field.reflectsNearAxisAt(slot, normal, max_off);
  };
  const OffPaneCells off_pane = drawStaticOffPane(box, region_.classes, panes_, faces_normal);
  for (int i : off_pane.cells) {
    if (redrawn_tiles.empty() || redrawn_tiles.back() != tile_of(i)) {
      redrawn_tiles.push_back(tile_of(i));
    }
  }
  counts.glass_cells -= off_pane.glass;
  counts.metal_cells -= off_pane.metal;
  counts.static_cells += off_pane.glass + off_pane.metal;
  region_.unchanged_tiles.clear();
  if (motion_) markUnchangedTiles(window, redrawn_tiles);
  redrawn_tiles_ = std::move(redrawn_tiles);
  return counts;
}

void RegionClassifier::markUnchangedTiles(const RollingWindow& window,
                                          const std::vector<TileIndex>& redrawn_tiles) {
  region_.unchanged_tiles.assign(window.storageTiles(), 0);
  for (const TileIndex& tile : window.tiles()) {
    region_.unchanged_tiles[window.storageTile(tile)] =
        motion_->reusedTile(window.tileBox(tile).min);
  }
  auto mark_changed = [&](const std::vector<TileIndex>& tiles) {
    for (const TileIndex& tile : tiles) {
      if (window.contains(window.tileBox(tile).min)) {
        region_.unchanged_tiles[window.storageTile(tile)] = 0;
      }
    }
  };
  mark_changed(redrawn_tiles);
  mark_changed(redrawn_tiles_);
}

void RegionClassifier::writeTo(const RollingWindow& window, GlobalMap2D& map) const {
  auto class_at = [this](const CellIndex& cell) { return region_.at(cell); };
  if (region_.unchanged_tiles.empty()) {
    map.assign(region_.box, class_at);
    return;
  }
  for (const TileIndex& tile : window.tiles()) {
    if (!region_.unchanged_tiles[window.storageTile(tile)]) {
      map.assign(window.tileBox(tile), class_at);
    }
  }
}

}  // namespace rfm
