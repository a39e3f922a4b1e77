// When the batch's Alg. 3 passes stop: the glass each pass found, against the passes before.
#pragma once

#include <algorithm>
#include <cstddef>
#include <set>
#include <utility>
#include <vector>

namespace rfm::detail {

// Cells (x, y) that block rays and are not static: glass, metal, structure.
using GlassCells = std::set<std::pair<int, int>>;

enum class GlassPassOutcome {
  kChanged,    // the glass moved on: another pass may find more
  kConverged,  // under 1 % of it changed since the pass before
  kCycle,      // a state seen before: the passes alternate
};

// Alg. 3 iterates until the glass found stops changing. Under 1 % changed counts as converged:
// the paper sees no meaningful difference after the first re-processing, and a few cells may
// flicker forever. Two panes facing each other can make it alternate (each pass erases the other
// pane), so a state seen before ends it too.
class GlassPasses {
 public:
  GlassPassOutcome add(GlassCells glass) {
    const bool converged =
        !seen_.empty() && symmetricDifference(glass, seen_.back()) * 100 <= glass.size();
    const bool cycle = !converged && std::find(seen_.begin(), seen_.end(), glass) != seen_.end();
    seen_.push_back(std::move(glass));
    if (converged) return GlassPassOutcome::kConverged;
    return cycle ? GlassPassOutcome::kCycle : GlassPassOutcome::kChanged;
  }

 private:
  static size_t symmetricDifference(const GlassCells& a, const GlassCells& b) {
    size_t common = 0;
    for (const auto& cell : a)
      common += b.count(cell);
    return a.size() + b.size() - 2 * common;
  }

  std::vector<GlassCells> seen_;
};

}  // namespace rfm::detail
