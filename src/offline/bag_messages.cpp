#include "reflectance_field_map/offline/bag_messages.h"

#include <ros/serialization.h>

#include <exception>
#include <vector>

namespace rfm {
namespace offline {
namespace {

// Walks serialised bytes, checking that each field lies within them.
class LayoutWalker {
 public:
  LayoutWalker(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  bool skip(uint64_t bytes, const char* field) {
    if (bytes > size_ - at_) return failAt(field, bytes);
    at_ += static_cast<size_t>(bytes);
    return true;
  }
  // A uint32 length prefix, then `length * element_bytes` bytes, at most `max_length` of them.
  bool array(uint64_t element_bytes, uint64_t max_length, const char* field) {
    uint32_t length = 0;
    if (!readU32(length, field)) return false;
    if (length > max_length) {
      why_ = std::string(field) + " claims " + std::to_string(length) + " elements, more than " +
             std::to_string(max_length);
      return false;
    }
    return skip(length * element_bytes, field);
  }
  // An array of elements whose own layout `element` walks.
  template <typename Element>
  bool arrayOf(uint64_t min_element_bytes, const char* field, Element&& element) {
    uint32_t length = 0;
    if (!readU32(length, field)) return false;
    // Each element takes at least min_element_bytes: a count beyond what remains is a lie.
    if (length * min_element_bytes > size_ - at_) return failAt(field, length * min_element_bytes);
    for (uint32_t i = 0; i < length; ++i) {
      if (!element(*this)) return false;
    }
    return true;
  }
  bool header() { return skip(4 + 8, "header") && array(1, kMaxFrameIdBytes, "header.frame_id"); }
  bool atEnd(const char* type) {
    if (at_ == size_) return true;
    why_ = std::to_string(size_ - at_) + " bytes after the end of the " + type;
    return false;
  }
  const std::string& why() const { return why_; }

 private:
  bool readU32(uint32_t& value, const char* field) {
    if (size_ - at_ < 4) return failAt(field, 4);
    value = static_cast<uint32_t>(data_[at_]) | static_cast<uint32_t>(data_[at_ + 1]) << 8 |
            static_cast<uint32_t>(data_[at_ + 2]) << 16 |
            static_cast<uint32_t>(data_[at_ + 3]) << 24;
    at_ += 4;
    return true;
  }
  bool failAt(const char* field, uint64_t bytes) {
    why_ = std::string(field) + " needs " + std::to_string(bytes) + " bytes at byte " +
           std::to_string(at_) + " of " + std::to_string(size_);
    return false;
  }

  const uint8_t* data_;
  size_t size_;
  size_t at_ = 0;
  std::string why_;
};

// The message's bytes, if it is no larger than `max_bytes`.
DecodeResult readBytes(const rosbag::MessageInstance& message, uint64_t max_bytes,
                       std::vector<uint8_t>& bytes, std::string& why) {
  const uint32_t size = message.size();
  if (size > max_bytes) {
    why = std::to_string(size) + " bytes, more than the " + std::to_string(max_bytes) +
          " its type can need";
    return DecodeResult::kOversized;
  }
  bytes.resize(size);
  try {
    ros::serialization::OStream stream(bytes.data(), size);
    message.write(stream);
  } catch (const std::exception& e) {
    why = std::string("unreadable: ") + e.what();
    return DecodeResult::kUndecodable;
  }
  return DecodeResult::kOk;
}

template <typename Message>
DecodeResult decode(const std::vector<uint8_t>& bytes, Message& out, std::string& why) {
  try {
    // Every length was checked against the bytes: deserialising allocates no more than they hold.
    ros::serialization::IStream stream(const_cast<uint8_t*>(bytes.data()),
                                       static_cast<uint32_t>(bytes.size()));
    ros::serialization::deserialize(stream, out);
  } catch (const std::exception& e) {
    why = e.what();
    return DecodeResult::kUndecodable;
  }
  return DecodeResult::kOk;
}

}  // namespace

bool laserScanLayoutFits(const uint8_t* data, size_t size, std::string& why) {
  LayoutWalker walk(data, size);
  const bool fits = walk.header() && walk.skip(7 * 4, "angles, times and range limits") &&
                    walk.array(4, kMaxBeams, "ranges") && walk.array(4, kMaxBeams, "intensities") &&
                    walk.atEnd("LaserScan");
  if (!fits) why = walk.why();
  return fits;
}

bool tfMessageLayoutFits(const uint8_t* data, size_t size, std::string& why) {
  LayoutWalker walk(data, size);
  // A TransformStamped: header, child_frame_id, translation and rotation (7 float64).
  constexpr uint64_t kMinTransformBytes = 4 + 8 + 4 + 4 + 7 * 8;
  const bool fits = walk.arrayOf(kMinTransformBytes, "transforms", [](LayoutWalker& element) {
    return element.header() && element.array(1, kMaxFrameIdBytes, "child_frame_id") &&
           element.skip(7 * 8, "transform");
  }) && walk.atEnd("TFMessage");
  if (!fits) why = walk.why();
  return fits;
}

DecodeResult decodeLaserScan(const rosbag::MessageInstance& message, sensor_msgs::LaserScan& out,
                             std::string& why) {
  std::vector<uint8_t> bytes;
  const DecodeResult read = readBytes(message, kMaxScanMessageBytes, bytes, why);
  if (read != DecodeResult::kOk) return read;
  if (!laserScanLayoutFits(bytes.data(), bytes.size(), why)) return DecodeResult::kUndecodable;
  return decode(bytes, out, why);
}

DecodeResult decodeTfMessage(const rosbag::MessageInstance& message, tf2_msgs::TFMessage& out,
                             std::string& why) {
  std::vector<uint8_t> bytes;
  const DecodeResult read = readBytes(message, kMaxTfMessageBytes, bytes, why);
  if (read != DecodeResult::kOk) return read;
  if (!tfMessageLayoutFits(bytes.data(), bytes.size(), why)) return DecodeResult::kUndecodable;
  return decode(bytes, out, why);
}

}  // namespace offline
}  // namespace rfm
