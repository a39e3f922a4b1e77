// A CARMEN log as rfm_carmen2bag reads it: rfm::tools::readCarmenLog over the fuzzer's bytes as
// text (each line through parseCarmenLine), which counts and reports malformed lines and never
// throws.
#include "reflectance_field_map/tools/carmen_log.h"

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const rfm::tools::CarmenLog log = rfm::tools::readCarmenLog(in);
  // Malformed lines are counted, and the first few reported.
  if (log.errors.size() > rfm::tools::CarmenLog::kMaxReportedErrors ||
      log.errors.size() > log.malformed_lines) {
    __builtin_trap();
  }
  return 0;
}
