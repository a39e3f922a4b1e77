#include "reflectance_field_map/offline/arguments.h"

#include <cmath>
#include <cstdlib>
#include <sstream>

namespace rfm {
namespace offline {
namespace {

std::vector<std::string> splitComma(const std::string& text) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, ','))
    parts.push_back(part);
  if (!text.empty() && text.back() == ',') parts.emplace_back();
  return parts;
}

double parseNumber(const std::string& flag, const std::string& text) {
  const char* begin = text.c_str();
  char* end = nullptr;
  const double value = std::strtod(begin, &end);
  if (text.empty() || end == begin || *end != '\0' || !std::isfinite(value)) {
    throw ArgumentError(flag + ": '" + text + "' is not a number");
  }
  return value;
}

}  // namespace

std::string usage() {
  return "Usage: rosrun reflectance_field_map rfm_offline --bag IN.bag --out DIR [options]\n"
         "\n"
         "Builds the Reflectance Field Map of a whole recording and writes DIR/map.yaml +\n"
         "map.pgm (map_server), classes.pgm (map.pgm's cells, one class code a byte: 0 unknown,\n"
         "1 free, 2 static, 3 glass, 4 metal, 5 motion), layers.png (classes in colour),\n"
         "labels.bag (/rfm/ray_labels, one reflectance_field_map/RayLabels per scan) and\n"
         "summary.json.\n"
         "\n"
         "  --bag FILE               input bag (required)\n"
         "  --out DIR                output directory, created (required)\n"
         "  --params FILE.yaml       mapper parameters by name (as config/default.yaml)\n"
         "  --scan-topics /a,/b      sensor_msgs/LaserScan topics (default /scan_front,\n"
         "                           /scan_rear: those present in the bag)\n"
         "  --fixed-frame FRAME      map/odom frame the poses are looked up in (default odom);\n"
         "                           a bag without TF (stationary sensor): the scan frame\n"
         "  --base-frame FRAME       robot frame, centre of the active region (default base_link)\n"
         "  --no-motion-removal      keep moving objects (glass then goes unfound: no reflection\n"
         "                           removal either)\n"
         "  --no-reflection-removal  keep rays seen through glass or reflected\n"
         "  --baseline               plain 2D occupancy grid instead of the RFM\n"
         "  --theta-view x0,y0,x1,y1 also write DIR/theta_view.png: theta-resolved field of the\n"
         "                           cells along that segment (m, fixed frame)\n"
         "  -h, --help               this text\n";
}

OfflineArguments parseArguments(const std::vector<std::string>& args) {
  OfflineArguments parsed;
  for (size_t i = 0; i < args.size(); ++i) {
    std::string flag = args[i];
    std::string value;
    bool has_inline_value = false;
    const size_t eq = flag.find('=');
    if (flag.rfind("--", 0) == 0 && eq != std::string::npos) {
      value = flag.substr(eq + 1);
      flag = flag.substr(0, eq);
      has_inline_value = true;
    }
    auto takeValue = [&]() -> std::string {
      if (has_inline_value) {
        if (value.empty()) throw ArgumentError(flag + " needs a value");
        return value;
      }
      if (i + 1 >= args.size() || args[i + 1].rfind("--", 0) == 0) {
        throw ArgumentError(flag + " needs a value");
      }
      return args[++i];
    };
    auto noValue = [&]() {
      if (has_inline_value) throw ArgumentError(flag + " takes no value");
    };

    if (flag == "-h" || flag == "--help") {
      noValue();
      parsed.help = true;
    } else if (flag == "--bag") {
      parsed.bag = takeValue();
    } else if (flag == "--out") {
      parsed.out = takeValue();
    } else if (flag == "--params") {
      parsed.params = takeValue();
    } else if (flag == "--scan-topics") {
      const std::vector<std::string> topics = splitComma(takeValue());
      for (const std::string& topic : topics) {
        if (topic.empty()) throw ArgumentError("--scan-topics: empty topic name in the list");
      }
      parsed.scan_topics = topics;
      parsed.scan_topics_given = true;
    } else if (flag == "--fixed-frame") {
      parsed.fixed_frame = takeValue();
    } else if (flag == "--base-frame") {
      parsed.base_frame = takeValue();
    } else if (flag == "--no-motion-removal") {
      noValue();
      parsed.no_motion_removal = true;
    } else if (flag == "--no-reflection-removal") {
      noValue();
      parsed.no_reflection_removal = true;
    } else if (flag == "--baseline") {
      noValue();
      parsed.baseline = true;
    } else if (flag == "--theta-view") {
      const std::vector<std::string> parts = splitComma(takeValue());
      if (parts.size() != 4) {
        throw ArgumentError("--theta-view needs four comma-separated numbers x0,y0,x1,y1 (m)");
      }
      std::array<double, 4> segment{};
      for (size_t k = 0; k < 4; ++k)
        segment[k] = parseNumber("--theta-view", parts[k]);
      if (segment[0] == segment[2] && segment[1] == segment[3]) {
        throw ArgumentError("--theta-view: the two end points are the same");
      }
      parsed.theta_view = segment;
    } else {
      throw ArgumentError("unknown option '" + args[i] + "' (see --help)");
    }
  }
  if (parsed.help) return parsed;
  if (parsed.bag.empty()) throw ArgumentError("--bag IN.bag is required");
  if (parsed.out.empty()) throw ArgumentError("--out DIR is required");
  if (parsed.fixed_frame.empty()) throw ArgumentError("--fixed-frame must not be empty");
  if (parsed.base_frame.empty()) throw ArgumentError("--base-frame must not be empty");
  return parsed;
}

OfflineArguments parseArguments(int argc, char** argv) {
  std::vector<std::string> args;
  for (int i = 1; i < argc; ++i)
    args.emplace_back(argv[i]);
  return parseArguments(args);
}

ModeSelection selectMode(const OfflineArguments& args, MapperOptions& options) {
  ModeSelection selection;
  if (args.baseline) {
    selection.mode = BatchMode::kPlainGrid;
    selection.name = "plain_grid";
    return selection;
  }
  bool motion = options.motion_removal.motion_removal_enabled && !args.no_motion_removal;
  bool reflection =
      options.reflection_removal.reflection_removal_enabled && !args.no_reflection_removal;
  options.motion_removal.motion_removal_enabled = motion;
  options.reflection_removal.reflection_removal_enabled = reflection;
  if (motion && reflection) {
    selection = {BatchMode::kFull, "full"};
  } else if (motion) {
    selection = {BatchMode::kMotionRemoval, "motion_removal"};
  } else if (reflection) {
    selection = {BatchMode::kFull, "reflection_removal"};
  } else {
    selection = {BatchMode::kBasicRfm, "basic_rfm"};
  }
  return selection;
}

const char* toString(BatchMode mode) {
  switch (mode) {
    case BatchMode::kPlainGrid:
      return "kPlainGrid";
    case BatchMode::kBasicRfm:
      return "kBasicRfm";
    case BatchMode::kMotionRemoval:
      return "kMotionRemoval";
    case BatchMode::kFull:
      return "kFull";
  }
  return "?";
}

}  // namespace offline
}  // namespace rfm
