// rfm_carmen2bag: a CARMEN log (plain or gzip) to a ROS bag of scans, TF and odometry.

#include "carmen_bag_writer.h"
#include "reflectance_field_map/tools/carmen_conversion.h"
#include "reflectance_field_map/tools/carmen_log.h"
#include "reflectance_field_map/tools/compressed_text.h"

#include <ros/time.h>

#include <cmath>
#include <cstdlib>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

const char* const kUsage =
    "Usage: rosrun reflectance_field_map rfm_carmen2bag IN.log[.gz] OUT.bag [options]\n"
    "\n"
    "Converts a CARMEN log: FLASER/ROBOTLASER1 lines to /scan (frame laser), RLASER to\n"
    "/scan_rear (frame laser_rear), their poses to /tf odom -> base_link, the laser mounts to\n"
    "/tf_static base_link -> laser, laser_rear, and ODOM lines to /odom. Max-range readings\n"
    "become +inf (no return). Stamps that are unusable or not monotonic are repaired or\n"
    "replaced; stderr says what was done.\n"
    "\n"
    "  --max-range M   readings at or above M metres are no return (default: the sensor's\n"
    "                  max-range code found in the log)\n"
    "  --fov DEG       FLASER/RLASER beams spread evenly over DEG degrees, centred (default:\n"
    "                  the log's PARAMs or CARMEN's convention for the beam count)\n"
    "  --period S      seconds between scans when the stamps are unusable (default: the\n"
    "                  median time of the scans' steps at 0.3 m/s and 29 deg/s)\n";

struct Arguments {
  std::string in;
  std::string out;
  rfm::tools::ConversionOptions options;
};

double positiveNumber(const std::string& flag, const std::string& text) {
  char* end = nullptr;
  const double value = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(value) || value <= 0.0) {
    throw std::invalid_argument(flag + ": '" + text + "' is not a positive number");
  }
  return value;
}

// Returns false for --help.
bool parseArguments(int argc, char** argv, Arguments& args) {
  std::vector<std::string> positional;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") return false;
    if (arg == "--max-range" || arg == "--fov" || arg == "--period") {
      if (i + 1 >= argc) throw std::invalid_argument(arg + " needs a value");
      const double value = positiveNumber(arg, argv[++i]);
      if (arg == "--max-range") args.options.max_range = value;
      if (arg == "--fov") {
        if (value > 360.0) throw std::invalid_argument("--fov: at most 360 degrees");
        args.options.field_of_view_deg = value;
      }
      if (arg == "--period") args.options.synthetic_period = value;
    } else if (arg.size() > 1 && arg[0] == '-') {
      throw std::invalid_argument("unknown option " + arg);
    } else {
      positional.push_back(arg);
    }
  }
  if (positional.size() != 2) {
    throw std::invalid_argument("expected IN.log[.gz] and OUT.bag, got " +
                                std::to_string(positional.size()) + " file names");
  }
  args.in = positional[0];
  args.out = positional[1];
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  try {
    if (!parseArguments(argc, argv, args)) {
      std::cout << kUsage;
      return 0;
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "rfm_carmen2bag: " << e.what() << "\n\n" << kUsage;
    return 2;
  }
  ros::Time::init();

  try {
    std::istringstream text(rfm::tools::readPossiblyCompressedText(args.in));
    const rfm::tools::CarmenLog log = rfm::tools::readCarmenLog(text);
    std::cerr << "rfm_carmen2bag: " << args.in << ": " << log.lines << " lines, "
              << log.lasers.size() << " laser lines, " << log.odometry.size() << " ODOM lines, "
              << log.params.size() << " PARAMs\n";
    if (log.malformed_lines > 0) {
      std::cerr << "rfm_carmen2bag: warning: " << log.malformed_lines
                << " malformed lines are not converted:\n";
      for (const std::string& error : log.errors)
        std::cerr << "  " << error << "\n";
      if (log.malformed_lines > log.errors.size()) {
        std::cerr << "  (and " << log.malformed_lines - log.errors.size() << " more)\n";
      }
    }
    std::string skipped;
    for (const auto& [message, count] : log.skipped) {
      skipped +=
          " " + (message.empty() ? std::string("(blank)") : message) + " x" + std::to_string(count);
    }
    if (!skipped.empty()) std::cerr << "rfm_carmen2bag: not converted:" << skipped << "\n";

    const rfm::tools::CarmenConversion conversion = rfm::tools::convertCarmenLog(log, args.options);
    for (const std::string& note : conversion.notes)
      std::cerr << "rfm_carmen2bag: " << note << "\n";
    rfm::tools::writeCarmenBag(args.out, conversion);

    std::size_t rear = 0;
    for (const auto& scan : conversion.scans)
      rear += scan.rear;
    const double span = conversion.scans.back().time - conversion.scans.front().time;
    std::cout << "wrote " << args.out << ": " << conversion.scans.size() - rear << " scans on "
              << rfm::tools::kFrontScanTopic << ", " << rear << " on " << rfm::tools::kRearScanTopic
              << ", " << conversion.odometry.size() << " on " << rfm::tools::kOdometryTopic << ", "
              << span << " s of scans (" << rfm::tools::toString(conversion.clock_source)
              << " clock)\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "rfm_carmen2bag: " << e.what() << "\n";
    return 1;
  }
}
