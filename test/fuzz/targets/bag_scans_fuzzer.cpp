// A recording as rfm_offline reads it: the fuzzer's bytes written as a bag file and read by
// rfm::offline::readBagScans (rosbag, the scans of /scan_front and /scan_rear, their TF). A bag
// it cannot use must end in an error that rfm_offline reports (a BagInputError, or another
// std::exception), never a crash, a hang or an exhausted memory: readBagScans refuses a bag
// whose lengths rosbag would trust (checkBagStructure) before rosbag opens it.
#include "reflectance_field_map/offline/bag_input.h"

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <fstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  // In memory where there is a /dev/shm; one file per process (libFuzzer forks with -jobs).
  static const std::string path =
      (access("/dev/shm", W_OK) == 0 ? std::string("/dev/shm") : std::string("/tmp")) +
      "/rfm_bag_fuzz_" + std::to_string(getpid()) + ".bag";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), static_cast<std::streamsize>(size));
  }
  rfm::offline::BagInputOptions options;
  options.bag = path;
  options.scan_topics = {"/scan_front", "/scan_rear"};
  try {
    rfm::offline::readBagScans(options);
  } catch (const rfm::offline::BagInputError&) {
  } catch (const std::exception&) {
    // As rfm_offline (offline_tool.cpp) takes any other error: reported, the run ended cleanly.
    // rosbag's deserialisation throws ros::serialization::StreamOverrunException for a message
    // shorter than its arrays claim.
  }
  std::remove(path.c_str());
  return 0;
}
