#include "reflectance_field_map/ros/mapper_ros.h"

#include "reflectance_field_map/RfmStats.h"
#include "reflectance_field_map/ros/conversions.h"
#include "reflectance_field_map/ros/map_files.h"

#include <map_msgs/OccupancyGridUpdate.h>
#include <nav_msgs/OccupancyGrid.h>
#include <visualization_msgs/MarkerArray.h>

#include <boost/bind/bind.hpp>

#include <chrono>
#include <cstdlib>
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

double elapsedMs(const std::chrono::steady_clock::time_point& start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// "~/x" -> "$HOME/x".
std::string expandHome(const std::string& path) {
  const char* home = std::getenv("HOME");
  if (home != nullptr && path.size() >= 2 && path[0] == '~' && path[1] == '/') {
    return std::string(home) + path.substr(1);
  }
  return path;
}

const char* failureName(tf2_ros::FilterFailureReason reason) {
  switch (reason) {
    case tf2_ros::filter_failure_reasons::OutTheBack:
      return "older than the TF buffer";
    case tf2_ros::filter_failure_reasons::EmptyFrameID:
      return "empty frame_id";
    default:
      return "TF did not arrive before the queue overflowed";
  }
}

}  // namespace

MapperRos::MapperRos(const ros::NodeHandle& nh, const ros::NodeHandle& private_nh)
    : nh_(nh), private_nh_(private_nh) {
  setParams();
  setRosInterfaces();
  setDiagnostics();
}

MapperRos::~MapperRos() {
  // Stop the callbacks before the members they use go away.
  motion_timer_.stop();
  map_timer_.stop();
  marker_timer_.stop();
  stats_timer_.stop();
  watchdog_timer_.stop();
  diagnostics_timer_.stop();
  for (auto& input : inputs_) {
    input->subscriber.unsubscribe();
    input->tf_filter.reset();
  }
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
  std::ostringstream topics;
  for (const std::string& topic : params_.scan_topics)
    topics << ' ' << topic;
  ROS_INFO(
      "rfm: mapping in '%s' around '%s' from%s (resolution %.3f m, %d direction bins, "
      "active region %.1f m)",
      params_.fixed_frame.c_str(), params_.base_frame.c_str(), topics.str().c_str(),
      params_.mapper.grid.resolution, params_.mapper.grid.theta_bins,
      params_.mapper.active_region.active_region_radius);
}

void MapperRos::setRosInterfaces() {
  tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
  tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh_);

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
    in.filtered_pub = nh_.advertise<sensor_msgs::LaserScan>("/rfm/" + in.leaf + "/filtered", 10);
    in.labels_pub =
        nh_.advertise<reflectance_field_map::RayLabels>("/rfm/" + in.leaf + "/labels", 10);

    in.tf_filter =
        std::make_unique<ScanFilter>(in.valid, *tf_buffer_, params_.fixed_frame, queue, nh_);
    in.tf_filter->setTolerance(ros::Duration(params_.tf_tolerance));
    in.tf_filter->registerCallback(
        [this, &in](const sensor_msgs::LaserScanConstPtr& msg) { processScan(in, msg); });
    in.tf_filter->registerFailureCallback(
        [this, &in](const sensor_msgs::LaserScanConstPtr& msg,
                    tf2_ros::FilterFailureReason reason) { tfFailure(in, msg, reason); });
    in.subscriber.registerCallback(
        [this, &in](const sensor_msgs::LaserScanConstPtr& msg) { incomingScan(in, msg); });
    in.subscriber.subscribe(nh_, in.topic, std::max<uint32_t>(10, queue));
    inputs_.push_back(std::move(input));
  }

  save_service_ = private_nh_.advertiseService("save_map", &MapperRos::saveMap, this);
  load_service_ = private_nh_.advertiseService("load_map", &MapperRos::loadMap, this);
  reset_service_ = private_nh_.advertiseService("reset", &MapperRos::reset, this);

  motion_timer_ =
      nh_.createTimer(ros::Duration(1.0 / params_.mapper.motion_removal.motion_removal_rate),
                      &MapperRos::motionRemovalTimer, this);
  map_timer_ =
      nh_.createTimer(ros::Duration(1.0 / params_.map_publish_rate), &MapperRos::mapTimer, this);
  if (params_.marker_publish_rate > 0.0) {
    marker_timer_ = nh_.createTimer(ros::Duration(1.0 / params_.marker_publish_rate),
                                    &MapperRos::markerTimer, this);
  }
  stats_timer_ = nh_.createTimer(ros::Duration(1.0 / params_.stats_publish_rate),
                                 &MapperRos::statsTimer, this);
  // Wall timers keep running when simulated time stops or jumps.
  watchdog_timer_ = nh_.createWallTimer(ros::WallDuration(0.25), &MapperRos::watchdogTimer, this);

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
  // A scan older than the newest of its topic by more than the threshold: a bag restarted
  // without --clock, or a driver whose clock jumped.
  if (!input.last_stamp.isZero() &&
      msg->header.stamp + ros::Duration(params_.time_jump_threshold) < input.last_stamp) {
    std::ostringstream why;
    why << "scan on " << input.topic << " stamped "
        << (input.last_stamp - msg->header.stamp).toSec() << " s before the previous one";
    resetAfterTimeJump(why.str());
  }
  const std::string problem = toLaserScan2D(*msg).validate();
  if (problem.empty() && !msg->header.frame_id.empty()) {
    input.valid.add(msg);
    return;
  }
  ++input.malformed;
  ++malformed_scans_;
  ++scans_dropped_;
  ROS_ERROR_THROTTLE(5.0, "rfm: rejected malformed scan on %s (frame '%s'): %s",
                     input.topic.c_str(), msg->header.frame_id.c_str(),
                     problem.empty() ? "empty frame_id" : problem.c_str());
}

void MapperRos::tfFailure(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg,
                          tf2_ros::FilterFailureReason reason) {
  ++input.tf_failures;
  ++tf_failures_;
  ++scans_dropped_;
  if (reason == tf2_ros::filter_failure_reasons::Unknown) ++queue_overflows_;
  const std::string frame = normalizeFrame(msg->header.frame_id);
  // _frameExists is thread-safe (it locks the buffer).
  const bool known = !frame.empty() && tf_buffer_->_frameExists(frame);
  std::ostringstream text;
  if (!known) {
    text << "laser frame '" << frame << "' of " << input.topic
         << " is not in TF: publish a transform from '" << params_.base_frame << "' to it";
  } else {
    text << "no transform from '" << frame << "' to '" << params_.fixed_frame
         << "' at t=" << std::fixed << msg->header.stamp.toSec() << " for " << input.topic << " ("
         << failureName(reason) << ")";
  }
  {
    std::lock_guard<std::mutex> lock(counters_mutex_);
    if (!known) frames_not_in_tf_.insert(frame);
    last_tf_error_ = text.str();
  }
  ROS_WARN_THROTTLE(5.0, "rfm: dropped a scan (%llu so far): %s",
                    static_cast<unsigned long long>(tf_failures_.load()), text.str().c_str());
}

void MapperRos::processScan(ScanInput& input, const sensor_msgs::LaserScanConstPtr& msg) {
  const std::string laser_frame = normalizeFrame(msg->header.frame_id);
  geometry_msgs::TransformStamped sensor_tf, robot_tf;
  try {
    sensor_tf = tf_buffer_->lookupTransform(params_.fixed_frame, laser_frame, msg->header.stamp);
    robot_tf =
        tf_buffer_->lookupTransform(params_.fixed_frame, params_.base_frame, msg->header.stamp);
  } catch (const tf2::TransformException& e) {
    ++input.tf_failures;
    ++tf_failures_;
    ++scans_dropped_;
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
  timed.scan = toLaserScan2D(*msg, sensor.upside_down);
  timed.sensor_pose = sensor.pose;
  timed.robot_pose = toPose2D(robot_tf.transform);

  const bool want_labels =
      input.filtered_pub.getNumSubscribers() > 0 || input.labels_pub.getNumSubscribers() > 0;
  std::vector<rfm::RayLabel> labels;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    const rfm::ScanUpdate update = mapper_->addScan(timed);
    if (!update.error.empty()) {
      ++input.malformed;
      ++malformed_scans_;
      ++scans_dropped_;
      ROS_ERROR_THROTTLE(5.0, "rfm: rejected malformed scan on %s: %s", input.topic.c_str(),
                         update.error.c_str());
      return;
    }
    ++scans_since_motion_removal_;
    if (want_labels) {
      labels = mapper_->labelAddedScan(timed, update);
    }
  }
  input.last_stamp = std::max(input.last_stamp, msg->header.stamp);
  ++input.processed;
  ++scans_processed_;
  if (want_labels) {
    labels = toMessageOrder(std::move(labels), sensor.upside_down);
    if (input.filtered_pub.getNumSubscribers() > 0) {
      input.filtered_pub.publish(filterScan(*msg, labels));
    }
    if (input.labels_pub.getNumSubscribers() > 0) {
      input.labels_pub.publish(toRayLabelsMsg(msg->header, input.topic, labels));
    }
  }
}

void MapperRos::motionRemovalTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (scans_since_motion_removal_ == 0) return;
  runMotionRemovalLocked();
  publishMapUpdateLocked();
}

void MapperRos::runMotionRemovalLocked() {
  mapper_->removeMotion();
  scans_since_motion_removal_ = 0;
  map_changed_ = true;
  markers_changed_ = true;
}

void MapperRos::mapTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (map_changed_ || !map_published_) publishFullMapLocked();
}

void MapperRos::markerTimer(const ros::TimerEvent&) {
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  if (markers_changed_) publishMarkersLocked();
}

void MapperRos::publishFullMapLocked() {
  const auto start = std::chrono::steady_clock::now();
  const rfm::GlobalMap2D& map = mapper_->map();
  const rfm::CellBox box = map.bounds();
  map_pub_.publish(toOccupancyGrid(map, box, params_.mapper.grid.resolution, params_.fixed_frame,
                                   ros::Time::now()));
  // The full map carries every change so far.
  mapper_->takeMapChanges();
  published_box_ = box;
  map_published_ = true;
  map_changed_ = false;
  last_publish_ms_ = elapsedMs(start);
}

void MapperRos::publishMapUpdateLocked() {
  const rfm::GlobalMap2D& map = mapper_->map();
  const rfm::CellBox bounds = map.bounds();
  const bool same_geometry =
      map_published_ && bounds.min == published_box_.min && bounds.max == published_box_.max;
  if (!same_geometry) {
    // The map grew: subscribers need a new full grid before any update can apply.
    publishFullMapLocked();
    return;
  }
  const rfm::CellBox changed = mapper_->takeMapChanges().intersect(published_box_);
  if (changed.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  map_update_pub_.publish(
      toOccupancyGridUpdate(map, changed, published_box_, params_.fixed_frame, ros::Time::now()));
  last_publish_ms_ = elapsedMs(start);
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

void MapperRos::statsTimer(const ros::TimerEvent&) {
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
  }
  msg.header.stamp = ros::Time::now();
  msg.header.frame_id = params_.fixed_frame;
  msg.scans_processed = scans_processed_;
  msg.scans_dropped = scans_dropped_ + transport_drops_;  // rejected, without TF, or lost in queues
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
  if (jumped) {
    std::ostringstream why;
    why << "ROS time jumped back by " << back << " s";
    resetAfterTimeJump(why.str());
  }
  return jumped;
}

void MapperRos::resetAfterTimeJump(const std::string& why) {
  ++time_jumps_;
  ROS_WARN("rfm: %s (a looping bag?): clearing the TF buffer and resetting the map", why.c_str());
  tf_buffer_->clear();  // static transforms survive a clear
  for (auto& input : inputs_) {
    input->tf_filter->clear();
    input->last_stamp = ros::Time();
    input->last_seq = 0;
    if (input->rate) input->rate->clear();
  }
  std::lock_guard<std::mutex> lock(mapper_mutex_);
  resetMapperLocked();
}

void MapperRos::resetMapperLocked() {
  mapper_->reset();
  scans_since_motion_removal_ = 0;
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
  const std::string prefix = expandHome(request.path);
  std::string error;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    // Classify what arrived since the last pass so the files hold every scan so far.
    if (scans_since_motion_removal_ > 0) {
      runMotionRemovalLocked();
      publishMapUpdateLocked();
    }
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
  const std::string path = expandHome(request.path);
  std::string error;
  {
    std::lock_guard<std::mutex> lock(mapper_mutex_);
    response.success = loadMapperState(path, *mapper_, &error);
    if (response.success) {
      scans_since_motion_removal_ = 0;
      map_published_ = false;
      publishFullMapLocked();
      publishMarkersLocked();
    }
  }
  if (response.success) {
    response.message = "resumed from " + stateFilePath(path);
    ROS_INFO("rfm: %s", response.message.c_str());
  } else {
    response.message = "load_map failed: " + error;
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
  if (malformed > malformed_reported_) {
    status.summaryf(diagnostic_msgs::DiagnosticStatus::ERROR, "%llu malformed scans rejected",
                    static_cast<unsigned long long>(malformed - malformed_reported_));
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "scans well formed");
  }
  malformed_reported_ = malformed;
  for (const auto& input : inputs_) {
    std::ostringstream value;
    value << input->received << " received, " << input->processed << " processed, "
          << input->malformed << " malformed, " << input->tf_failures << " without TF, "
          << input->transport_drops << " lost in the subscriber queue";
    status.add(input->topic, value.str());
  }
  status.add("Scans dropped (total)", scans_dropped_.load());
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
  }
  const uint64_t jumps = time_jumps_;
  if (jumps > time_jumps_reported_) {
    status.summary(diagnostic_msgs::DiagnosticStatus::WARN, "ROS time jumped back: map reset");
  } else {
    status.summary(diagnostic_msgs::DiagnosticStatus::OK, "mapping");
  }
  time_jumps_reported_ = jumps;
  status.add("Scans processed", scans_processed_.load());
  status.add("Scan insertion time (ms)", stats.last_insert_ms);
  status.add("Reflection check time (ms)", stats.last_reflection_ms);
  status.add("Motion removal time (ms)", stats.last_motion_removal_ms);
  status.add("Glass cells (active region)", stats.glass_cells);
  status.add("Motion cells (active region)", stats.motion_cells);
  status.add("Field memory (bytes)", stats.field_bytes);
  status.add("Archived memory (bytes)", stats.archived_bytes);
  status.add("Time jumps (total)", jumps);
}

}  // namespace rfm::ros_glue
