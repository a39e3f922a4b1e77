// rfm_sim: simulates a scene (a file, or one drawn from a seed) with its lidars and writes a bag
// with scans, ground truth per beam (/sim/ray_truth), TF and odometry.
//
//   rosrun reflectance_field_map rfm_sim --scene config/scenes/atrium.yaml --out atrium.bag
//   rosrun reflectance_field_map rfm_sim --random 1001 --setup sick180 --out r.bag
//                                        --write-scene r.yaml
//   rosrun reflectance_field_map rfm_sim --list-setups
#include <rosbag/exceptions.h>
#include <yaml-cpp/yaml.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "reflectance_field_map/sim/random_scene.h"
#include "reflectance_field_map/sim/scene.h"
#include "reflectance_field_map/sim/sensor_setups.h"
#include "sim_bag_writer.h"

namespace {

void printUsage(std::ostream& out) {
  out << "usage: rfm_sim --scene SCENE.yaml --out OUT.bag [options]\n"
         "       rfm_sim --random SEED [--out OUT.bag] [--write-scene FILE] [options]\n"
         "       rfm_sim --list-setups\n"
         "  Simulates the scene (format: config/scenes/README.md), or a procedural one drawn\n"
         "  from SEED, and writes its scans, /sim/ray_truth, /tf, /tf_static and /odom.\n"
         "options:\n"
         "  --seed N            noise seed (default: the scene's; a random scene's is SEED)\n"
         "  --setup NAME        sensor setup (see --list-setups) instead of the scene's lidars\n"
         "  --keep-every-m M    keep a scan only once the robot moved M metres since the last\n"
         "  --keep-every-deg D  ... or turned D degrees (a CARMEN-style thinned log)\n"
         "  --duration S        seconds of data (a random scene is planned for it)\n"
         "  --no-drift          a random scene's odometry follows the true path\n"
         "  --write-scene FILE  also write the scene simulated as YAML (reproduce with --scene)\n";
}

std::optional<unsigned long long> parseUnsigned(const std::string& text, unsigned long long max) {
  try {
    std::size_t used = 0;
    const unsigned long long value = std::stoull(text, &used);
    if (used != text.size() || value > max || text[0] == '-') return std::nullopt;
    return value;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::optional<double> parseNonNegative(const std::string& text) {
  try {
    std::size_t used = 0;
    const double value = std::stod(text, &used);
    if (used != text.size() || !(value >= 0.0) || !std::isfinite(value)) return std::nullopt;
    return value;
  } catch (const std::exception&) {
    return std::nullopt;
  }
}

std::string readFile(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw rfm::sim::SceneError(path, "", "cannot open scene file");
  std::ostringstream contents;
  contents << file.rdbuf();
  return contents.str();
}

void listSetups() {
  for (const rfm::sim::SensorSetup& setup : rfm::sim::sensorSetups()) {
    std::cout << setup.name << ": " << setup.description << "\n";
    for (const rfm::sim::LidarSpec& lidar : setup.lidars) {
      const double fov = (lidar.beam_count - 1) * lidar.angle_increment * 180.0 / M_PI;
      std::cout << "    " << lidar.topic << " (" << lidar.frame_id << "): " << lidar.beam_count
                << " beams over " << std::setprecision(4) << fov << " deg, " << lidar.rate_hz
                << " Hz, " << lidar.range_min << "-" << lidar.range_max << " m\n";
    }
    if (setup.logger.enabled()) {
      std::cout << "    logger: a scan kept every " << setup.logger.keep_every_m << " m or "
                << setup.logger.keep_every_deg << " deg\n";
    }
  }
}

struct Overrides {
  std::optional<std::string> setup;
  std::optional<double> keep_every_m, keep_every_deg, duration;
  bool any() const { return setup || keep_every_m || keep_every_deg || duration; }
  rfm::sim::ScanLoggerSpec logger(rfm::sim::ScanLoggerSpec base) const {
    if (keep_every_m) base.keep_every_m = *keep_every_m;
    if (keep_every_deg) base.keep_every_deg = *keep_every_deg;
    return base;
  }
};

// The scene file's text with the command line's overrides written into it, so that what is
// simulated and what --write-scene writes are one and the same.
std::string overriddenSceneText(const std::string& text, const std::string& source,
                                const Overrides& overrides) {
  if (!overrides.any()) return text;
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw rfm::sim::SceneError(source, "", std::string("invalid YAML: ") + error.what());
  }
  if (!root.IsMap()) throw rfm::sim::SceneError(source, "", "expected a YAML mapping");
  if (overrides.setup) {
    root.remove("lidars");
    root.remove("sensors");
    root.remove("logger");
    root["setup"] = *overrides.setup;
  }
  if (overrides.duration) root["duration"] = rfm::sim::formatNumber(*overrides.duration);
  if (overrides.keep_every_m || overrides.keep_every_deg) {
    const rfm::sim::ScanLoggerSpec logger =
        overrides.logger(rfm::sim::parseScene(YAML::Dump(root), source).logger);
    YAML::Node node;
    node["keep_every_m"] = rfm::sim::formatNumber(logger.keep_every_m);
    node["keep_every_deg"] = rfm::sim::formatNumber(logger.keep_every_deg);
    root["logger"] = node;
  }
  return YAML::Dump(root) + "\n";
}

int simulate(const rfm::sim::Scene& scene, std::uint32_t seed, const std::string& out_path) {
  const auto start = std::chrono::steady_clock::now();
  rfm::sim::SimulationSummary summary;
  try {
    summary = rfm::tools::writeSimulationBag(scene, seed, out_path);
  } catch (const rosbag::BagException& error) {
    std::cerr << "rfm_sim: cannot write '" << out_path << "': " << error.what() << "\n";
    std::remove(out_path.c_str());
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "rfm_sim: simulation failed: " << error.what() << "\n";
    return 1;
  }
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << "rfm_sim: scene '" << scene.name << "' (" << scene.duration << " s, seed " << seed
            << ", " << scene.world.surfaceCount() << " surfaces, " << scene.people.size()
            << " people, robot path " << summary.path_length << " m) -> " << out_path << "\n"
            << "  " << summary.scans << " scans";
  if (summary.scans_not_logged) std::cout << " (" << summary.scans_not_logged << " not logged)";
  std::cout << ", " << summary.robot_states << " tf samples, generated in " << seconds << " s\n";
  if (scene.odometry.enabled) {
    std::cout << "  odometry drifted " << summary.final_odometry_error_m << " m and "
              << summary.final_odometry_error_deg << " deg by the end\n";
  }
  std::cout << "  beams:";
  const char* names[] = {"no_return", "diffuse", "glass", "metal", "motion", "reflection"};
  for (int i = 0; i < 6; ++i)
    std::cout << " " << names[i] << "=" << summary.beams_per_class[i];
  std::cout << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> options;
  bool no_drift = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      printUsage(std::cout);
      return 0;
    }
    if (arg == "--list-setups") {
      listSetups();
      return 0;
    }
    if (arg == "--no-drift") {
      no_drift = true;
      continue;
    }
    const bool takes_value = arg == "--scene" || arg == "--out" || arg == "--seed" ||
                             arg == "--random" || arg == "--setup" || arg == "--keep-every-m" ||
                             arg == "--keep-every-deg" || arg == "--duration" ||
                             arg == "--write-scene";
    if (takes_value && i + 1 < argc) {
      options[arg] = argv[++i];
    } else {
      std::cerr << "rfm_sim: unexpected argument '" << arg << "'\n";
      printUsage(std::cerr);
      return 2;
    }
  }
  const bool random = options.count("--random") > 0;
  if (random == (options.count("--scene") > 0)) {
    std::cerr << "rfm_sim: give either --scene or --random\n";
    printUsage(std::cerr);
    return 2;
  }
  if (!options.count("--out") && !(random && options.count("--write-scene"))) {
    std::cerr << "rfm_sim: --out is required (--random may write only the scene with "
                 "--write-scene)\n";
    printUsage(std::cerr);
    return 2;
  }
  if (no_drift && !random) {
    std::cerr << "rfm_sim: --no-drift applies to --random scenes (edit a scene file's odometry)\n";
    return 2;
  }

  Overrides overrides;
  if (options.count("--setup")) {
    try {
      rfm::sim::sensorSetup(options["--setup"]);
    } catch (const std::invalid_argument& error) {
      std::cerr << "rfm_sim: " << error.what() << "\n";
      return 2;
    }
    overrides.setup = options["--setup"];
  }
  for (const auto& [flag, target] :
       {std::pair<const char*, std::optional<double>*>{"--keep-every-m", &overrides.keep_every_m},
        {"--keep-every-deg", &overrides.keep_every_deg},
        {"--duration", &overrides.duration}}) {
    if (!options.count(flag)) continue;
    *target = parseNonNegative(options[flag]);
    if (!*target) {
      std::cerr << "rfm_sim: " << flag << " must be a number >= 0, got '" << options[flag] << "'\n";
      return 2;
    }
  }
  std::optional<std::uint32_t> seed_override;
  if (options.count("--seed")) {
    const auto seed = parseUnsigned(options["--seed"], 0xffffffffULL);
    if (!seed) {
      std::cerr << "rfm_sim: --seed must be an integer in [0, 4294967295], got '"
                << options["--seed"] << "'\n";
      return 2;
    }
    seed_override = static_cast<std::uint32_t>(*seed);
  }

  std::string scene_text, source;
  try {
    if (random) {
      const auto seed = parseUnsigned(options["--random"], 0xffffffffULL);
      if (!seed) {
        std::cerr << "rfm_sim: --random must be an integer in [0, 4294967295], got '"
                  << options["--random"] << "'\n";
        return 2;
      }
      rfm::sim::RandomSceneOptions random_options;
      random_options.seed = static_cast<std::uint32_t>(*seed);
      if (overrides.setup) random_options.setup = *overrides.setup;
      random_options.duration = overrides.duration;
      if (overrides.keep_every_m || overrides.keep_every_deg) {
        random_options.logger =
            overrides.logger(rfm::sim::sensorSetup(random_options.setup).logger);
      }
      random_options.odometry_drift = !no_drift;
      scene_text = rfm::sim::generateRandomScene(random_options).yaml;
      source = "random scene " + options["--random"];
    } else {
      source = options["--scene"];
      scene_text = overriddenSceneText(readFile(source), source, overrides);
    }
  } catch (const rfm::sim::SceneError& error) {
    std::cerr << "rfm_sim: invalid scene: " << error.what() << "\n";
    return 1;
  } catch (const std::exception& error) {
    std::cerr << "rfm_sim: cannot make the scene: " << error.what() << "\n";
    return 1;
  }

  rfm::sim::Scene scene;
  try {
    scene = rfm::sim::parseScene(scene_text, source);
  } catch (const rfm::sim::SceneError& error) {
    std::cerr << "rfm_sim: invalid scene: " << error.what() << "\n";
    return 1;
  }
  if (options.count("--write-scene")) {
    std::ofstream file(options["--write-scene"]);
    file << scene_text;
    if (!file) {
      std::cerr << "rfm_sim: cannot write '" << options["--write-scene"] << "'\n";
      return 1;
    }
    std::cout << "rfm_sim: wrote the scene to " << options["--write-scene"] << "\n";
  }
  if (!options.count("--out")) return 0;
  return simulate(scene, seed_override ? *seed_override : scene.seed, options["--out"]);
}
