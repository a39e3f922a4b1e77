#include "reflectance_field_map/offline/bag_input.h"

#include "reflectance_field_map/core/pose_gate.h"
#include "reflectance_field_map/offline/bag_messages.h"
#include "reflectance_field_map/offline/bag_structure.h"
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
#include <fstream>
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

// Tallies skips by reason; `topics` sizes each new tally.
class SkipCounter {
 public:
  explicit SkipCounter(size_t topics) : topics_(topics) {}
  void add(const std::string& reason, uint32_t topic, const std::string& what) {
    SkipTally& tally = tallyFor(reason);
    if (tally.per_topic[topic]++ == 0) tally.first[topic] = what;
    ++tally.total;
  }
  // Adds a later stretch's skips (its first ones come after this one's).
  void merge(const std::map<std::string, SkipTally>& later) {
    for (const auto& [reason, theirs] : later) {
      SkipTally& mine = tallyFor(reason);
      for (size_t t = 0; t < topics_; ++t) {
        if (mine.per_topic[t] == 0) mine.first[t] = theirs.first[t];
        mine.per_topic[t] += theirs.per_topic[t];
      }
      mine.total += theirs.total;
    }
  }
  std::map<std::string, SkipTally>& tallies() { return tallies_; }

 private:
  SkipTally& tallyFor(const std::string& reason) {
    SkipTally& tally = tallies_[reason];
    if (tally.per_topic.empty()) {
      tally.per_topic.assign(topics_, 0);
      tally.first.assign(topics_, std::string());
    }
    return tally;
  }

  size_t topics_;
  std::map<std::string, SkipTally> tallies_;
};

// What a reason's scans are, after "N of M scans ".
std::string reasonText(const std::string& reason) {
  if (reason == "oversized") return "are larger than any LaserScan this tool takes";
  if (reason == "undecodable") return "hold bytes that are not a LaserScan (corrupt)";
  if (reason == "malformed") return "are malformed";
  if (reason == "no_transform") return "have no transform into the fixed frame at their stamp";
  if (reason == "pose_jump") return "were taken at a pose jump faster than --max-speed";
  return reason;
}

// A damaged bag still starts with rosbag's version line.
bool looksLikeBag(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char start[8] = {};
  return in.read(start, sizeof(start)) && std::string(start, sizeof(start)) == "#ROSBAG ";
}

// A recording cut short loses its index, which rosbag needs to read any of it.
std::string recoveryHint(const std::string& bag) {
  return "\nIf the recording was cut short (a full disk, a crash), rebuild its index with "
         "`rosbag reindex " +
         bag + "` (it keeps the original as " + std::filesystem::path(bag).stem().string() +
         ".orig.bag) and run again: every message before the cut is then read.";
}

std::string stampText(const ros::Time& stamp) {
  std::ostringstream out;
  out.setf(std::ios::fixed);
  out.precision(3);
  out << stamp.toSec();
  return out.str();
}

// What one reader takes from its stretch of the recording, in bag order.
struct BagStretch {
  explicit BagStretch(size_t topics) : read_per_topic(topics, 0), skips(topics) {}
  std::vector<std::pair<geometry_msgs::TransformStamped, bool>> transforms;  // and whether static
  uint64_t tf_messages = 0;
  uint64_t tf_refused = 0;  // TF messages too large or corrupt
  std::vector<TimedScan> scans;
  std::vector<ScanSource> sources;
  std::vector<uint64_t> read_per_topic;
  SkipCounter skips;
  bool zero_stamps = false;
};

void readTf(const rosbag::MessageInstance& message, BagStretch& out) {
  if (!message.isType<tf2_msgs::TFMessage>()) return;
  tf2_msgs::TFMessage tf_message;
  std::string why;
  if (decodeTfMessage(message, tf_message, why) != DecodeResult::kOk) {
    ++out.tf_refused;
    return;
  }
  const bool is_static = message.getTopic() == "/tf_static";
  for (geometry_msgs::TransformStamped& transform : tf_message.transforms) {
    transform.header.frame_id = ros_glue::tf2FrameId(transform.header.frame_id);
    transform.child_frame_id = ros_glue::tf2FrameId(transform.child_frame_id);
    out.transforms.emplace_back(std::move(transform), is_static);
  }
  ++out.tf_messages;
}

void readScan(const rosbag::MessageInstance& message, uint32_t topic, BagStretch& out) {
  if (!message.isType<sensor_msgs::LaserScan>()) return;
  ++out.read_per_topic[topic];
  const std::string when = "bag time " + stampText(message.getTime()) + ": ";
  sensor_msgs::LaserScan msg;
  std::string why;
  const DecodeResult decoded = decodeLaserScan(message, msg, why);
  if (decoded != DecodeResult::kOk) {
    out.skips.add(decoded == DecodeResult::kOversized ? "oversized" : "undecodable", topic,
                  when + why);
    return;
  }
  ScanSource source;
  source.topic_index = topic;
  source.seq = msg.header.seq;
  source.stamp = msg.header.stamp;
  source.bag_time = message.getTime();
  source.frame_id = ros_glue::tf2FrameId(msg.header.frame_id);
  if (source.stamp.isZero()) {
    source.stamp = source.bag_time;  // unstamped driver: the recording time is all we have
    out.zero_stamps = true;
  }
  TimedScan scan;
  scan.sensor_id = topic;
  scan.stamp = source.stamp.toSec();
  scan.scan = ros_glue::toLaserScan2D(msg);
  source.reversed = ros_glue::isClockwise(msg);
  source.sweep_end =
      source.stamp + ros::Duration(sweepSeconds(msg.time_increment, msg.ranges.size()));
  std::string problem = scan.scan.validate();
  if (problem.empty() && source.frame_id.empty()) problem = "the scan has an empty frame_id";
  if (!problem.empty()) {
    out.skips.add("malformed", topic, "t=" + stampText(source.stamp) + ": " + problem);
    return;
  }
  out.scans.push_back(std::move(scan));
  out.sources.push_back(std::move(source));
}

// Reads a view of scan and TF messages; `counted` is called after each message.
void readStretch(rosbag::View& view, const std::map<std::string, uint32_t>& topic_index,
                 BagStretch& out, const std::function<void()>& counted) {
  for (const rosbag::MessageInstance& message : view) {
    const auto scan_topic = topic_index.find(message.getTopic());
    if (scan_topic == topic_index.end()) {
      readTf(message, out);
    } else {
      readScan(message, scan_topic->second, out);
    }
    counted();
  }
}

}  // namespace

std::vector<std::string> splitTopicList(const std::string& list) {
  std::vector<std::string> topics;
  std::istringstream in(list);
  for (std::string topic; std::getline(in, topic, ',');) {
    if (!topic.empty()) topics.push_back(topic);
  }
  return topics;
}

uint64_t BagScans::scansRead() const {
  return std::accumulate(read_per_topic.begin(), read_per_topic.end(), uint64_t{0});
}

uint64_t BagScans::scansSkipped() const {
  uint64_t total = 0;
  for (const auto& entry : skipped)
    total += entry.second.total;
  return total;
}

std::vector<std::string> BagScans::describeSkips() const {
  std::vector<std::string> lines;
  for (const auto& [reason, tally] : skipped) {
    std::ostringstream line;
    line << tally.total << " of " << scansRead() << " scans " << reasonText(reason) << " ("
         << reason << "):";
    std::string first;
    for (size_t t = 0; t < topics.size(); ++t) {
      if (tally.per_topic[t] == 0) continue;
      line << ' ' << topics[t] << ": " << tally.per_topic[t] << " of " << read_per_topic[t] << ";";
      if (first.empty()) first = tally.first[t];
    }
    line << " e.g. " << first;
    lines.push_back(line.str());
  }
  return lines;
}

BagScans readBagScans(const BagInputOptions& options,
                      const std::function<void(size_t, size_t)>& progress) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(options.bag, ec)) {
    throw BagInputError("cannot read bag " + options.bag + ": no such file");
  }
  const std::string hint = looksLikeBag(options.bag) ? recoveryHint(options.bag) : std::string();
  // rosbag allocates and parses at the lengths the file claims: a bag it cannot take safely is
  // refused before it opens it.
  const std::string structure_problem = checkBagStructure(options.bag);
  if (!structure_problem.empty()) {
    throw BagInputError("cannot read bag " + options.bag + ": " + structure_problem + hint);
  }
  rosbag::Bag bag;
  try {
    bag.open(options.bag, rosbag::bagmode::Read);
  } catch (const rosbag::BagException& e) {
    throw BagInputError("cannot read bag " + options.bag + ": " + e.what() + hint);
  }

  BagScans result;
  const std::string fixed_frame = ros_glue::tf2FrameId(options.fixed_frame);
  const std::string base_frame = ros_glue::tf2FrameId(options.base_frame);

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
    throw BagInputError("cannot read bag " + options.bag + ": " + e.what() + hint);
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
  result.read_per_topic.assign(result.topics.size(), 0);

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
    throw BagInputError("cannot read " + options.bag + ": " + e.what() + hint);
  }

  std::vector<TimedScan> scans;
  std::vector<ScanSource> sources;
  SkipCounter skips(result.topics.size());
  bool zero_stamps = false;
  uint64_t tf_refused = 0;
  for (BagStretch& stretch : stretches) {
    for (const auto& [transform, is_static] : stretch.transforms)
      tf.setTransform(transform, "rosbag", is_static);
    result.tf_messages += stretch.tf_messages;
    tf_refused += stretch.tf_refused;
    for (size_t t = 0; t < result.topics.size(); ++t)
      result.read_per_topic[t] += stretch.read_per_topic[t];
    skips.merge(stretch.skips.tallies());
    zero_stamps |= stretch.zero_stamps;
    std::move(stretch.scans.begin(), stretch.scans.end(), std::back_inserter(scans));
    std::move(stretch.sources.begin(), stretch.sources.end(), std::back_inserter(sources));
  }
  if (zero_stamps) result.notes.push_back("scans with a zero header stamp use their bag time");
  if (tf_refused > 0) {
    result.notes.push_back(std::to_string(tf_refused) +
                           " TF messages are too large or corrupt: left out");
  }

  // Chronological order for the mapper (topics interleave by recording time otherwise).
  std::vector<size_t> order(scans.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&sources](size_t a, size_t b) { return sources[a].stamp < sources[b].stamp; });

  // Poses at each scan's stamp.
  const bool bag_has_tf = result.tf_messages > 0;
  std::string frame_without_tf;
  uint64_t upside_down = 0;
  uint64_t swept = 0;  // scans whose sensor motion during the sweep was compensated
  PoseGate gate(options.max_speed, kPoseJumpSlack);
  result.scans.reserve(scans.size());
  result.sources.reserve(scans.size());
  for (size_t i : order) {
    TimedScan& scan = scans[i];
    ScanSource& source = sources[i];
    const std::string& frame = source.frame_id;
    try {
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
        swept += ros_glue::compensateSweepFromTf(tf, fixed_frame, frame, source.stamp,
                                                 source.sweep_end, source.reversed, scan);
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
      skips.add("no_transform", source.topic_index,
                "t=" + stampText(source.stamp) + ": " + e.what());
      continue;
    }
    if (!gate.accept(scan.stamp, scan.robot_pose.position)) {
      std::ostringstream what;
      what << "t=" << stampText(source.stamp) << ": the robot at (" << scan.robot_pose.position.x()
           << ", " << scan.robot_pose.position.y() << "), " << gate.lastRejectedJump()
           << " m from its last mapped pose";
      skips.add("pose_jump", source.topic_index, what.str());
      continue;
    }
    ++result.scans_per_topic[source.topic_index];
    result.scans.push_back(std::move(scan));
    result.sources.push_back(std::move(source));
  }
  result.skipped = std::move(skips.tallies());
  if (result.scans.empty()) {
    std::string message = "no scan of " + options.bag + " can be mapped:";
    for (const std::string& line : result.describeSkips())
      message += "\n  " + line;
    if (!bag_has_tf && !frame_without_tf.empty()) {
      message += "\nThe bag has no /tf or /tf_static, so scans in frame '" + frame_without_tf +
                 "' can't be placed in the fixed frame '" + fixed_frame +
                 "'. For a sensor that does not move, pass --fixed-frame " + frame_without_tf +
                 " (the scan frame): its poses are then the identity.";
    } else if (result.skipped.count("no_transform") > 0) {
      message += "\nCheck --fixed-frame and --base-frame ('" + fixed_frame + "', '" + base_frame +
                 "'). Frames in the bag's TF:\n" + tf.allFramesAsString();
    }
    throw BagInputError(message);
  }
  if (upside_down > 0) {
    result.notes.push_back(std::to_string(upside_down) +
                           " scans come from a laser mounted upside down: mirrored");
  }
  if (swept > 0) {
    result.notes.push_back(
        std::to_string(swept) +
        " scans turned as the sensor turned during their sweep (time_increment)");
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
