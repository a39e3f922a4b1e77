// A motion-removal pass over the active region: its cells classified and written to the map.
#pragma once

#include "reflectance_field_map/core/active_classes.h"
#include "reflectance_field_map/core/anchor_history.h"
#include "reflectance_field_map/core/glass_completion.h"
#include "reflectance_field_map/core/global_map.h"
#include "reflectance_field_map/core/motion_removal.h"
#include "reflectance_field_map/core/occupancy.h"
#include "reflectance_field_map/core/pane_shape.h"
#include "reflectance_field_map/core/parallel_runner.h"
#include "reflectance_field_map/core/reflectance_field.h"

#include <vector>

namespace rfm {

// Classifies the field's active box: motion removal (Alg. 2), or the plain eq. 5 projection when
// there is no MotionRemover, then glass completion, and glass and metal on no pane drawn static
// (PaneShape). It remembers which tiles are known to hold the classes of its last pass, so that
// writing the region into the explored map skips them.
class RegionClassifier {
 public:
  // `rule` and `motion` (null: motion removal off) must outlive this.
  RegionClassifier(const OccupancyRule& rule, MotionRemover* motion, GlassCompletion completion);

  // Classifies the active box of `field`; `map` gives the known classes just outside it. Rows
  // on the runner's threads. The counts include the glass completed and the cells on no pane as
  // static.
  MotionRemovalCounts classify(const ReflectanceField& field, const AnchorHistory& history,
                               const GlobalMap2D& map, ParallelRunner* runner);
  const ClassifiedRegion& region() const { return region_; }
  // Writes the last pass's classes into `map`, skipping the tiles known unchanged.
  void writeTo(const RollingWindow& window, GlobalMap2D& map) const;
  // Forgets where glass was completed or drawn static (the classes it made are forgotten
  // elsewhere).
  void clear() { redrawn_tiles_.clear(); }

 private:
  // Marks the tiles motion removal copied from its last pass, unless glass is or was completed
  // or drawn static there: those cells change class with no change of their own evidence.
  void markUnchangedTiles(const RollingWindow& window, const std::vector<TileIndex>& redrawn_tiles);

  const OccupancyRule& rule_;
  MotionRemover* motion_;
  GlassCompletion completion_;
  ClassifiedRegion region_;
  PaneShape panes_;
  // Tiles holding completed glass or glass drawn static at the last pass.
  std::vector<TileIndex> redrawn_tiles_;
};

}  // namespace rfm
