// rfm_mrpt_peer: MRPT's 2D occupancy grid (COccupancyGridMap2D) inserting the beams rfm_offline
// maps, for the side-by-side comparison of test/benchmark/run_peers.sh (doc/benchmarks.md).
//
//   rfm_mrpt_peer IN.bag TOPIC[,TOPIC...] [FIXED_FRAME BASE_FRAME]
//
// The scans and their poses come from rfm_offline's own reader. Each scan becomes one
// CObservation2DRangeScan with the same beam directions and the same returns (classifyBeam),
// inserted by MRPT's own ray casting (simple rays) at 5 cm, the grid growing as MRPT grows it.
// A beam without a return clears the RFM's stretch (clearing_distance) and adds no hit: MRPT
// does that for a valid range at its maxDistanceInsertion, so such beams go in a second
// observation of the scan with that distance set to the stretch. Prints one JSON line: scans,
// rays, the insertion's seconds and the grid's size.
#include "peer_input.h"
#include "reflectance_field_map/core/laser_scan.h"
#include "reflectance_field_map/core/options.h"
#include "reflectance_field_map/offline/bag_input.h"

#include <mrpt/maps/COccupancyGridMap2D.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/poses/CPose3D.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <exception>
#include <iostream>
#include <limits>
#include <string>

namespace {

// Fills `returns` with the scan's beams that returned and `no_returns` with those that did not
// (at `clearing` m), every other beam invalid in each; counts them in `hits` and `clears`.
void fillObservations(const rfm::LaserScan2D& scan, float clearing,
                      mrpt::obs::CObservation2DRangeScan& returns,
                      mrpt::obs::CObservation2DRangeScan& no_returns, size_t& hits,
                      size_t& clears) {
  returns.resizeScan(scan.ranges.size());
  no_returns.resizeScan(scan.ranges.size());
  hits = clears = 0;
  for (size_t beam = 0; beam < scan.ranges.size(); ++beam) {
    const rfm::BeamReading reading =
        rfm::classifyBeam(scan.ranges[beam], scan.range_min, scan.range_max);
    const bool hit = reading == rfm::BeamReading::kReturn;
    const bool clear = reading == rfm::BeamReading::kNoReturn;
    returns.setScanRange(beam, hit ? scan.ranges[beam] : 0.0f);
    returns.setScanRangeValidity(beam, hit);
    no_returns.setScanRange(beam, clear ? clearing : 0.0f);
    no_returns.setScanRangeValidity(beam, clear);
    hits += hit;
    clears += clear;
  }
}

}  // namespace

int main(int argc, char** argv) {
  const auto input_options = rfm::benchmark::peerInputOptions(argc, argv);
  if (!input_options) {
    std::cerr << "usage: rfm_mrpt_peer " << rfm::benchmark::peerUsage() << "\n";
    return 2;
  }
  try {
    const rfm::offline::BagScans input = rfm::offline::readBagScans(*input_options);

    const rfm::MapperOptions defaults;
    const auto resolution = static_cast<float>(defaults.grid.resolution);
    mrpt::maps::COccupancyGridMap2D grid(-10.0f, 10.0f, -10.0f, 10.0f, resolution);
    auto& insertion = grid.insertionOptions;
    insertion.considerInvalidRangesAsFreeSpace = false;  // invalid beams change nothing
    insertion.wideningBeamsWithDistance = false;         // one ray per beam, as the RFM
    mrpt::obs::CObservation2DRangeScan returns, no_returns;
    size_t ray_count = 0;
    const auto start = std::chrono::steady_clock::now();
    for (const rfm::TimedScan& timed : input.scans) {
      const rfm::LaserScan2D& scan = timed.scan;
      const size_t beams = scan.ranges.size();
      if (beams == 0) continue;
      // MRPT's beam k heads phi - aperture / 2 + k * aperture / beams: the scan's own directions.
      const float aperture = static_cast<float>(beams) * scan.angle_increment;
      const double phi = timed.sensor_pose.yaw + scan.angle_min + 0.5 * aperture;
      const mrpt::poses::CPose3D sensor(timed.sensor_pose.position.x(),
                                        timed.sensor_pose.position.y(), 0.0, phi, 0.0, 0.0);
      for (auto* observation : {&returns, &no_returns}) {
        observation->aperture = aperture;
        observation->rightToLeft = true;
        observation->maxRange = scan.range_max;
      }
      const float clearing = static_cast<float>(
          std::min<double>(defaults.insertion.clearing_distance, scan.range_max));
      size_t hits = 0, clears = 0;
      fillObservations(scan, clearing, returns, no_returns, hits, clears);
      insertion.maxDistanceInsertion = std::numeric_limits<float>::max();
      if (hits > 0) grid.insertObservation(returns, sensor);
      insertion.maxDistanceInsertion = clearing;
      if (clears > 0) grid.insertObservation(no_returns, sensor);
      ray_count += hits + clears;
    }
    const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::printf(
        "{\"scans\": %zu, \"rays\": %zu, \"process_seconds\": %.3f, \"cells\": %zu, "
        "\"grid_bytes\": %zu}\n",
        input.scans.size(), ray_count, seconds,
        static_cast<size_t>(grid.getSizeX()) * grid.getSizeY(),
        static_cast<size_t>(grid.getSizeX()) * grid.getSizeY() *
            sizeof(mrpt::maps::COccupancyGridMap2D::cellType));
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "rfm_mrpt_peer: " << e.what() << "\n";
    return 1;
  }
}
