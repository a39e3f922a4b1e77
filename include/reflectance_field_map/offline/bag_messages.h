#pragma once

#include <rosbag/message_instance.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <cstddef>
#include <cstdint>
#include <string>

namespace rfm {
namespace offline {

// Messages of a recording that may be corrupt, decoded without trusting any length in them:
// the message's size is checked before its bytes are read, and every array and string length
// inside is checked against the bytes that remain before anything is allocated for it (roscpp's
// own deserialiser resizes to whatever length it reads first).

// The largest scan taken: kMaxBeams ranges and as many intensities, and a header of up to
// kMaxFrameIdBytes of frame_id.
constexpr uint32_t kMaxBeams = 1u << 20;
constexpr uint32_t kMaxFrameIdBytes = 4096;
constexpr uint64_t kMaxScanMessageBytes =
    4 + 8 + 4 + kMaxFrameIdBytes + 7 * 4 + 2 * (4 + 4ull * kMaxBeams);
// The largest TF message taken (a robot's tree many times over).
constexpr uint64_t kMaxTfMessageBytes = 16ull << 20;

enum class DecodeResult {
  kOk,
  kOversized,    // larger than any message of its type this tool takes
  kUndecodable,  // its bytes do not hold a message of its type (lengths beyond its end)
};

// Whether `size` bytes hold a serialised sensor_msgs/LaserScan (or tf2_msgs/TFMessage) whose
// every length lies within them; `why` says where not.
bool laserScanLayoutFits(const uint8_t* data, size_t size, std::string& why);
bool tfMessageLayoutFits(const uint8_t* data, size_t size, std::string& why);

// Reads a bag message into `out`, refusing it (with `why`) before allocating from its lengths.
DecodeResult decodeLaserScan(const rosbag::MessageInstance& message, sensor_msgs::LaserScan& out,
                             std::string& why);
DecodeResult decodeTfMessage(const rosbag::MessageInstance& message, tf2_msgs::TFMessage& out,
                             std::string& why);

}  // namespace offline
}  // namespace rfm
