// The command line the peer programs share (rfm_octomap_peer, rfm_mrpt_peer):
//   PROGRAM IN.bag TOPIC[,TOPIC...] [FIXED_FRAME BASE_FRAME]
// turned into the options of rfm_offline's own reader for the scans it names.
#pragma once

#include "reflectance_field_map/offline/bag_input.h"

#include <optional>
#include <string>

namespace rfm::benchmark {

// The reader's options from the arguments, or nothing when they do not fit the usage.
inline std::optional<offline::BagInputOptions> peerInputOptions(int argc, char** argv) {
  if (argc != 3 && argc != 5) return std::nullopt;
  offline::BagInputOptions options;
  options.bag = argv[1];
  options.scan_topics = offline::splitTopicList(argv[2]);
  if (argc == 5) {
    options.fixed_frame = argv[3];
    options.base_frame = argv[4];
  }
  return options;
}

inline const char* peerUsage() {
  return "IN.bag TOPIC[,TOPIC...] [FIXED_FRAME BASE_FRAME]";
}

}  // namespace rfm::benchmark
