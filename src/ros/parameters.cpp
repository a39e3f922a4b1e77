#include "reflectance_field_map/ros/parameters.h"

#include "reflectance_field_map/ros/conversions.h"

#include <xmlrpcpp/XmlRpcValue.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace rfm::ros_glue {
namespace {

std::string str(double value) {
  std::ostringstream out;
  out << value;
  return out.str();
}

// Allowed: [low, high], or (low, high] when low_open.
void requireRange(const std::string& name, double value, double low, double high,
                  bool low_open = false) {
  const bool ok = std::isfinite(value) && (low_open ? value > low : value >= low) && value <= high;
  if (!ok) {
    throw rfm::InvalidOption(name, str(value),
                             std::string(low_open ? "(" : "[") + str(low) + ", " + str(high) + "]");
  }
}

std::string describe(XmlRpc::XmlRpcValue& value) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeString:
      return "\"" + static_cast<std::string>(value) + "\"";
    case XmlRpc::XmlRpcValue::TypeArray:
      return "a list";
    case XmlRpc::XmlRpcValue::TypeStruct:
      return "a dictionary";
    default:
      return value.toXml();
  }
}

// A number parameter (int, double or bool in YAML). False when unset.
bool readNumber(const ros::NodeHandle& nh, const std::string& name, double& out,
                const char* expected) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return false;
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeInt:
      out = static_cast<int>(value);
      return true;
    case XmlRpc::XmlRpcValue::TypeDouble:
      out = static_cast<double>(value);
      return true;
    case XmlRpc::XmlRpcValue::TypeBoolean:
      out = static_cast<bool>(value) ? 1.0 : 0.0;
      return true;
    default:
      throw rfm::InvalidOption(name, describe(value), expected);
  }
}

void readDouble(const ros::NodeHandle& nh, const std::string& name, double& out) {
  readNumber(nh, name, out, "a number");
}

void readInt(const ros::NodeHandle& nh, const std::string& name, int& out) {
  double value = out;
  if (!readNumber(nh, name, value, "an integer")) return;
  if (!std::isfinite(value) || value != std::round(value) || std::fabs(value) > 2e9) {
    throw rfm::InvalidOption(name, str(value), "an integer");
  }
  out = static_cast<int>(value);
}

void readString(const ros::NodeHandle& nh, const std::string& name, std::string& out) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return;
  if (value.getType() != XmlRpc::XmlRpcValue::TypeString) {
    throw rfm::InvalidOption(name, describe(value), "a string");
  }
  out = static_cast<std::string>(value);
}

// A list of strings, or one string of names separated by spaces or commas.
void readTopics(const ros::NodeHandle& nh, const std::string& name, std::vector<std::string>& out) {
  XmlRpc::XmlRpcValue value;
  if (!nh.getParam(name, value)) return;
  std::vector<std::string> topics;
  if (value.getType() == XmlRpc::XmlRpcValue::TypeArray) {
    for (int i = 0; i < value.size(); ++i) {
      if (value[i].getType() != XmlRpc::XmlRpcValue::TypeString) {
        throw rfm::InvalidOption(name, describe(value[i]) + " (element " + std::to_string(i) + ")",
                                 "a list of topic names");
      }
      topics.push_back(static_cast<std::string>(value[i]));
    }
  } else if (value.getType() == XmlRpc::XmlRpcValue::TypeString) {
    std::string text = static_cast<std::string>(value);
    std::replace_if(
        text.begin(), text.end(), [](char c) { return c == ',' || c == '[' || c == ']'; }, ' ');
    std::istringstream in(text);
    for (std::string topic; in >> topic;)
      topics.push_back(topic);
  } else {
    throw rfm::InvalidOption(name, describe(value), "a list of topic names");
  }
  out = topics;
}

const std::vector<std::string>& nodeParameterNames() {
  static const std::vector<std::string> names = {
      "scan_topics",         "fixed_frame",        "base_frame",          "map_publish_rate",
      "marker_publish_rate", "stats_publish_rate", "tf_tolerance",        "tf_queue_size",
      "min_scan_rate",       "max_scan_rate",      "time_jump_threshold", "max_robot_speed",
      "max_map_extent",      "map_directory",      "diagnostic_period"};  // diagnostic_period: read
                                                                          // by diagnostic_updater
  return names;
}

}  // namespace

std::string topicLeaf(const std::string& topic) {
  std::string trimmed = topic;
  while (!trimmed.empty() && trimmed.back() == '/')
    trimmed.pop_back();
  const size_t slash = trimmed.rfind('/');
  return slash == std::string::npos ? trimmed : trimmed.substr(slash + 1);
}

void RosParameters::validate() const {
  if (scan_topics.empty()) {
    throw rfm::InvalidOption("scan_topics", "[]", "a non-empty list of topic names");
  }
  std::set<std::string> leaves;
  for (const std::string& topic : scan_topics) {
    const std::string leaf = topicLeaf(topic);
    if (leaf.empty()) {
      throw rfm::InvalidOption("scan_topics", "\"" + topic + "\"", "topic names");
    }
    if (!leaves.insert(leaf).second) {
      throw rfm::InvalidOption(
          "scan_topics", "\"" + topic + "\"",
          "topics whose last components differ (they name /rfm/<last>/filtered)");
    }
  }
  if (tf2FrameId(fixed_frame).empty()) {
    throw rfm::InvalidOption("fixed_frame", "\"" + fixed_frame + "\"", "a frame id");
  }
  if (tf2FrameId(base_frame).empty()) {
    throw rfm::InvalidOption("base_frame", "\"" + base_frame + "\"", "a frame id");
  }
  requireRange("map_publish_rate", map_publish_rate, 0.0, 100.0, true);
  requireRange("marker_publish_rate", marker_publish_rate, 0.0, 100.0);
  requireRange("stats_publish_rate", stats_publish_rate, 0.0, 100.0, true);
  requireRange("tf_tolerance", tf_tolerance, 0.0, 10.0);
  requireRange("tf_queue_size", tf_queue_size, 1, 10000);
  requireRange("min_scan_rate", min_scan_rate, 0.0, 10000.0);
  requireRange("max_scan_rate", max_scan_rate, min_scan_rate, 1e6, true);
  requireRange("time_jump_threshold", time_jump_threshold, 0.0, 3600.0);
  requireRange("max_robot_speed", max_robot_speed, 0.0, 1000.0, true);
  if (map_directory.empty()) {
    throw rfm::InvalidOption("map_directory", "\"\"", "a directory path");
  }
  mapper.validate();
  // The map must hold at least one active region around the robot (and a tile either side).
  const double region = 2.0 * (mapper.active_region.active_region_radius +
                               mapper.grid.tile_cells * mapper.grid.resolution);
  requireRange("max_map_extent", max_map_extent, region, 100000.0);
}

RosParameters readParameters(const ros::NodeHandle& private_nh) {
  RosParameters params;
  readTopics(private_nh, "scan_topics", params.scan_topics);
  readString(private_nh, "fixed_frame", params.fixed_frame);
  readString(private_nh, "base_frame", params.base_frame);
  readDouble(private_nh, "map_publish_rate", params.map_publish_rate);
  readDouble(private_nh, "marker_publish_rate", params.marker_publish_rate);
  readDouble(private_nh, "stats_publish_rate", params.stats_publish_rate);
  readDouble(private_nh, "tf_tolerance", params.tf_tolerance);
  readInt(private_nh, "tf_queue_size", params.tf_queue_size);
  readDouble(private_nh, "min_scan_rate", params.min_scan_rate);
  readDouble(private_nh, "max_scan_rate", params.max_scan_rate);
  readDouble(private_nh, "time_jump_threshold", params.time_jump_threshold);
  readDouble(private_nh, "max_robot_speed", params.max_robot_speed);
  readDouble(private_nh, "max_map_extent", params.max_map_extent);
  readString(private_nh, "map_directory", params.map_directory);

  for (const rfm::OptionField& field : rfm::optionFields()) {
    double value = rfm::getOption(params.mapper, field.name);
    switch (field.type) {
      case rfm::OptionField::Type::kDouble:
        readDouble(private_nh, field.name, value);
        break;
      case rfm::OptionField::Type::kInt: {
        int integer = static_cast<int>(value);
        readInt(private_nh, field.name, integer);
        value = integer;
        break;
      }
      case rfm::OptionField::Type::kBool:
        readNumber(private_nh, field.name, value, "true or false");
        if (value != 0.0 && value != 1.0) {
          throw rfm::InvalidOption(field.name, str(value), "true or false");
        }
        break;
    }
    rfm::setOption(params.mapper, field.name, value);
  }
  params.fixed_frame = tf2FrameId(params.fixed_frame);
  params.base_frame = tf2FrameId(params.base_frame);
  params.validate();
  return params;
}

std::vector<std::string> knownParameterNames() {
  std::vector<std::string> names = nodeParameterNames();
  for (const rfm::OptionField& field : rfm::optionFields())
    names.push_back(field.name);
  // The offline batch's tuning shares config/default.yaml: the node takes it silently.
  for (const rfm::OptionField& field : rfm::batchOptionFields())
    names.push_back(field.name);
  return names;
}

std::vector<std::string> unknownParameters(const ros::NodeHandle& private_nh) {
  std::vector<std::string> all;
  if (!private_nh.getParamNames(all)) return {};
  const std::string prefix = private_nh.getNamespace() + "/";
  const std::vector<std::string> known = knownParameterNames();
  std::vector<std::string> unknown;
  for (const std::string& name : all) {
    if (name.compare(0, prefix.size(), prefix) != 0) continue;
    const std::string relative = name.substr(prefix.size());
    const std::string top = relative.substr(0, relative.find('/'));
    if (std::find(known.begin(), known.end(), top) == known.end()) unknown.push_back(relative);
  }
  return unknown;
}

}  // namespace rfm::ros_glue
