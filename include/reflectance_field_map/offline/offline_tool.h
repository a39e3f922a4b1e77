#pragma once

#include "reflectance_field_map/offline/arguments.h"

#include <iosfwd>

namespace rfm {
namespace offline {

// Runs rfm_offline for parsed arguments: options, bag -> scans, processBatch, outputs.
// Messages go to `log` (progress bars to stderr when it is a terminal). Returns the exit code:
// 0 done, 1 the run failed (bag, TF, output), 2 bad parameters.
int runOffline(const OfflineArguments& args, std::ostream& log);

}  // namespace offline
}  // namespace rfm
