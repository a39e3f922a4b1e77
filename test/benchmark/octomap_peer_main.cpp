// rfm_octomap_peer: OctoMap inserting the rays rfm_offline maps, as a planar slice, for the
// side-by-side comparison of test/benchmark/run_peers.sh (doc/benchmarks.md).
//
//   rfm_octomap_peer IN.bag TOPIC[,TOPIC...] [FIXED_FRAME BASE_FRAME]
//
// The scans and their poses come from rfm_offline's own reader, and each scan's rays from the
// RFM's own conversion (scanToRays, default insertion options: the same returns, the same
// cleared stretch for a beam without one). Each ray's cells along z = 0 get a miss and its end
// cell a hit, as OcTree::insertRay does, at 5 cm; inner nodes are updated once at the end. Prints
// one JSON line: scans, rays, the insertion's seconds and the tree's size.
#include "peer_input.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/offline/bag_input.h"

#include <octomap/octomap.h>

#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  const auto input_options = rfm::benchmark::peerInputOptions(argc, argv);
  if (!input_options) {
    std::cerr << "usage: rfm_octomap_peer " << rfm::benchmark::peerUsage() << "\n";
    return 2;
  }
  try {
    const rfm::offline::BagScans input = rfm::offline::readBagScans(*input_options);

    const rfm::MapperOptions defaults;
    const double resolution = defaults.grid.resolution;
    octomap::OcTree tree(resolution);
    octomap::KeyRay cells;
    std::vector<rfm::Ray> rays;
    size_t ray_count = 0;
    const auto start = std::chrono::steady_clock::now();
    for (const rfm::TimedScan& scan : input.scans) {
      rfm::scanToRays(scan.scan, scan.sensor_pose, defaults.insertion, rays);
      ray_count += rays.size();
      for (const rfm::Ray& ray : rays) {
        const octomap::point3d origin(static_cast<float>(ray.origin.x()),
                                      static_cast<float>(ray.origin.y()), 0.0f);
        const octomap::point3d end(static_cast<float>(ray.end.x()), static_cast<float>(ray.end.y()),
                                   0.0f);
        if (tree.computeRayKeys(origin, end, cells)) {
          for (const octomap::OcTreeKey& key : cells)
            tree.updateNode(key, false, /*lazy_eval=*/true);
        }
        if (ray.hit) tree.updateNode(end, true, /*lazy_eval=*/true);
      }
    }
    tree.updateInnerOccupancy();
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "{\"scans\": %zu, \"rays\": %zu, \"process_seconds\": %.3f, \"leaf_nodes\": %zu, "
        "\"tree_bytes\": %zu}\n",
        input.scans.size(), ray_count, seconds, tree.getNumLeafNodes(), tree.memoryUsage());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "rfm_octomap_peer: " << e.what() << "\n";
    return 1;
  }
}
