#include "reflectance_field_map/offline/bag_input.h"

#include "reflectance_field_map/ros/conversions.h"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>
#include <rosbag/view.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_msgs/TFMessage.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <iterator>
#include <map>
#include <numeric>
#include <sstream>
#include <thread>
#include <utility>

namespace rfm {
namespace offline {
namespace {

constexpr const char* kLaserScanType = "sensor_msgs/LaserScan";

std::string joinList(const std::vector<std::string>& items) {
  std::string text;
  for (const std::string& item : items)
    text += (text.empty() ? "" : ", ") + item;
  return text.empty() ? "(none)" : text;
}

// Per-topic tally of scans that could not be used, with the first reason.
struct Failures {
  std::vector<uint64_t> count;
  std::vector<std::string> first;
  uint64_t total = 0;

  explicit Failures(size_t topics) : count(topics, 0), first(topics) {}
  void add(uint32_t topic, const std::string& reason) {
    if (count[topic]++ == 0) first[topic] = reason;
    ++total;
  }
  // Adds a later stretch's failures (its first reasons come after this one's).
  void merge(const Failures& later) {
    for (size_t t = 0; t < count.size(); ++t) {
      if (count[t] == 0) first[t] = later.first[t];
      count[t] += later.count[t];
    }
    total += later.total;
  }
  std::string describe(const BagScans& scans) const {
    std::ostringstream out;
    for (size_t t = 0; t < count.size(); ++t) {
      if (count[t] == 0) continue;
      out << "\n  " << scans.topics[t] << ": " << count[t] << " of " << scans.scans_per_topic[t]
          << " scans, first: " << first[t];
    }
    return out.str();
  }
};

std::string stampText(const ros::Time& stamp) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << stamp.toSec();
  return out.str();
}

// What one reader takes from its stretch of the recording, in bag order.
struct BagStretch {
  explicit BagStretch(size_t topics) : scans_per_topic(topics, 0), malformed(topics) {}
  std::vector<std::pair<geometry_msgs::TransformStamped, bool>> transforms;  // and whether static
  uint64_t tf_messages = 0;
  std::vector<TimedScan> scans;
  std::vector<ScanSource> sources;
  std::vector<uint64_t> scans_per_topic;
  Failures malformed;
  bool zero_stamps = false;
};

// Reads a view of scan and TF messages; `counted` is called after each message.
void readStretch(rosbag::View& view, const std::map<std::string, uint32_t>& topic_index,
                 BagStretch& out, const std::function<void()>& counted) {
  for (const rosbag::MessageInstance& message : view) {
    const std::string& topic = message.getTopic();
    const auto scan_topic = topic_index.find(topic);
    if (scan_topic == topic_index.end()) {
      const tf2_msgs::TFMessage::ConstPtr tf_message = message.instantiate<tf2_msgs::TFMessage>();
      if (tf_message) {
        const bool is_static = topic == "/tf_static";
        for (geometry_msgs::TransformStamped transform : tf_message->transforms) {
          transform.header.frame_id = normalizedFrame(transform.header.frame_id);
          transform.child_frame_id = normalizedFrame(transform.child_frame_id);
          out.transforms.emplace_back(std::move(transform), is_static);
        }
        ++out.tf_messages;
      }
      counted();
      continue;
    }
    const sensor_msgs::LaserScan::ConstPtr msg = message.instantiate<sensor_msgs::LaserScan>();
    if (!msg) {
      counted();
      continue;
    }
    ScanSource source;
    source.topic_index = scan_topic->second;
    source.seq = msg->header.seq;
    source.stamp = msg->header.stamp;
    source.bag_time = message.getTime();
    source.frame_id = normalizedFrame(msg->header.frame_id);
    if (source.stamp.isZero()) {
      source.stamp = source.bag_time;  // unstamped driver: the recording time is all we have
      out.zero_stamps = true;
    }
    TimedScan scan;
    scan.sensor_id = source.topic_index;
    scan.stamp = source.stamp.toSec();
    scan.scan = ros_glue::toLaserScan2D(*msg);
    // The node rejects these; a recording is taken as it is (none of its scans dropped).
    source.reversed = scan.scan.angle_increment < 0.0f && !scan.scan.ranges.empty();
    if (source.reversed) reverseBeamOrder(scan.scan);
    const std::string problem = scan.scan.validate();
    if (!problem.empty())
      out.malformed.add(source.topic_index, "t=" + stampText(source.stamp) + ": " + problem);
    ++out.scans_per_topic[source.topic_index];
    out.scans.push_back(std::move(scan));
    out.sources.push_back(std::move(source));
    counted();
  }
}

}  // namespace

std::string normalizedFrame(const std::string& frame) {
  size_t start = 0;
  while (start < frame.size() && frame[start] == '/')
    ++start;
  return frame.substr(start);
}

BagScans readBagScans(const BagInputOptions& options,
                      const std::function<void(size_t, size_t)>& progress) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(options.bag, ec)) {
    throw BagInputError("cannot read bag " + options.bag + ": no such file");
  }
  rosbag::Bag bag;
  try {
    bag.open(options.bag, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw BagInputError("cannot read bag " + options.bag + ": " + e.what());
  }

  BagScans result;
  const std::string fixed_frame = normalizedFrame(options.fixed_frame);
  const std::string base_frame = normalizedFrame(options.base_frame);

  // Topics in the bag.
  std::map<std::string, std::string> types;
  ros::Time bag_begin, bag_end;
  try {
    rosbag::View all(bag);
    for (const rosbag::ConnectionInfo* connection : all.getConnections()) {
      types[connection->topic] = connection->datatype;
    }
    if (all.size() > 0) {
      bag_begin = all.getBeginTime();
      bag_end = all.getEndTime();
    }
  } catch (const rosbag::BagException& e) {
    throw BagInputError("cannot read bag " + options.bag + ": " + e.what());
  }

  std::vector<std::string> laser_topics;
  for (const auto& [topic, type] : types) {
    if (type == kLaserScanType) laser_topics.push_back(topic);
  }
  for (const std::string& requested : options.scan_topics) {
    const std::string topic = requested.front() == '/' ? requested : "/" + requested;
    const auto found = types.find(topic);
    if (found == types.end()) {
      result.missing_topics.push_back(topic);
      continue;
    }
    if (found->second != kLaserScanType) {
      throw BagInputError("topic " + topic + " in " + options.bag + " is a " + found->second +
                          ", not a " + kLaserScanType +
                          "; LaserScan topics in the bag: " + joinList(laser_topics));
    }
    if (std::find(result.topics.begin(), result.topics.end(), topic) == result.topics.end()) {
      result.topics.push_back(topic);
    }
  }
  if (result.topics.empty()) {
    throw BagInputError("none of the scan topics " + joinList(options.scan_topics) + " is in " +
                        options.bag + "; its LaserScan topics: " + joinList(laser_topics) +
                        " (choose with --scan-topics /a,/b)");
  }
  if (options.require_all_topics && !result.missing_topics.empty()) {
    throw BagInputError("scan topics not in " + options.bag + ": " +
                        joinList(result.missing_topics) +
                        "; its LaserScan topics: " + joinList(laser_topics));
  }
  result.scans_per_topic.assign(result.topics.size(), 0);

  // TF: the whole bag's /tf and /tf_static in one buffer whose cache spans the recording.
  const double span = bag_end > bag_begin ? (bag_end - bag_begin).toSec() : 0.0;
  tf2::BufferCore tf(ros::Duration(span + 60.0));
  std::vector<std::string> read_topics = result.topics;
  for (const char* topic : {"/tf", "/tf_static"}) {
    if (types.count(topic)) read_topics.push_back(topic);
  }

  // TF and scans in one view: the topics share the bag's chunks, so a view per kind would
  // decompress every chunk twice. Two threads read the two halves of the recording, each with
  // its own handle on the bag; their stretches are joined in bag order.
  std::map<std::string, uint32_t> topic_index;
  for (size_t t = 0; t < result.topics.size(); ++t) {
    topic_index[result.topics[t]] = static_cast<uint32_t>(t);
  }
  std::vector<BagStretch> stretches;
  try {
    const rosbag::TopicQuery query(read_topics);
    const size_t total = rosbag::View(bag, query).size();
    std::atomic<size_t> done{0};
    const bool split = bag_end - bag_begin > ros::Duration(1.0);
    const ros::Time middle = bag_begin + (bag_end - bag_begin) * 0.5;
    stretches.resize(split ? 2 : 1, BagStretch(result.topics.size()));
    std::exception_ptr second_error;
    std::thread second;
    if (split) {
      second = std::thread([&] {
        try {
          rosbag::Bag own;
          own.open(options.bag, rosbag::bagmode::Read);
          rosbag::View view(own, query, middle + ros::Duration(0, 1), bag_end);
          readStretch(view, topic_index, stretches[1], [&done] { ++done; });
        } catch (...) {
          second_error = std::current_exception();
        }
      });
    }
    // This thread alone reports progress: the bar is not shared.
    try {
      rosbag::View view(bag, query, split ? bag_begin : ros::TIME_MIN,
                        split ? middle : ros::TIME_MAX);
      readStretch(view, topic_index, stretches[0], [&] {
        if (progress) progress(std::min(++done, total), total);
      });
    } catch (...) {
      if (second.joinable()) second.join();
      throw;
    }
    if (second.joinable()) second.join();
    if (second_error) std::rethrow_exception(second_error);
    if (progress) progress(total, total);
  } catch (const rosbag::BagException& e) {
    throw BagInputError("cannot read " + options.bag + ": " + e.what());
  }

  std::vector<TimedScan> scans;
  std::vector<ScanSource> sources;
  Failures malformed(result.topics.size());
  bool zero_stamps = false;
  for (BagStretch& stretch : stretches) {
    for (const auto& [transform, is_static] : stretch.transforms)
      tf.setTransform(transform, "rosbag", is_static);
    result.tf_messages += stretch.tf_messages;
    for (size_t t = 0; t < result.topics.size(); ++t)
      result.scans_per_topic[t] += stretch.scans_per_topic[t];
    malformed.merge(stretch.malformed);
    zero_stamps |= stretch.zero_stamps;
    std::move(stretch.scans.begin(), stretch.scans.end(), std::back_inserter(scans));
    std::move(stretch.sources.begin(), stretch.sources.end(), std::back_inserter(sources));
  }
  if (zero_stamps) result.notes.push_back("scans with a zero header stamp use their bag time");
  if (malformed.total > 0) {
    throw BagInputError(std::to_string(malformed.total) + " of " + std::to_string(scans.size()) +
                        " scans are malformed:" + malformed.describe(result));
  }

  // Chronological order for the mapper (topics interleave by recording time otherwise).
  std::vector<size_t> order(scans.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&sources](size_t a, size_t b) { return sources[a].stamp < sources[b].stamp; });

  // Poses at each scan's stamp.
  const bool bag_has_tf = result.tf_messages > 0;
  Failures no_tf(result.topics.size());
  std::string frame_without_tf;
  uint64_t upside_down = 0;
  result.scans.reserve(scans.size());
  result.sources.reserve(scans.size());
  for (size_t i : order) {
    TimedScan& scan = scans[i];
    ScanSource& source = sources[i];
    const std::string& frame = source.frame_id;
    try {
      if (frame.empty()) throw tf2::InvalidArgumentException("the scan has an empty frame_id");
      if (frame == fixed_frame) {
        scan.sensor_pose = Pose2D();
      } else if (!bag_has_tf) {
        frame_without_tf = frame;
        throw tf2::LookupException("no TF in the bag");
      } else {
        const geometry_msgs::TransformStamped laser =
            tf.lookupTransform(fixed_frame, frame, source.stamp);
        const ros_glue::PlanarSensorPose sensor = ros_glue::toPlanarSensorPose(laser.transform);
        scan.sensor_pose = sensor.pose;
        if (sensor.upside_down) {
          mirrorScan(scan.scan);
          source.reversed = !source.reversed;
          ++upside_down;
        }
      }
      if (base_frame == fixed_frame) {
        scan.robot_pose = Pose2D();
      } else if (!bag_has_tf) {
        scan.robot_pose = scan.sensor_pose;  // stationary sensor: it is the centre
      } else {
        scan.robot_pose =
            ros_glue::toPose2D(tf.lookupTransform(fixed_frame, base_frame, source.stamp).transform);
      }
    } catch (const tf2::TransformException& e) {
      no_tf.add(source.topic_index, "t=" + stampText(source.stamp) + ": " + e.what());
    }
    result.scans.push_back(std::move(scan));
    result.sources.push_back(std::move(source));
  }
  if (!bag_has_tf && !frame_without_tf.empty()) {
    throw BagInputError("the bag has no /tf or /tf_static, so scans in frame '" + frame_without_tf +
                        "' can't be placed in the fixed frame '" + fixed_frame +
                        "'. For a sensor that does not move, pass --fixed-frame " +
                        frame_without_tf + " (the scan frame): its poses are then the identity.");
  }
  if (no_tf.total > 0) {
    throw BagInputError(std::to_string(no_tf.total) + " of " + std::to_string(result.scans.size()) +
                        " scans have no transform from their frame or from '" + base_frame +
                        "' into '" + fixed_frame + "' at their stamp:" + no_tf.describe(result) +
                        "\nCheck --fixed-frame and --base-frame. Frames in the bag's TF:\n" +
                        tf.allFramesAsString());
  }
  if (upside_down > 0) {
    result.notes.push_back(std::to_string(upside_down) +
                           " scans come from a laser mounted upside down: mirrored");
  }
  if (!bag_has_tf && base_frame != fixed_frame) {
    result.notes.push_back("no TF in the bag: the base pose is the scan pose");
  }
  if (!result.scans.empty()) {
    result.duration = result.scans.back().stamp - result.scans.front().stamp;
  }
  return result;
}

}  // namespace offline
}  // namespace rfm
