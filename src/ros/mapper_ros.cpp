#include "reflectance_field_map/ros/mapper_ros.h"

#include "reflectance_field_map/RfmStats.h"
#include "reflectance_field_map/ros/conversions.h"
#include "reflectance_field_map/ros/map_files.h"

#include <map_msgs/OccupancyGridUpdate.h>
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include <ros/callback_queue_interface.h>

#include <boost/bind/bind.hpp>
#include <boost/make_shared.hpp>

#include <chrono>
#include <functional>
#include <limits>
#include <sstream>

namespace rfm::ros_glue {
namespace {

constexpr char kMapTopic[] = "/rfm/map";
constexpr char kMapUpdatesTopic[] = "/rfm/map_updates";
constexpr char kGlassMarkersTopic[] = "/rfm/glass_markers";
constexpr char kMotionMarkersTopic[] = "/rfm/motion_markers";
constexpr char kStatsTopic[] = "/rfm/stats";
// Scans a topic's subscriber holds while the mapper is busy (a motion-removal pass that finds new
// glass re-processes its buffered scans): 10 s of a 40 Hz lidar, 1 s of it in a bag replayed at
// 10x (100 loses 20-70 of its 6401 scans there), at most 4 MB of 1081-beam scans. Scans beyond it
// are dropped by roscpp and counted from the gaps in header.seq.
constexpr uint32_t kSubscriberQueue = 400;
// Filtered scans and labels held for a subscriber that reads late (a busy planner, a loaded
// machine): 1.25 s of two 40 Hz lidars, where 10 would lose them after an eighth of a second.
constexpr uint32_t kPerScanOutputQueue = 100;

double elapsedMs(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// tf2's words for a transform that can never come: the buffer has moved past the stamp.
bool olderThanBuffer(const std::string& tf_error) {
  return tf_error.find("extrapolation into the past") != std::string::npos;
}

// A function run by a callback queue, in the order of the queue's other callbacks.
class QueuedCall : public ros::CallbackInterface {
 public:
  explicit QueuedCall(std::function<void()> call) : call_(std::move(call)) {}
  CallResult call() override {
    call_();
    return Success;
  }

 private:
  std::function<void()> call_;
};

}  // namespace

MapperRos::MapperRos(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh), private_nh_(private_nh) {
  setParams();
  setRosInterfaces();
  setDiagnostics();
}

MapperRos::~MapperRos() {
  // Stop the callbacks before the members they use go away.
  tf_listener_.reset();  // its thread calls onTransformsChanged
  tf_buffer_->_removeTransformsChangedListener(transforms_changed_);
  nh_.getCallbackQueue()->removeByID(callbackOwnerId());
  motion_timer_.stop();
  map_timer_.stop();
  marker_timer_.stop();
  stats_timer_.stop();
  watchdog_timer_.stop();
  diagnostics_timer_.stop();
  tf_wait_timer_.stop();
  for (auto& input : inputs_)
    input->subscriber.shutdown();
}

std::string MapperRos::describeParameterError(const rfm::InvalidOption& error) {
  return "invalid parameter ~" + error.field() + ": " + error.what();
}

void MapperRos::setParams() {
  params_ = readParameters(private_nh_);  // throws rfm::InvalidOption
  for (const std::string& name : unknownParameters(private_nh_)) {
    ROS_WARN("rfm: ignoring unknown parameter ~%s (see config/default.yaml)", name.c_str());
  }
  mapper_ = std::make_unique<rfm::Mapper>(params_.mapper);
  mapper_->prefault();  // here, not on the first scan
  pose_gate_ = std::make_unique<rfm::PoseGate>(params_.max_robot_speed, rfm::kPoseJumpSlack);
  map_directory_ = std::make_unique<MapDirectory>(params_.map_directory);
  std::ostringstream topics;
  for (const std::string& topic : params_.scan_topics)
    topics << ' ' << topic;
  ROS_INFO(
      "rfm: mapping in '%s' around '%s' from%s (resolution %.3f m, %d direction bins, "
      "active region %.1f m)",
      params_.fixed_frame.c_str(), params_.base_frame.c_str(), topics.str().c_str(),
      params_.mapper.grid.resolution, params_.mapper.grid.theta_bins,
      params_.mapper.active_region.active_region_radius);
  ROS_INFO("rfm: poses faster than %.1f m/s rejected, map up to %.0f m across, maps in %s",
           params_.max_robot_speed, params_.max_map_extent, map_directory_->path().c_str());
}

void MapperRos::setRosInterfaces() {
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<TransformListenerThread>(*tf_buffer_, nh_);

  map_pub_ = nh_.advertise<nav_msgs::OccupancyGrid>(kMapTopic, 1, true);
  map_update_pub_ = nh_.advertise<map_msgs::OccupancyGridUpdate>(kMapUpdatesTopic, 10);
  glass_pub_ = nh_.advertise<visualization_msgs::MarkerArray>(kGlassMarkersTopic, 1, true);
  motion_pub_ = nh_.advertise<visualization_msgs::MarkerArray>(kMotionMarkersTopic, 1, true);
  stats_pub_ = nh_.advertise<reflectance_field_map::RfmStats>(kStatsTopic, 10);

  const uint32_t queue = static_cast<uint32_t>(params_.tf_queue_size);
  for (size_t i = 0; i < params_.scan_topics.size(); ++i) {
    auto input = std::make_unique<ScanInput>();
    ScanInput& in = *input;
    in.id = static_cast<uint32_t>(i);
    in.topic = params_.scan_topics[i];
    in.leaf = topicLeaf(in.topic);
    in.filtered_pub =
        nh_.advertise<sensor_msgs::LaserScan>("/rfm/" + in.leaf + "/filtered", kPerScanOutputQueue);
    in.labels_pub = nh_.advertise<reflectance_field_map::RayLabels>("/rfm/" + in.leaf + "/labels",
                                                                    kPerScanOutputQueue);

    in.subscriber = nh_.subscribe<sensor_msgs::LaserScan>(
        in.topic, std::max<uint32_t>(kSubscriberQueue, queue),
        boost::function<void(const sensor_msgs::LaserScanConstPtr&)>(
            [this, &in](const sensor_msgs::LaserScanConstPtr& msg) { incomingScan(in, msg); }));
    inputs_.push_back(std::move(input));
  }

  save_service_ = private_nh_.advertiseService("save_map", &MapperRos::saveMap, this);
  load_service_ = private_nh_.advertiseService("load_map", &MapperRos::loadMap, this);
  reset_service_ = private_nh_.advertiseService("reset", &MapperRos::reset, this);

  // Every timer runs on wall time. Under simulated time (a replay) roscpp's ROS-time timer
  // thread wakes every millisecond to look at the clock, 1-3 % of a core for nothing; the
  // motion-removal passes follow the scans' own clock anyway (processScan). Wall timers also keep
  // running while a replay is paused and after ROS time jumps back.
  motion_timer_ = nh_.createWallTimer(
      ros::WallDuration(1.0 / params_.mapper.motion_removal.motion_removal_rate),
      &MapperRos::motionRemovalTimer, this);
  map_timer_ = nh_.createWallTimer(ros::WallDuration(1.0 / params_.map_publish_rate),
                                   &MapperRos::mapTimer, this);
  if (params_.marker_publish_rate > 0.0) {
    marker_timer_ = nh_.createWallTimer(ros::WallDuration(1.0 / params_.marker_publish_rate),
                                        &MapperRos::markerTimer, this);
  }
  stats_timer_ = nh_.createWallTimer(ros::WallDuration(1.0 / params_.stats_publish_rate),
                                     &MapperRos::statsTimer, this);
  watchdog_timer_ = nh_.createWallTimer(ros::WallDuration(0.25), &MapperRos::watchdogTimer, this);
  // Waiting scans are looked at again as soon as a transform arrives (posted to this node's
  // callback queue, so they stay on its one thread), and on a slow wall timer besides, which
  // gives up on those whose transform can no longer come when TF stops altogether.
  transforms_changed_ =
      tf_buffer_->_addTransformsChangedListener([this] { onTransformsChanged(); });
  tf_wait_timer_ = nh_.createWallTimer(ros::WallDuration(0.1), &MapperRos::tfWaitTimer, this);

  std::lock_guard<std::mutex> lock(mapper_mutex_);
  publishFullMapLocked();
}

void MapperRos::setDiagnostics() {
  diagnostics_ = std::make_unique<diagnostic_updater::Updater>(nh_, private_nh_);
  diagnostics_->setHardwareID("rfm:" + params_.fixed_frame);
  for (auto& input : inputs_) {
    input->min_rate = params_.min_scan_rate;
    input->max_rate = params_.max_scan_rate;
    input->rate = std::make_unique<diagnostic_updater::FrequencyStatus>(
        diagnostic_updater::FrequencyStatusParam(&input->min_rate, &input->max_rate, 0.1, 5),
        "Scan rate " + input->topic);
    diagnostics_->add(*input->rate);
  }
  diagnostics_->add("Scan input", this, &MapperRos::diagnoseInput);
  diagnostics_->add("TF", this, &MapperRos::diagnoseTf);
  diagnostics_->add("Mapper", this, &MapperRos::diagnoseMapper);
  diagnostics_timer_ =
      nh_.createWallTimer(ros::WallDuration(1.0), &MapperRos::diagnosticsTimer, this);
}

void MapperRos::incomingScan(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg) {
  const auto arrival = std::chrono::steady_clock::now();
  ++input.received;
  if (input.rate) input.rate->tick();
  // Publishers number their messages: a gap means the subscriber queue dropped scans.
  const uint32_t seq = msg->header.seq;
  if (input.last_seq != 0 && seq > input.last_seq + 1 && seq - input.last_seq < 100000) {
    const uint32_t lost = seq - input.last_seq - 1;
    input.transport_drops += lost;
    transport_drops_ += lost;
    ROS_WARN_THROTTLE(5.0, "rfm: %u scans on %s lost in the subscriber queue (mapper too slow?)",
                      lost, input.topic.c_str());
  }
  input.last_seq = seq;
  checkTimeJump();
  // A scan stamped before the previous one on its topic (a driver's clock stepping back, a bag
  // replayed without --clock, a message re-sent late) is dropped: the map stays.
  const ros::Time previous = input.last_stamp;
  input.last_stamp = msg->header.stamp;
  if (!previous.isZero() && msg->header.stamp < previous) {
    dropScan(input, input.stale, stale_scans_);
    ROS_WARN_THROTTLE(5.0,
                      "rfm: dropped a stale scan on %s: stamped %.3f s before the previous one "
                      "(%llu so far; the map is kept)",
                      input.topic.c_str(), (previous - msg->header.stamp).toSec(),
                      static_cast<unsigned long long>(stale_scans_.load()));
    return;
  }
  ArrivedScan arrived{msg, toLaserScan2D(*msg), arrival, arrival};
  const std::string problem = arrived.scan.validate();
  if (problem.empty() && !msg->header.frame_id.empty()) {
    input.waiting.push_back(std::move(arrived));
    // Before its transform is looked for: one arriving between that look and the end of the
    // pass must queue a release, or the scan waits for the next scan or transform.
    scans_waiting_.store(true, std::memory_order_release);
    if (input.waiting.size() > static_cast<size_t>(params_.tf_queue_size)) {
      const sensor_msgs::LaserScanConstPtr oldest = input.waiting.front().msg;
      input.waiting.pop_front();
      tfFailure(input, oldest, TfFailure::kQueueOverflow);
    }
    releaseWaiting();
    return;
  }
  dropScan(input, input.malformed, malformed_scans_);
  ROS_ERROR_THROTTLE(5.0, "rfm: rejected malformed scan on %s (frame '%s'): %s",
                     input.topic.c_str(), msg->header.frame_id.c_str(),
                     problem.empty() ? "empty frame_id" : problem.c_str());
}

void MapperRos::dropScan(ScanInput&, std::atomic<uint64_t>& reason_on_topic,
                         std::atomic<uint64_t>& reason_total) {
  ++reason_on_topic;
  ++reason_total;
  ++scans_dropped_;
}

bool MapperRos::transformReady(const sensor_msgs::LaserScan& msg, std::string& error) const {
  const std::string frame = tf2FrameId(msg.header.frame_id);
  const ros::Time stamp = msg.header.stamp;
  const ros::Time settled = stamp + ros::Duration(params_.tf_tolerance);
  // The sensor's pose when its sweep ended turns the beams and moves the returns
  // (rfm::compensateSweepMotion).
  const ros::Time sweep_end = sweepEnd(msg);
  return tf_buffer_->canTransform(params_.fixed_frame, frame, settled, &error) &&
         (sweep_end <= settled ||
          tf_buffer_->canTransform(params_.fixed_frame, frame, sweep_end, &error)) &&
         tf_buffer_->canTransform(params_.fixed_frame, params_.base_frame, settled, &error) &&
         tf_buffer_->canTransform(params_.fixed_frame, frame, stamp, &error) &&
         tf_buffer_->canTransform(params_.fixed_frame, params_.base_frame, stamp, &error);
}

void MapperRos::releaseWaiting() {
  // tf2_ros::MessageFilter can lose a scan whose transform arrives while it is being queued: the
  // buffer is asked directly instead, each time. Scans go in by stamp across topics, as the
  // offline tool reads them; a topic whose oldest scan still waits holds only its own.
  using Clock = std::chrono::steady_clock;
  const int64_t changed_ns = buffer_changed_ns_.exchange(0, std::memory_order_acq_rel);
  const Clock::time_point changed_at{std::chrono::nanoseconds(changed_ns)};
  std::vector<bool> held(inputs_.size(), false);
  for (;;) {
    ScanInput* next = nullptr;
    for (auto& input : inputs_) {
      if (held[input->id] || input->waiting.empty()) continue;
      if (!next ||
          input->waiting.front().msg->header.stamp < next->waiting.front().msg->header.stamp) {
        next = input.get();
      }
    }
    if (!next) break;
    std::string error;
    const bool ready = transformReady(*next->waiting.front().msg, error);
    if (!ready && !olderThanBuffer(error)) {  // its transform may still come
      held[next->id] = true;
      continue;
    }
    ArrivedScan arrived = std::move(next->waiting.front());
    next->waiting.pop_front();
    if (ready) {
      // Found waiting before: ready since the first transform after that look.
      if (changed_ns != 0) arrived.ready_at = std::max(arrived.arrived_at, changed_at);
      processScan(*next, std::move(arrived));
    } else {
      tfFailure(*next, arrived.msg, TfFailure::kOlderThanBuffer);
    }
  }
  updateScansWaiting();
}

void MapperRos::tfWaitTimer(const ros::WallTimerEvent&) {
  releaseWaiting();
}

void MapperRos::onTransformsChanged() {
  // On the TF listener's thread, for every transform: one queued call at a time, and none while
  // no scan waits.
  int64_t none = 0;
  buffer_changed_ns_.compare_exchange_strong(
      none, std::chrono::steady_clock::now().time_since_epoch().count(), std::memory_order_acq_rel);
  if (!scans_waiting_.load(std::memory_order_acquire)) return;
  if (release_queued_.exchange(true, std::memory_order_acq_rel)) return;
  nh_.getCallbackQueue()->addCallback(boost::make_shared<QueuedCall>([this] {
                                        release_queued_.store(false, std::memory_order_release);
                                        releaseWaiting();
                                      }),
                                      callbackOwnerId());
}

uint64_t MapperRos::callbackOwnerId() const {
  return reinterpret_cast<uint64_t>(this);
}

void MapperRos::updateScansWaiting() {
  bool any = false;
  for (const auto& input : inputs_)
    any = any || !input->waiting.empty();
  scans_waiting_.store(any, std::memory_order_release);
}

void MapperRos::tfFailure(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg,
                          TfFailure reason) {
  dropScan(input, input.tf_failures, tf_failures_);
  if (reason == TfFailure::kQueueOverflow) ++queue_overflows_;
  const std::string frame = tf2FrameId(msg->header.frame_id);
  // _frameExists is thread-safe (it locks the buffer).
  const bool known = !frame.empty() && tf_buffer_->_frameExists(frame);
  std::ostringstream text;
  if (!known) {
    text << "laser frame '" << frame << "' of " << input.topic
         << " is not in TF: publish a transform from '" << params_.base_frame << "' to it";
  } else {
    text << "no transform from '" << frame << "' to '" << params_.fixed_frame
         << "' at t=" << std::fixed << msg->header.stamp.toSec() << " for " << input.topic << " ("
         << (reason == TfFailure::kQueueOverflow ? "TF did not arrive before the queue overflowed"
                                                 : "older than the TF buffer")
         << ")";
  }
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    if (!known) frames_not_in_tf_.insert(frame);
    last_tf_error_ = text.str();
  }
  ROS_WARN_THROTTLE(5.0, "rfm: dropped a scan (%llu so far): %s",
                    static_cast<unsigned long long>(tf_failures_.load()), text.str().c_str());
}

void MapperRos::processScan(ScanInput& input, ArrivedScan arrived) {
  const sensor_msgs::LaserScanConstPtr& msg = arrived.msg;
  const std::string laser_frame = tf2FrameId(msg->header.frame_id);
  geometry_msgs::TransformStamped sensor_tf, robot_tf;
  try {
    sensor_tf = tf_buffer_->lookupTransform(params_.fixed_frame, laser_frame, msg->header.stamp);
    robot_tf =
        tf_buffer_->lookupTransform(params_.fixed_frame, params_.base_frame, msg->header.stamp);
  } catch (const tf2::TransformException& e) {
    dropScan(input, input.tf_failures, tf_failures_);
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      last_tf_error_ = e.what();
    }
    ROS_WARN_THROTTLE(5.0, "rfm: dropped a scan on %s: %s", input.topic.c_str(), e.what());
    return;
  }
  const PlanarSensorPose sensor = toPlanarSensorPose(sensor_tf.transform);
  rfm::TimedScan timed;
  timed.sensor_id = input.id;
  timed.stamp = msg->header.stamp.toSec();
  timed.scan = std::move(arrived.scan);
  if (sensor.upside_down) rfm::mirrorScan(timed.scan);
  const bool reversed = reversesBeamOrder(*msg, sensor.upside_down);
  timed.sensor_pose = sensor.pose;
  timed.robot_pose = toPose2D(robot_tf.transform);
  compensateSweepFromTf(*tf_buffer_, params_.fixed_frame, laser_frame, msg->header.stamp,
                        sweepEnd(*msg), reversed, timed);

  const bool want_labels =
      input.filtered_pub.getNumSubscribers() > 0 || input.labels_pub.getNumSubscribers() > 0;
  std::vector<rfm::RayLabel> labels;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    if (!admitPoseLocked(input, timed.stamp, timed.robot_pose.position)) return;
    const rfm::ScanUpdate update = mapper_->addScan(timed);
    if (!update.error.empty()) {
      dropScan(input, input.malformed, malformed_scans_);
      ROS_ERROR_THROTTLE(5.0, "rfm: rejected malformed scan on %s: %s", input.topic.c_str(),
                         update.error.c_str());
      return;
    }
    ++scans_since_motion_removal_;
    last_scan_processed_ = ros::Time::now();
    if (want_labels) {
      labels = mapper_->labelAddedScan(timed, update);
    }
  }
  ++input.processed;
  ++scans_processed_;
  if (want_labels) {
    labels = toMessageOrder(std::move(labels), reversed);
    if (input.filtered_pub.getNumSubscribers() > 0) {
      input.filtered_pub.publish(filterScan(*msg, labels));
    }
    if (input.labels_pub.getNumSubscribers() > 0) {
      input.labels_pub.publish(toRayLabelsMsg(msg->header, input.topic, labels));
    }
  }
  // One clock reading for the three, so that the wait and the work add up to the latency.
  const auto published = std::chrono::steady_clock::now();
  auto ms = [](std::chrono::steady_clock::duration d) {
    return std::chrono::duration<double, std::milli>(d).count();
  };
  scan_latency_.add(ms(published - arrived.arrived_at));
  tf_wait_.add(ms(arrived.ready_at - arrived.arrived_at));
  scan_work_.add(ms(published - arrived.ready_at));
  scan_age_.add((ros::Time::now() - msg->header.stamp).toSec() * 1000.0);

  // Motion removal every 1 / motion_removal_rate s of the scans' own clock, after the scan's
  // labels went out: which scans a pass has seen then depends on the recording alone, not on
  // how fast this machine keeps up with it (rfm_live_labels does the same). A persistence tick
  // the scan made due, and a part of the last pass's revert behind new glass, run here too, off
  // its latency.
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  mapper_->runDueTick();
  mapper_->revertPartBehindNewGlass();
  const double stamp = msg->header.stamp.toSec();
  const double period = motionRemovalPeriod();
  // A pass stamped far ahead of the scans (one scan stamped in the future) must not hold the
  // next ones back: the clock starts again from this scan.
  if (last_pass_stamp_ && stamp < *last_pass_stamp_ - 2.0 * period) last_pass_stamp_ = stamp;
  if (!last_pass_stamp_ || stamp - *last_pass_stamp_ >= period) {
    last_pass_stamp_ = stamp;
    removeMotionAndPublishLocked();
  }
}

double MapperRos::motionRemovalPeriod() const {
  return 1.0 / params_.mapper.motion_removal.motion_removal_rate;
}

bool MapperRos::admitPoseLocked(ScanInput& input, double stamp, const Eigen::Vector2d& robot) {
  if (!pose_gate_->accept(stamp, robot)) {
    dropScan(input, input.pose_jumps, pose_jumps_);
    const double jump = pose_gate_->lastRejectedJump();
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      last_pose_jump_m_ = jump;
    }
    ROS_WARN_THROTTLE(5.0,
                      "rfm: rejected a robot pose %.1f m from the last one, faster than "
                      "max_robot_speed %.1f m/s (%llu scans dropped so far; TF glitch?)",
                      jump, params_.max_robot_speed,
                      static_cast<unsigned long long>(pose_jumps_.load()));
    return false;
  }
  const Eigen::Vector2d extent = extentWithLocked(robot);
  if (extent.x() > params_.max_map_extent || extent.y() > params_.max_map_extent) {
    dropScan(input, input.beyond_extent, beyond_extent_);
    {
      std::lock_guard<std::mutex> lock(counters_mutex_);
      last_extent_m_ = extent;
    }
    ROS_ERROR_THROTTLE(5.0,
                       "rfm: map extent limit reached: mapping at (%.1f, %.1f) would make the map "
                       "%.0f x %.0f m, more than max_map_extent %.0f m; scan dropped (%llu so far)",
                       robot.x(), robot.y(), extent.x(), extent.y(), params_.max_map_extent,
                       static_cast<unsigned long long>(beyond_extent_.load()));
    return false;
  }
  return true;
}

Eigen::Vector2d MapperRos::extentWithLocked(const Eigen::Vector2d& robot) const {
  const double resolution = params_.mapper.grid.resolution;
  // The active region around the robot, rounded out to the field's and the map's tiles.
  const double reach = (mapper_->field().window().sizeCells() / 2 + params_.mapper.grid.tile_cells +
                        mapper_->map().tileCells()) *
                       resolution;
  Eigen::Vector2d low = robot - Eigen::Vector2d(reach, reach);
  Eigen::Vector2d high = robot + Eigen::Vector2d(reach, reach);
  const rfm::CellBox box = mapper_->map().bounds();
  if (!box.empty()) {
    low = low.cwiseMin(box.min.cast<double>() * resolution);
    high = high.cwiseMax(box.max.cast<double>() * resolution);
  }
  return high - low;
}

void MapperRos::motionRemovalTimer(const ros::WallTimerEvent&) {
  // Passes follow the scans' clock (processScan); this one classifies the last scans once they
  // stop coming.
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (scans_since_motion_removal_ == 0) return;
  if (ros::Time::now() - last_scan_processed_ < ros::Duration(motionRemovalPeriod())) return;
  removeMotionAndPublishLocked();
}

void MapperRos::removeMotionAndPublishLocked() {
  const auto start = std::chrono::steady_clock::now();
  mapper_->classifyActiveRegion();
  scans_since_motion_removal_ = 0;
  map_changed_ = true;
  markers_changed_ = true;
  if (publishMapUpdateLocked()) pass_to_update_.add(elapsedMs(start));
  // Alg. 3's re-processing of the buffered scans behind new glass changes only the evidence the
  // next scans meet: it goes in parts after the next scans (processScan).
}

void MapperRos::mapTimer(const ros::WallTimerEvent&) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (map_changed_ || !map_published_) publishFullMapLocked();
}

void MapperRos::markerTimer(const ros::WallTimerEvent&) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (markers_changed_) publishMarkersLocked();
}

void MapperRos::publishFullMapLocked() {
  const auto start = std::chrono::steady_clock::now();
  const rfm::GlobalMap2D& map = mapper_->map();
  const rfm::CellBox box = map.bounds();
  const nav_msgs::OccupancyGrid grid = toOccupancyGrid(map, box, params_.mapper.grid.resolution,
                                                       params_.fixed_frame, ros::Time::now());
  map_tally_.cells += grid.data.size();
  map_pub_.publish(grid);
  // The full map carries every change so far.
  mapper_->takeMapChanges();
  published_box_ = box;
  map_published_ = true;
  map_changed_ = false;
  last_publish_ms_ = elapsedMs(start);
  ++map_tally_.full_maps;
  map_tally_.ms += last_publish_ms_;
}

bool MapperRos::publishMapUpdateLocked() {
  const rfm::GlobalMap2D& map = mapper_->map();
  const rfm::CellBox bounds = map.bounds();
  const bool same_geometry =
      map_published_ && bounds.min == published_box_.min && bounds.max == published_box_.max;
  if (!same_geometry) {
    // The map grew: subscribers need a new full grid before any update can apply.
    publishFullMapLocked();
    return true;
  }
  const rfm::CellBox changed = mapper_->takeMapChanges().intersect(published_box_);
  if (changed.empty()) return false;
  const auto start = std::chrono::steady_clock::now();
  const map_msgs::OccupancyGridUpdate update =
      toOccupancyGridUpdate(map, changed, published_box_, params_.fixed_frame, ros::Time::now());
  map_tally_.cells += update.data.size();
  map_update_pub_.publish(update);
  last_publish_ms_ = elapsedMs(start);
  ++map_tally_.updates;
  map_tally_.ms += last_publish_ms_;
  return true;
}

void MapperRos::publishMarkersLocked() {
  const rfm::GlobalMap2D& map = mapper_->map();
  const rfm::CellBox box = map.bounds();
  std::vector<rfm::CellClass> cells;
  if (!box.empty()) map.extract(box, cells);
  const ros::Time stamp = ros::Time::now();
  const double resolution = params_.mapper.grid.resolution;
  const std::string& frame = params_.fixed_frame;
  visualization_msgs::MarkerArray glass, motion;
  glass.markers.push_back(
      toCubeList(cells, box, rfm::CellClass::kGlass, resolution, frame, stamp, "glass", 0));
  glass.markers.push_back(
      toCubeList(cells, box, rfm::CellClass::kMetal, resolution, frame, stamp, "metal", 1));
  motion.markers.push_back(
      toCubeList(cells, box, rfm::CellClass::kMotion, resolution, frame, stamp, "motion", 0));
  glass_pub_.publish(glass);
  motion_pub_.publish(motion);
  markers_changed_ = false;
}

void MapperRos::statsTimer(const ros::WallTimerEvent&) {
  reflectance_field_map::RfmStats msg;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    const rfm::MapperStats stats = mapper_->stats();
    msg.rays_inserted = stats.rays_inserted;
    msg.insert_ms = stats.last_insert_ms;
    msg.reflection_ms = stats.last_reflection_ms;
    msg.motion_removal_ms = stats.last_motion_removal_ms;
    msg.occupied_cells = static_cast<uint32_t>(stats.occupied_cells);
    msg.free_cells = static_cast<uint32_t>(stats.free_cells);
    msg.glass_cells = static_cast<uint32_t>(stats.glass_cells);
    msg.motion_cells = static_cast<uint32_t>(stats.motion_cells);
    msg.field_bytes = stats.field_bytes;
    msg.archived_bytes = stats.archived_bytes;
    msg.publish_ms = last_publish_ms_;
    msg.full_maps_published = map_tally_.full_maps;
    msg.map_updates_published = map_tally_.updates;
    msg.map_cells_published = map_tally_.cells;
    msg.map_publish_ms_total = map_tally_.ms;
    msg.scan_latency_ms_median = scan_latency_.quantile(0.5);
    msg.scan_latency_ms_p99 = scan_latency_.quantile(0.99);
    msg.scan_latency_ms_max = scan_latency_.max();
    msg.tf_wait_ms_median = tf_wait_.quantile(0.5);
    msg.tf_wait_ms_p99 = tf_wait_.quantile(0.99);
    msg.tf_wait_ms_max = tf_wait_.max();
    msg.scan_work_ms_median = scan_work_.quantile(0.5);
    msg.scan_work_ms_p99 = scan_work_.quantile(0.99);
    msg.scan_work_ms_max = scan_work_.max();
    msg.scan_age_ms_median = scan_age_.quantile(0.5);
    msg.scan_age_ms_p99 = scan_age_.quantile(0.99);
    msg.scan_age_ms_max = scan_age_.max();
    msg.pass_to_update_ms_median = pass_to_update_.quantile(0.5);
    msg.pass_to_update_ms_p99 = pass_to_update_.quantile(0.99);
    msg.pass_to_update_ms_max = pass_to_update_.max();
  }
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = params_.fixed_frame;
  msg.scans_processed = scans_processed_;
  // Every reason: malformed, without TF, stale, pose jump, map extent, lost in queues.
  msg.scans_dropped = scans_dropped_ + transport_drops_;
  stats_pub_.publish(msg);
}

bool MapperRos::checkTimeJump() {
  const ros::Time now = ros::Time::now();
  bool jumped = false;
  double back = 0.0;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    if (!newest_time_.isZero() && now + ros::Duration(params_.time_jump_threshold) < newest_time_) {
      jumped = true;
      back = (newest_time_ - now).toSec();
      newest_time_ = now;
    } else if (now > newest_time_) {
      newest_time_ = now;
    }
  }
  if (jumped) resetAfterTimeJump(back);
  return jumped;
}

void MapperRos::resetAfterTimeJump(double seconds_back) {
  ++time_jumps_;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    last_time_jump_s_ = seconds_back;
  }
  ROS_WARN(
      "rfm: ROS time jumped back by %.3f s (a looping bag?): clearing the TF buffer and "
      "resetting the map",
      seconds_back);
  tf_buffer_->clear();  // static transforms survive a clear
  for (auto& input : inputs_) {
    // Scans of the time before the jump can no longer be placed.
    scans_dropped_ += input->waiting.size();
    time_jump_drops_ += input->waiting.size();
    input->waiting.clear();
    updateScansWaiting();
    input->last_stamp = ros::Time();
    input->last_seq = 0;
    if (input->rate) input->rate->clear();
  }
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  resetMapperLocked();
}

void MapperRos::resetMapperLocked() {
  mapper_->reset();
  mapper_->prefault();
  pose_gate_->reset();
  scans_since_motion_removal_ = 0;
  last_pass_stamp_.reset();
  map_published_ = false;
  publishFullMapLocked();
  publishMarkersLocked();
}

void MapperRos::watchdogTimer(const ros::WallTimerEvent&) {
  checkTimeJump();
}

void MapperRos::diagnosticsTimer(const ros::WallTimerEvent&) {
  diagnostics_->force_update();
}

bool MapperRos::saveMap(reflectance_field_map::SaveMap::Request& request,
                        reflectance_field_map::SaveMap::Response& response) {
  std::string prefix, error;
  response.success = map_directory_->resolve(request.path, true, prefix, &error);
  for (const char* suffix : {".pgm", ".yaml", ""}) {
    if (!response.success) break;
    const std::string file = *suffix ? prefix + suffix : stateFilePath(prefix);
    response.success = map_directory_->holds(file, &error);
  }
  if (response.success) {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    // Classify what arrived since the last pass so the files hold every scan so far.
    if (scans_since_motion_removal_ > 0) {
      removeMotionAndPublishLocked();
    }
    mapper_->revertBehindNewGlass();  // the state file holds no evidence from beyond glass
    response.success = saveMapFiles(prefix, *mapper_, params_.fixed_frame, &error);
  }
  if (response.success) {
    response.message = "saved " + prefix + ".pgm, " + prefix + ".yaml and " + stateFilePath(prefix);
    ROS_INFO("rfm: %s", response.message.c_str());
  } else {
    response.message = "save_map failed: " + error;
    ROS_ERROR("rfm: %s", response.message.c_str());
  }
  return true;
}

bool MapperRos::loadMap(reflectance_field_map::LoadMap::Request& request,
                        reflectance_field_map::LoadMap::Response& response) {
  std::string path, error;
  response.success = map_directory_->resolve(request.path, false, path, &error) &&
                     map_directory_->holds(stateFilePath(path), &error);
  // Loaded beside the running mapper, which keeps mapping until the state is known good.
  std::unique_ptr<rfm::Mapper> loaded;
  if (response.success) {
    loaded = std::make_unique<rfm::Mapper>(params_.mapper);
    response.success = loadMapperState(path, *loaded, &error);
  }
  if (response.success) {
    const rfm::CellBox box = loaded->map().bounds();
    const double resolution = params_.mapper.grid.resolution;
    const double width = box.empty() ? 0.0 : box.width() * resolution;
    const double height = box.empty() ? 0.0 : box.height() * resolution;
    if (width > params_.max_map_extent || height > params_.max_map_extent) {
      std::ostringstream why;
      why << stateFilePath(path) << " holds a map of " << width << " x " << height
          << " m, more than max_map_extent " << params_.max_map_extent << " m";
      error = why.str();
      response.success = false;
    }
  }
  if (response.success) {
    loaded->prefault();  // outside the lock: the running mapper keeps mapping meanwhile
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    mapper_.swap(loaded);  // the old mapper goes when `loaded` does, outside the lock
    pose_gate_->reset();
    scans_since_motion_removal_ = 0;
    last_pass_stamp_.reset();
    map_published_ = false;
    publishFullMapLocked();
    publishMarkersLocked();
  }
  if (response.success) {
    response.message = "resumed from " + stateFilePath(path);
    ROS_INFO("rfm: %s", response.message.c_str());
  } else {
    response.message = "load_map failed (the map is unchanged): " + error;
    ROS_ERROR("rfm: %s", response.message.c_str());
  }
  return true;
}

bool MapperRos::reset(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  resetMapperLocked();
  response.success = true;
  response.message = "map cleared";
  ROS_INFO("rfm: map cleared (~reset)");
  return true;
}

void MapperRos::diagnoseInput(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const uint64_t malformed = malformed_scans_;
  const uint64_t stale = stale_scans_;
  if (malformed > malformed_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%llu malformed scans rejected",
                    static_cast<unsigned long long>(malformed - malformed_reported_));
  } else if (stale > stale_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%llu stale scans dropped (stamped before the previous scan on their topic; "
                    "the map is kept)",
                    static_cast<unsigned long long>(stale - stale_reported_));
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "scans well formed");
  }
  malformed_reported_ = malformed;
  stale_reported_ = stale;
  for (const auto& input : inputs_) {
    std::ostringstream value;
    value << input->received << " received, " << input->processed << " processed, "
          << input->malformed << " malformed, " << input->tf_failures << " without TF, "
          << input->stale << " stale, " << input->pose_jumps << " at a pose jump, "
          << input->beyond_extent << " beyond the map extent limit, " << input->transport_drops
          << " lost in the subscriber queue";
    status.add(input->topic, value.str());
  }
  status.add("Scans dropped (total)", scans_dropped_.load());
  status.add("Stale scans dropped (total)", stale);
  status.add("TF queue overflows (total)", queue_overflows_.load());
  const uint64_t lost = transport_drops_;
  status.add("Scans lost in subscriber queues (total)", lost);
  if (lost > transport_drops_reported_ && status.level == diagnostic_msgs::DiagnosticStatus::OK) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%llu scans lost in subscriber queues (mapper slower than the scans)",
                    static_cast<unsigned long long>(lost - transport_drops_reported_));
  }
  transport_drops_reported_ = lost;
}

void MapperRos::diagnoseTf(diagnostic_updater::DiagnosticStatusWrapper& status) {
  const uint64_t failures = tf_failures_;
  std::string frames, last_error;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    for (const std::string& frame : frames_not_in_tf_)
      frames += (frames.empty() ? "" : ", ") + frame;
    last_error = last_tf_error_;
  }
  if (failures > tf_failures_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%llu scans dropped without a transform to '%s'",
                    static_cast<unsigned long long>(failures - tf_failures_reported_),
                    params_.fixed_frame.c_str());
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "transforms available");
  }
  tf_failures_reported_ = failures;
  status.add("Scans without transform (total)", failures);
  status.add("Laser frames never seen in TF", frames.empty() ? std::string("none") : frames);
  status.add("Last TF error", last_error.empty() ? std::string("none") : last_error);
}

void MapperRos::diagnoseMapper(diagnostic_updater::DiagnosticStatusWrapper& status) {
  rfm::MapperStats stats;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    stats = mapper_->stats();
    status.add("Publish time (ms)", last_publish_ms_);
    const rfm::CellBox box = mapper_->map().bounds();
    const double resolution = params_.mapper.grid.resolution;
    std::ostringstream size;
    size << (box.empty() ? 0.0 : box.width() * resolution) << " x "
         << (box.empty() ? 0.0 : box.height() * resolution) << " (limit " << params_.max_map_extent
         << ")";
    status.add("Map extent (m)", size.str());
    status.add("Explored map memory (bytes)", mapper_->map().bytes());
  }
  const uint64_t jumps = time_jumps_, pose_jumps = pose_jumps_, beyond = beyond_extent_;
  double time_back = 0.0, pose_jump = 0.0;
  Eigen::Vector2d extent;
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    time_back = last_time_jump_s_;
    pose_jump = last_pose_jump_m_;
    extent = last_extent_m_;
  }
  // The worst news of the period first: a limit reached, a reset, rejected poses.
  if (beyond > beyond_extent_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR,
                    "map extent limit reached: %llu scans dropped that would make the map %.0f x "
                    "%.0f m (max_map_extent %.0f m)",
                    static_cast<unsigned long long>(beyond - beyond_extent_reported_), extent.x(),
                    extent.y(), params_.max_map_extent);
  } else if (jumps > time_jumps_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "ROS time jumped back by %.3f s: map reset", time_back);
  } else if (pose_jumps > pose_jumps_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::WARN,
                    "%llu scans dropped at a pose jump (last %.1f m, faster than max_robot_speed "
                    "%.1f m/s)",
                    static_cast<unsigned long long>(pose_jumps - pose_jumps_reported_), pose_jump,
                    params_.max_robot_speed);
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "mapping");
  }
  time_jumps_reported_ = jumps;
  pose_jumps_reported_ = pose_jumps;
  beyond_extent_reported_ = beyond;
  status.add("Scans processed", scans_processed_.load());
  auto add_latency = [&status](const std::string& name, const LatencyHistogram& histogram) {
    status.add(name + " median (ms)", histogram.quantile(0.5));
    status.add(name + " p99 (ms)", histogram.quantile(0.99));
    status.add(name + " max (ms)", histogram.max());
  };
  add_latency("Scan latency", scan_latency_);
  add_latency("TF wait", tf_wait_);
  add_latency("Scan work", scan_work_);
  add_latency("Scan age", scan_age_);
  add_latency("Pass to map update", pass_to_update_);
  status.add("Scan insertion time (ms)", stats.last_insert_ms);
  status.add("Reflection check time (ms)", stats.last_reflection_ms);
  status.add("Motion removal time (ms)", stats.last_motion_removal_ms);
  status.add("Glass cells (active region)", stats.glass_cells);
  status.add("Motion cells (active region)", stats.motion_cells);
  status.add("Field memory (bytes)", stats.field_bytes);
  status.add("Archived memory (bytes)", stats.archived_bytes);
  status.add("Time jumps (total)", jumps);
  status.add("Scans dropped at a time jump (total)", time_jump_drops_.load());
  status.add("Scans dropped at a pose jump (total)", pose_jumps);
  status.add("Scans dropped beyond the map extent limit (total)", beyond);
}

}  // namespace rfm::ros_glue
