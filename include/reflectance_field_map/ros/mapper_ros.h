#pragma once

#include "reflectance_field_map/LoadMap.h"
#include "reflectance_field_map/SaveMap.h"
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/core/pose_gate.h"
#include "reflectance_field_map/ros/latency_histogram.h"
#include "reflectance_field_map/ros/map_directory.h"
#include "reflectance_field_map/ros/parameters.h"
#include "reflectance_field_map/ros/transform_listener_thread.h"

#include <diagnostic_updater/diagnostic_updater.h>
#include <diagnostic_updater/update_functions.h>
#include <ros/ros.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>
#include <tf2_ros/buffer.h>

#include <boost/signals2/connection.hpp>

#include <atomic>
#include <chrono>
#include <deque>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <vector>

namespace rfm::ros_glue {

// The live Reflectance Field Map front-end shared by rfm_node and the RfmNodelet: owns one
// rfm::Mapper, feeds it the scans of every scan topic once TF knows the laser and the robot at
// the scan's stamp, runs motion removal every 1 / motion_removal_rate s of the scans' clock (on
// a timer once they stop) and publishes the map (/rfm/map,
// /rfm/map_updates), the glass and motion markers, one filtered scan per input, statistics and
// diagnostics. Services ~save_map, ~load_map and ~reset.
//
// Nothing a topic or a file brings may crash it, wipe the map or take the machine's memory: a
// scan that cannot be used is dropped and counted with its reason (malformed, no transform,
// stale: stamped before the previous scan on its topic, a pose jump faster than
// max_robot_speed, beyond max_map_extent, lost in a queue); only ROS time going back resets the
// map; ~save_map and ~load_map stay inside map_directory, and a state that fails to load leaves
// the running map as it was.
//
// Callbacks may run on several threads (nodelet manager, TF listener): the mapper and the
// publishing state are guarded by one mutex, the counters by another.
class MapperRos {
 public:
  // Reads and validates the private parameters (throws rfm::InvalidOption naming the
  // parameter before anything is subscribed or advertised), then sets up the ROS interfaces.
  MapperRos(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh);
  ~MapperRos();
  MapperRos(const MapperRos&) = delete;
  MapperRos& operator=(const MapperRos&) = delete;

  const RosParameters& parameters() const { return params_; }

  // "invalid parameter ~NAME: NAME = VALUE is invalid: allowed RANGE" for a FATAL log.
  static std::string describeParameterError(const rfm::InvalidOption& error);

 private:
  // Why a scan waiting for its transform was given up.
  enum class TfFailure {
    kOlderThanBuffer,  // the buffer no longer (or never) reaches back to its stamp
    kQueueOverflow,    // tf_queue_size newer scans arrived before its transform did
  };

  // A scan as it arrived and as the core takes it, converted and validated once, on arrival.
  struct ArrivedScan {
    sensor_msgs::LaserScanConstPtr msg;
    rfm::LaserScan2D scan;  // in the message's beam order (mirrored once TF says upside down)
    std::chrono::steady_clock::time_point arrived_at;  // incomingScan's start
    // When TF could first give its pose: arrived_at, or the first transform to reach the
    // buffer after the scan was last found waiting. From here on the time is the node's own.
    std::chrono::steady_clock::time_point ready_at;
  };

  struct ScanInput {
    uint32_t id = 0;
    std::string topic;  // as configured (absolute or relative to the node's namespace)
    std::string leaf;   // last component: /rfm/<leaf>/filtered
    ros::Subscriber subscriber;
    // Valid scans waiting, in order, until TF reaches their stamp (at most tf_queue_size). Only
    // the node's callback thread touches it.
    std::deque<ArrivedScan> waiting;
    ros::Publisher filtered_pub;
    ros::Publisher labels_pub;
    double min_rate = 0.0, max_rate = 0.0;
    std::unique_ptr<diagnostic_updater::FrequencyStatus> rate;
    ros::Time last_stamp;   // stamp of the previous scan received (stale: stamped before it)
    uint32_t last_seq = 0;  // header.seq of the last scan received (0: none yet)
    // transport_drops: gaps in header.seq (the subscriber queue overflowed: mapper too slow).
    std::atomic<uint64_t> received{0}, processed{0}, malformed{0}, tf_failures{0}, stale{0},
        pose_jumps{0}, beyond_extent{0}, transport_drops{0};
  };

  void setParams();
  void setRosInterfaces();
  void setDiagnostics();

  // Subscriber -> incomingScan (rate, time jumps, staleness, validation) -> waiting ->
  // processScan once TF reaches the scan's stamp (releaseWaiting, on every scan, on every change
  // of the TF buffer and on a wall timer); a scan given up on goes to tfFailure.
  void incomingScan(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg);
  // Every topic's waiting scans whose transforms have come, oldest stamp first across topics.
  void releaseWaiting();
  // Whether TF can place the scan now (empty `error`), or why not.
  bool transformReady(const sensor_msgs::LaserScan& msg, std::string& error) const;
  void processScan(ScanInput& input, ArrivedScan arrived);
  void tfFailure(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg, TfFailure reason);
  // On the TF listener's thread: notes the change and queues releaseWaiting on this node's
  // callback queue.
  void onTransformsChanged();
  // Whether any scan waits (scans_waiting_), after the queues changed.
  void updateScansWaiting();
  uint64_t callbackOwnerId() const;  // of the calls this node queues

  void motionRemovalTimer(const ros::WallTimerEvent& event);
  void mapTimer(const ros::WallTimerEvent& event);
  void markerTimer(const ros::WallTimerEvent& event);
  void statsTimer(const ros::WallTimerEvent& event);
  void watchdogTimer(const ros::WallTimerEvent& event);
  void tfWaitTimer(const ros::WallTimerEvent& event);
  void diagnosticsTimer(const ros::WallTimerEvent& event);

  bool saveMap(reflectance_field_map::SaveMap::Request& request,
               reflectance_field_map::SaveMap::Response& response);
  bool loadMap(reflectance_field_map::LoadMap::Request& request,
               reflectance_field_map::LoadMap::Response& response);
  bool reset(std_srvs::Trigger::Request& request, std_srvs::Trigger::Response& response);

  // ROS time went back (a looping bag): clears TF and the queued scans and resets the mapper.
  bool checkTimeJump();
  void resetAfterTimeJump(double seconds_back);

  // With mapper_mutex_ held: whether the mapper may take a scan whose robot stands at `robot`
  // (a pose within max_robot_speed of the last one, a map within max_map_extent). A refusal is
  // counted and reported; false then.
  bool admitPoseLocked(ScanInput& input, double stamp, const Eigen::Vector2d& robot);
  // The side of the box (m) the explored map would span once the active region reaches `robot`.
  Eigen::Vector2d extentWithLocked(const Eigen::Vector2d& robot) const;
  void dropScan(ScanInput& input, std::atomic<uint64_t>& reason_on_topic,
                std::atomic<uint64_t>& reason_total);

  // With mapper_mutex_ held.
  // A motion-removal pass and the map update carrying its changes (pass_to_update_), sent
  // before the pass's revert behind new glass.
  void removeMotionAndPublishLocked();
  double motionRemovalPeriod() const;  // s
  void publishFullMapLocked();
  // The changed window to /rfm/map_updates, or the full map when its bounds grew; false when
  // nothing changed.
  bool publishMapUpdateLocked();
  void publishMarkersLocked();
  void resetMapperLocked();

  void diagnoseTf(diagnostic_updater::DiagnosticStatusWrapper& status);
  void diagnoseInput(diagnostic_updater::DiagnosticStatusWrapper& status);
  void diagnoseMapper(diagnostic_updater::DiagnosticStatusWrapper& status);

  ros::NodeHandle nh_;
  ros::NodeHandle private_nh_;
  RosParameters params_;
  std::unique_ptr<MapDirectory> map_directory_;

  std::mutex mapper_mutex_;
  std::unique_ptr<rfm::Mapper> mapper_;
  std::unique_ptr<rfm::PoseGate> pose_gate_;
  uint64_t scans_since_motion_removal_ = 0;
  std::optional<double> last_pass_stamp_;  // the scan stamp (s) of the last motion-removal pass
  ros::Time last_scan_processed_;          // ROS time a scan was last inserted
  bool map_published_ = false;
  rfm::CellBox published_box_;   // geometry of the last full /rfm/map
  bool map_changed_ = true;      // since the last full map
  bool markers_changed_ = true;  // since the last markers
  double last_publish_ms_ = 0.0;
  // What /rfm/map and /rfm/map_updates cost so far (cells sent, time spent flattening and
  // publishing), reported on /rfm/stats.
  struct MapPublishTally {
    uint64_t full_maps = 0;
    uint64_t updates = 0;
    uint64_t cells = 0;
    double ms = 0.0;
  } map_tally_;
  // Each processed scan's wall time from its arrival (incomingScan) to its filtered scan and
  // labels published, and its two parts: the wait for its transform (to ready_at) and the
  // node's own work after it. Callback thread only.
  LatencyHistogram scan_latency_;
  LatencyHistogram tf_wait_;
  LatencyHistogram scan_work_;
  // And from its stamp (ROS time): what a consumer of the filtered scan sees, the sweep included.
  LatencyHistogram scan_age_;
  // Each motion-removal pass's wall time from its start to its map update (or full map)
  // published: how far /rfm/map_updates trails the scans the pass classified.
  LatencyHistogram pass_to_update_;

  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<TransformListenerThread> tf_listener_;
  std::vector<std::unique_ptr<ScanInput>> inputs_;

  ros::Publisher map_pub_, map_update_pub_, glass_pub_, motion_pub_, stats_pub_;
  ros::ServiceServer save_service_, load_service_, reset_service_;
  ros::WallTimer motion_timer_, map_timer_, marker_timer_, stats_timer_, watchdog_timer_,
      diagnostics_timer_, tf_wait_timer_;
  boost::signals2::connection transforms_changed_;  // TF listener -> onTransformsChanged
  std::atomic<bool> scans_waiting_{false};          // read on the TF listener's thread
  std::atomic<bool> release_queued_{false};         // a releaseWaiting call is queued
  // steady_clock nanoseconds of the first transform since the last release pass (0: none).
  std::atomic<int64_t> buffer_changed_ns_{0};
  std::unique_ptr<diagnostic_updater::Updater> diagnostics_;

  // Counters (also written from the TF listener thread through tfFailure).
  std::mutex counters_mutex_;
  std::set<std::string> frames_not_in_tf_;
  std::string last_tf_error_;
  std::atomic<uint64_t> scans_dropped_{0}, tf_failures_{0}, queue_overflows_{0},
      malformed_scans_{0}, stale_scans_{0}, pose_jumps_{0}, beyond_extent_{0}, time_jumps_{0},
      scans_processed_{0}, transport_drops_{0}, time_jump_drops_{0};
  uint64_t tf_failures_reported_ = 0, malformed_reported_ = 0, stale_reported_ = 0,
           pose_jumps_reported_ = 0, beyond_extent_reported_ = 0, time_jumps_reported_ = 0,
           transport_drops_reported_ = 0;
  double last_time_jump_s_ = 0.0;  // how far ROS time went back, last time (counters_mutex_)
  double last_pose_jump_m_ = 0.0;  // the last rejected pose's distance (counters_mutex_)
  Eigen::Vector2d last_extent_m_{0.0, 0.0};  // the extent a refused scan would have made
  ros::Time newest_time_;                    // newest ROS time seen, to detect jumps back
};

}  // namespace rfm::ros_glue
