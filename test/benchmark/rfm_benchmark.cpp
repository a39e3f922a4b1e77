// Insertion, motion removal and whole-update benchmarks on the default active region
// (10 m, 5 cm, 2 deg) with 1081-beam UTM-30LX scans. Results: doc/benchmarks.md.

#include "reflectance_field_map/core/clearance_map.h"
#include "reflectance_field_map/core/mapper.h"
#include "reflectance_field_map/core/motion_removal.h"
#include "reflectance_field_map/core/plain_occupancy_grid.h"
#include "reflectance_field_map/core/scan_inserter.h"

#include "indoor_scene.h"

#include <benchmark/benchmark.h>
#include <octomap/octomap.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <vector>

namespace rfm {
namespace {

constexpr int kPoses = 400;  // 10 m of corridor, 800 scans

const std::vector<benchmarking::BenchmarkScan>& scans() {
  static const auto all = benchmarking::indoorScans(kPoses, InsertionOptions());
  return all;
}

void reportRays(benchmark::State& state) {
  size_t rays = 0, cells = 0;
  for (const auto& s : scans()) {
    rays += s.rays.size();
    for (const Ray& r : s.rays)
      cells += static_cast<size_t>((r.end - r.origin).norm() / 0.05);
  }
  state.counters["rays_per_scan"] = static_cast<double>(rays) / scans().size();
  state.counters["mean_ray_cells"] = static_cast<double>(cells) / rays;
}

// Sweeps a scan's rays theta bin by theta bin as the RFM's insertion does (clipped to the
// window, bucketed by bin, one visitCellsOfRays per bin), but through `visit` instead of the
// field's writers. Returns the visitor.
template <typename Visit>
Visit sweepScan(ReflectanceField& field, const benchmarking::BenchmarkScan& s,
                ScanInserter::PreparedScan& scratch, Visit visit) {
  field.recenter(s.scan.robot_pose.position);
  ScanInserter::prepare(s.rays, field, scratch);
  const std::vector<uint32_t>& group_begin = scratch.group_begin;
  for (size_t bin = 0; bin + 1 < group_begin.size(); ++bin) {
    visit = visitCellsOfRays(scratch.clipped, scratch.order.data() + group_begin[bin],
                             group_begin[bin + 1] - group_begin[bin],
                             field.geometry().inverseResolution(), field.window(), visit);
  }
  return visit;
}

// Counts the sweep's cell visits, with and without de-duplication marks.
struct VisitCounter {
  size_t marked = 0;
  size_t unmarked = 0;
  void operator()(int) { ++marked; }
  void once(int) { ++unmarked; }
};

// Share of a scan's RFM cell visits that the sweep makes without de-duplication marks (a theta
// bin's single fan, in the columns where all its rays are under way; visitCellsOfRays).
double unmarkedVisitShare() {
  const MapperOptions options;
  ReflectanceField field(options.grid, options.log_odds, options.active_region);
  ScanInserter::PreparedScan scratch;
  VisitCounter counter;
  for (const auto& s : scans())
    counter = sweepScan(field, s, scratch, counter);
  return static_cast<double>(counter.unmarked) /
         std::max<size_t>(counter.marked + counter.unmarked, 1);
}

// Argument: insertion threads (the default options use 2; 1 shows the single-thread cost).
void BM_RfmInsert(benchmark::State& state) {
  const MapperOptions options;
  ReflectanceField field(options.grid, options.log_odds, options.active_region);
  // As in the Mapper: one set of threads for re-centring and insertion.
  auto runner = std::make_shared<ParallelRunner>(static_cast<int>(state.range(0)));
  ScanInserter inserter(runner);
  size_t i = 0, updates = 0;
  for (auto _ : state) {
    const auto& s = scans()[i++ % scans().size()];
    field.recenter(s.scan.robot_pose.position, runner.get());
    updates += inserter.insert(s.rays, field);
  }
  reportRays(state);
  // One per (cell, theta bin) a scan's rays cross: what Alg. 1 must write.
  state.counters["updates_per_scan"] = static_cast<double>(updates) / std::max<size_t>(i, 1);
  state.counters["active_region_MB"] = field.activeBytes() / 1e6;
  static const double unmarked_share = unmarkedVisitShare();
  state.counters["unmarked_visit_share"] = unmarked_share;
}
BENCHMARK(BM_RfmInsert)->Arg(2)->Arg(1)->Unit(benchmark::kMillisecond);

// The sweep alone, on one thread: RfmInsert/1's work without the field's updates (no reads or
// writes of bins, no hits, no summaries). Set beside RfmInsert/1, it shows what share of an
// insertion walking the cells costs.
void BM_RfmSweepOnly(benchmark::State& state) {
  const MapperOptions options;
  ReflectanceField field(options.grid, options.log_odds, options.active_region);
  size_t i = 0;
  ScanInserter::PreparedScan scratch;
  VisitCounter counter;
  for (auto _ : state) {
    counter = sweepScan(field, scans()[i++ % scans().size()], scratch, counter);
    benchmark::DoNotOptimize(counter);
  }
  state.counters["visits_per_scan"] =
      static_cast<double>(counter.marked + counter.unmarked) / std::max<size_t>(i, 1);
}
BENCHMARK(BM_RfmSweepOnly)->Unit(benchmark::kMillisecond);

void BM_PlainGridInsert(benchmark::State& state) {
  const MapperOptions options;
  PlainOccupancyGrid grid(options.grid, options.log_odds, options.active_region);
  size_t i = 0, updates = 0;
  for (auto _ : state) {
    const auto& s = scans()[i++ % scans().size()];
    grid.recenter(s.scan.robot_pose.position);
    updates += grid.insert(s.rays);
  }
  reportRays(state);
  state.counters["updates_per_scan"] = static_cast<double>(updates) / std::max<size_t>(i, 1);
}
BENCHMARK(BM_PlainGridInsert)->Unit(benchmark::kMillisecond);

// The single-thread RFM / plain grid ratio, measured block by block: each iteration inserts
// the same block of scans into the RFM and then into the plain grid, each timed on its own.
// Both see the machine in the same state, so a neighbour's load moves both sides of a pair and
// the median of the per-pair ratios holds still where ratios of separate medians do not. Blocks
// are long enough (kBlockScans) that the plain grid's few hundred kB are back in cache after
// its first scan.
void BM_RfmOverPlainPaired(benchmark::State& state) {
  constexpr size_t kBlockScans = 64;
  const MapperOptions options;
  ReflectanceField field(options.grid, options.log_odds, options.active_region);
  auto runner = std::make_shared<ParallelRunner>(1);
  ScanInserter inserter(runner);
  PlainOccupancyGrid grid(options.grid, options.log_odds, options.active_region);
  using Clock = std::chrono::steady_clock;
  std::vector<double> ratios, rfm_ms, plain_ms;
  size_t next = 0;
  for (auto _ : state) {
    const size_t first = next;
    next += kBlockScans;
    const auto rfm_start = Clock::now();
    for (size_t i = first; i < next; ++i) {
      const auto& s = scans()[i % scans().size()];
      field.recenter(s.scan.robot_pose.position, runner.get());
      benchmark::DoNotOptimize(inserter.insert(s.rays, field));
    }
    const auto plain_start = Clock::now();
    for (size_t i = first; i < next; ++i) {
      const auto& s = scans()[i % scans().size()];
      grid.recenter(s.scan.robot_pose.position);
      benchmark::DoNotOptimize(grid.insert(s.rays));
    }
    const auto end = Clock::now();
    const double rfm = std::chrono::duration<double, std::milli>(plain_start - rfm_start).count();
    const double plain = std::chrono::duration<double, std::milli>(end - plain_start).count();
    ratios.push_back(rfm / plain);
    rfm_ms.push_back(rfm / kBlockScans);
    plain_ms.push_back(plain / kBlockScans);
  }
  auto median = [](std::vector<double> values) {
    if (values.empty()) return 0.0;
    std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
    return values[values.size() / 2];
  };
  state.counters["ratio_median"] = median(ratios);
  state.counters["rfm_ms_per_scan"] = median(rfm_ms);
  state.counters["plain_ms_per_scan"] = median(plain_ms);
}
// Enough blocks to cover the 800 scans several times.
BENCHMARK(BM_RfmOverPlainPaired)->Iterations(60)->Unit(benchmark::kMillisecond);

// OctoMap inserting the same rays as a planar slice (z = 0), with its own per-scan
// de-duplication (insertPointCloud: occupied wins) and max-range clearing for no-returns.
void BM_OctomapInsert(benchmark::State& state) {
  octomap::OcTree tree(0.05);
  std::vector<octomap::Pointcloud> clouds;
  std::vector<octomap::point3d> origins;
  for (const auto& s : scans()) {
    octomap::Pointcloud cloud;
    const InsertionOptions insertion;
    for (const Ray& r : s.rays) {
      // No-returns become points at the clearing distance beyond max range: cleared, not hit.
      const Eigen::Vector2d end = r.hit ? r.end : r.origin + (r.end - r.origin) * (1.0 + 1e-3);
      cloud.push_back(static_cast<float>(end.x()), static_cast<float>(end.y()), 0.0f);
    }
    clouds.push_back(std::move(cloud));
    origins.emplace_back(static_cast<float>(s.scan.sensor_pose.position.x()),
                         static_cast<float>(s.scan.sensor_pose.position.y()), 0.0f);
  }
  size_t i = 0;
  for (auto _ : state) {
    const size_t k = i++ % clouds.size();
    tree.insertPointCloud(clouds[k], origins[k], InsertionOptions().clearing_distance);
  }
  reportRays(state);
}
BENCHMARK(BM_OctomapInsert)->Unit(benchmark::kMillisecond);

// Mapper driven as online: a filled field (two passes of the corridor), then the stage alone.
// Argument 0 switches the departure checks off (departure_min_angle = departure_vacant_time =
// 0, so no history is kept), to show their cost.
Mapper& filledMapper(bool departures) {
  static std::unique_ptr<Mapper> mappers[2];
  std::unique_ptr<Mapper>& mapper = mappers[departures];
  if (!mapper) {
    MapperOptions options;
    if (!departures) {
      options.motion_removal.departure_min_angle = 0.0;
      options.motion_removal.departure_vacant_time = 0.0;
    }
    mapper = std::make_unique<Mapper>(options);
    for (const auto& s : scans())
      mapper->addScan(s.scan);
    mapper->removeMotion();
  }
  return *mapper;
}

// The 40 scans (two 40 Hz lidars) that arrive between two runs of motion removal at 2 Hz,
// continuing along the corridor (and around again) with advancing stamps.
void addScansBetweenRuns(Mapper& mapper, size_t& next_scan) {
  for (int k = 0; k < 40; ++k, ++next_scan) {
    TimedScan scan = scans()[next_scan % scans().size()].scan;
    scan.stamp += 100.0 + 0.0125 * static_cast<double>(next_scan);
    mapper.addScan(scan);
  }
}

// As online: 40 new scans (not timed) before each run, so what changed is what 0.5 s of driving
// changes; unchanged free-space tiles are reused.
void BM_MotionRemoval(benchmark::State& state) {
  Mapper& mapper = filledMapper(state.range(0) != 0);
  size_t next_scan = 0;
  for (auto _ : state) {
    state.PauseTiming();
    addScansBetweenRuns(mapper, next_scan);
    state.ResumeTiming();
    benchmark::DoNotOptimize(mapper.removeMotion());
  }
  state.counters["static_cells"] = static_cast<double>(mapper.stats().occupied_cells);
}
BENCHMARK(BM_MotionRemoval)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The classification alone, the same way, by one remover that reuses unchanged tiles
// (argument 1) and by a new remover each time that classifies every tile afresh (argument 0).
void BM_MotionClassify(benchmark::State& state) {
  MapperOptions options;
  options.motion_removal.motion_removal_enabled = false;  // the field only
  Mapper mapper(options);
  for (const auto& s : scans())
    mapper.addScan(s.scan);
  const OccupancyRule rule(options.occupancy, mapper.field().geometry().binWidth());
  ParallelRunner runner(options.insertion.insertion_threads);
  MotionRemover reusing(rule);
  std::vector<CellClass> classes;
  auto outside = [](const CellIndex&) { return CellClass::kUnknown; };
  size_t next_scan = 0;
  for (auto _ : state) {
    state.PauseTiming();
    addScansBetweenRuns(mapper, next_scan);
    MotionRemover fresh(rule);
    state.ResumeTiming();
    MotionRemover& remover = state.range(0) != 0 ? reusing : fresh;
    benchmark::DoNotOptimize(remover.classify(mapper.field(), mapper.anchorHistory(),
                                              mapper.field().activeBox(), outside, classes,
                                              &runner));
  }
}
BENCHMARK(BM_MotionClassify)->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);

// The reflection check's clearance map, rebuilt as each motion-removal pass and placement of
// the window rebuild it: 512 x 512 cells (the default window's side), 2 % of them blocking, in
// single cells (argument 0, the mapper's) or blocks of 4 (argument 2).
void BM_ClearanceRebuild(benchmark::State& state) {
  constexpr int kSide = 512;
  std::vector<uint8_t> blocking(kSide * kSide);
  std::mt19937 rng(1);
  std::bernoulli_distribution two_percent(0.02);
  for (uint8_t& cell : blocking)
    cell = two_percent(rng);
  ClearanceMap clearance(static_cast<int>(state.range(0)));
  const CellBox box{{0, 0}, {kSide, kSide}};
  for (auto _ : state) {
    clearance.compute(box, [&](int dx, int dy) { return blocking[dy * kSide + dx] == 0; });
    benchmark::DoNotOptimize(clearance.at({kSide / 2, kSide / 2}));
  }
}
BENCHMARK(BM_ClearanceRebuild)->Arg(0)->Arg(2)->Unit(benchmark::kMillisecond);

// The whole online update per scan: reflection check + insertion + motion removal at 2 Hz with
// two 40 Hz lidars (one removal every 40 scans), amortised.
void BM_WholeUpdatePerScan(benchmark::State& state) {
  Mapper mapper{MapperOptions()};
  size_t i = 0;
  for (const auto& s : scans())
    mapper.addScan(s.scan);
  for (auto _ : state) {
    const auto& s = scans()[i % scans().size()];
    TimedScan scan = s.scan;
    scan.stamp += 100.0 + 0.0125 * static_cast<double>(i);
    benchmark::DoNotOptimize(mapper.addScan(scan));
    if (++i % 40 == 0) mapper.removeMotion();
  }
}
BENCHMARK(BM_WholeUpdatePerScan)->Unit(benchmark::kMillisecond);

// Scaling: the whole online update per scan (as BM_WholeUpdatePerScan) and the active region's
// memory, as one of the active-region radius (m), the theta bins and the beams per scan moves
// away from the defaults (10 m, 180, 1081). Args: radius, theta bins, beams. Drawn by
// test/benchmark/run_scaling.sh into doc/scaling.png.
const std::vector<benchmarking::BenchmarkScan>& scansWithBeams(int beams) {
  static std::map<int, std::vector<benchmarking::BenchmarkScan>> by_beams;
  auto it = by_beams.find(beams);
  if (it == by_beams.end()) {
    it =
        by_beams.emplace(beams, benchmarking::indoorScans(kPoses, InsertionOptions(), beams)).first;
  }
  return it->second;
}

void BM_Scaling(benchmark::State& state) {
  MapperOptions options;
  options.active_region.active_region_radius = static_cast<double>(state.range(0));
  options.grid.theta_bins = static_cast<int>(state.range(1));
  const auto& corridor = scansWithBeams(static_cast<int>(state.range(2)));
  Mapper mapper{options};
  for (const auto& s : corridor)
    mapper.addScan(s.scan);
  mapper.removeMotion();
  size_t i = 0;
  for (auto _ : state) {
    const auto& s = corridor[i % corridor.size()];
    TimedScan scan = s.scan;
    scan.stamp += 100.0 + 0.0125 * static_cast<double>(i);
    benchmark::DoNotOptimize(mapper.addScan(scan));
    if (++i % 40 == 0) mapper.removeMotion();
  }
  state.counters["radius_m"] = static_cast<double>(state.range(0));
  state.counters["theta_bins"] = static_cast<double>(state.range(1));
  state.counters["beams"] = static_cast<double>(state.range(2));
  state.counters["active_region_MB"] = mapper.stats().field_bytes / 1e6;
}
BENCHMARK(BM_Scaling)
    ->Args({5, 180, 1081})
    ->Args({10, 180, 1081})
    ->Args({20, 180, 1081})
    ->Args({10, 90, 1081})
    ->Args({10, 720, 1081})
    ->Args({10, 180, 270})
    ->Args({10, 180, 4320})
    ->Unit(benchmark::kMillisecond);

// Memory, measured once: the active region at defaults, the compressed evidence kept for cells
// that left it (per explored square metre), and the global 2D map of a 200 m x 200 m area.
void BM_MemoryFootprint(benchmark::State& state) {
  for (auto _ : state) {
    Mapper mapper{MapperOptions()};
    // 30 m of corridor at 1 m/s: most of the region scrolls out into the archive.
    const auto corridor = benchmarking::indoorScans(1200, InsertionOptions());
    for (const auto& s : corridor)
      mapper.addScan(s.scan);
    const MapperStats stats = mapper.stats();
    const ReflectanceField& field = mapper.field();
    const double tile_area =
        std::pow(field.window().tileCells() * field.geometry().resolution(), 2);
    state.counters["active_region_MB"] = stats.field_bytes / 1e6;
    state.counters["archived_tiles"] = static_cast<double>(field.archivedTiles());
    state.counters["archive_bytes_per_m2"] =
        field.archivedTiles() == 0 ? 0.0
                                   : field.archivedBytes() / (field.archivedTiles() * tile_area);
    GlobalMap2D map;
    const int cells = static_cast<int>(200.0 / 0.05);
    map.assign({{0, 0}, {cells, cells}}, [](const CellIndex&) { return CellClass::kFree; });
    state.counters["global_map_200m_MB"] = map.bytes() / 1e6;
  }
}
BENCHMARK(BM_MemoryFootprint)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace rfm

BENCHMARK_MAIN();
