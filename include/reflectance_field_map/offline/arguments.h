#pragma once

#include "reflectance_field_map/core/batch_processor.h"
#include "reflectance_field_map/core/options.h"

#include <array>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace offline {

// A command line that can't be run: what() says why, in one line, naming the flag.
class ArgumentError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// The rfm_offline command line (the flags are a contract, see usage()).
struct OfflineArguments {
  std::string bag;     // --bag IN.bag (required)
  std::string out;     // --out DIR (required, created)
  std::string params;  // --params FILE.yaml: mapper options by parameter name
  std::vector<std::string> scan_topics{"/scan_front", "/scan_rear"};
  bool scan_topics_given = false;  // --scan-topics was passed (else the defaults, those present)
  std::string fixed_frame = "odom";
  std::string base_frame = "base_link";
  bool no_motion_removal = false;
  bool no_reflection_removal = false;
  bool baseline = false;
  std::optional<std::array<double, 4>> theta_view;  // --theta-view x0,y0,x1,y1 (m)
  bool strict = false;     // --strict: a scan that cannot be mapped fails the run
  double max_speed = 5.0;  // --max-speed M/S: a faster robot pose is a pose jump (skipped)
  bool help = false;       // --help / -h: print usage, nothing else
};

// Parses argv[1..]. Throws ArgumentError for unknown flags, missing values, malformed values
// and missing required flags (unless --help). Accepts "--flag value" and "--flag=value".
OfflineArguments parseArguments(const std::vector<std::string>& args);
OfflineArguments parseArguments(int argc, char** argv);

std::string usage();

// The pipeline the flags (and the enable switches of `options`) select, and the options made
// consistent with it:
//   --baseline                                        kPlainGrid
//   --no-motion-removal --no-reflection-removal       kBasicRfm      (both switches off)
//   --no-reflection-removal                           kMotionRemoval (reflection switch off)
//   --no-motion-removal                               kFull with motion_removal_enabled = 0:
//        glass is found by motion removal (Alg. 3 step 1 uses Alg. 2), so without it nothing
//        blocks rays and the result equals the basic RFM
//   (none)                                            kFull
// A switch set to 0 in the --params file counts like the flag.
struct ModeSelection {
  BatchMode mode = BatchMode::kFull;
  std::string name;  // "full", "plain_grid", "basic_rfm", "motion_removal", "reflection_removal"
};
ModeSelection selectMode(const OfflineArguments& args, MapperOptions& options);

const char* toString(BatchMode mode);

}  // namespace offline
}  // namespace rfm
