// rfm_sim: simulates a scene with two lidars on a wheelchair-like robot and writes a bag with
// scans, ground truth per beam (/sim/ray_truth), TF and odometry.
//
//   rosrun reflectance_field_map rfm_sim --scene config/scenes/atrium.yaml --out atrium.bag
//                                        [--seed N]
#include <rosbag/exceptions.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <string>

#include "reflectance_field_map/sim/scene.h"
#include "sim_bag_writer.h"

namespace {

void printUsage(std::ostream& out) {
  out << "usage: rfm_sim --scene SCENE.yaml --out OUT.bag [--seed N]\n"
         "  Simulates the scene (format: config/scenes/README.md) and writes /scan_front,\n"
         "  /scan_rear, /sim/ray_truth, /tf, /tf_static and /odom. --seed overrides the scene's.\n";
}

bool parseSeed(const std::string& text, std::uint32_t& seed) {
  try {
    std::size_t used = 0;
    const unsigned long long value = std::stoull(text, &used);
    if (used != text.size() || value > 0xffffffffULL) return false;
    seed = static_cast<std::uint32_t>(value);
    return true;
  } catch (const std::exception&) {
    return false;
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path, out_path, seed_text;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      printUsage(std::cout);
      return 0;
    }
    if ((arg == "--scene" || arg == "--out" || arg == "--seed") && i + 1 < argc) {
      (arg == "--scene" ? scene_path : arg == "--out" ? out_path : seed_text) = argv[++i];
    } else {
      std::cerr << "rfm_sim: unexpected argument '" << arg << "'\n";
      printUsage(std::cerr);
      return 2;
    }
  }
  if (scene_path.empty() || out_path.empty()) {
    std::cerr << "rfm_sim: --scene and --out are required\n";
    printUsage(std::cerr);
    return 2;
  }

  rfm::sim::Scene scene;
  try {
    scene = rfm::sim::loadScene(scene_path);
  } catch (const rfm::sim::SceneError& error) {
    std::cerr << "rfm_sim: invalid scene: " << error.what() << "\n";
    return 1;
  }
  std::uint32_t seed = scene.seed;
  if (!seed_text.empty() && !parseSeed(seed_text, seed)) {
    std::cerr << "rfm_sim: --seed must be an integer in [0, 4294967295], got '" << seed_text
              << "'\n";
    return 2;
  }

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
            << "  " << summary.scans << " scans, " << summary.robot_states
            << " tf samples, generated in " << seconds << " s\n  beams:";
  const char* names[] = {"no_return", "diffuse", "glass", "metal", "motion", "reflection"};
  for (int i = 0; i < 6; ++i)
    std::cout << " " << names[i] << "=" << summary.beams_per_class[i];
  std::cout << "\n";
  return 0;
}
