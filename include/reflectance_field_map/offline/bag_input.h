#pragma once

#include "reflectance_field_map/core/mapper.h"

#include <ros/time.h>

#include <cstdint>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {
namespace offline {

// The bag can't be turned into scans (unreadable, topics missing, TF missing): what() says
// why and what to do, in a few lines.
class BagInputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct BagInputOptions {
  std::string bag;
  std::vector<std::string> scan_topics;
  bool require_all_topics = false;  // else topics absent from the bag are skipped with a warning
  std::string fixed_frame = "odom";
  std::string base_frame = "base_link";
  double max_speed = 5.0;  // m/s: a robot pose that moved faster is a pose jump (PoseGate)
};

// Scans of one reason for not mapping them (the keys of BagScans::skipped, in summary.json):
//   oversized     larger than any LaserScan this tool takes (kMaxScanMessageBytes)
//   undecodable   bytes that do not hold a LaserScan (lengths beyond the message's end)
//   malformed     geometry that validate() refuses, or no frame_id
//   no_transform  no transform from the scan's frame or the base frame at its stamp
//   pose_jump     the robot moved faster than max_speed since the last mapped scan
struct SkipTally {
  uint64_t total = 0;
  std::vector<uint64_t> per_topic;  // parallel to BagScans::topics
  std::vector<std::string> first;   // per topic: when the first one was, and why
};

// Where one TimedScan came from, to label it back in the bag's terms.
struct ScanSource {
  uint32_t topic_index = 0;
  uint32_t seq = 0;
  ros::Time stamp;     // header stamp
  ros::Time bag_time;  // time the scan was recorded in the bag
  std::string frame_id;
  bool reversed = false;  // angle_increment < 0 in the bag: beams were reversed for the core
  ros::Time sweep_end;    // when the last beam was measured (ros_glue::sweepEnd): stamp if unknown
};

struct BagScans {
  std::vector<std::string> topics;           // scan topics read (present in the bag)
  std::vector<std::string> missing_topics;   // requested but absent
  std::vector<TimedScan> scans;              // the scans to map, by header stamp (stable)
  std::vector<ScanSource> sources;           // parallel to scans
  std::vector<uint64_t> scans_per_topic;     // parallel to topics: scans to map
  std::vector<uint64_t> read_per_topic;      // parallel to topics: scans in the bag
  std::map<std::string, SkipTally> skipped;  // by reason: scans read but not mapped
  uint64_t tf_messages = 0;                  // /tf + /tf_static messages loaded
  double duration = 0.0;                     // s, first to last scan stamp
  std::vector<std::string> notes;            // decisions worth telling the user

  uint64_t scansRead() const;
  uint64_t scansSkipped() const;
  // One line per reason for skipping: how many of the scans, on which topics, the first of them.
  std::vector<std::string> describeSkips() const;
};

// The topics of a comma-separated list ("/a,/b"), empty entries dropped.
std::vector<std::string> splitTopicList(const std::string& list);

// Reads all scans of the requested topics and their poses: TF comes from the bag's /tf and
// /tf_static (one tf2::BufferCore whose cache spans the whole bag). The laser pose and the
// base pose are looked up in the fixed frame at each scan's stamp; a scan already in the
// fixed frame has the identity pose (a stationary sensor: pass --fixed-frame <scan frame>).
// Every usable scan is kept; the others are skipped and counted by reason and topic
// (BagScans::skipped). Throws BagInputError when the bag cannot be read (saying how to recover a
// recording cut short) or when no scan is usable (with the counts and what to check).
// `progress(done, total)` may be empty.
BagScans readBagScans(const BagInputOptions& options,
                      const std::function<void(size_t, size_t)>& progress = {});

}  // namespace offline
}  // namespace rfm
