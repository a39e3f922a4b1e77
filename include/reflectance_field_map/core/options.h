// The user's parameters, one validated struct per component. Names match the ROS parameters of
// config/default.yaml.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

namespace rfm {

// A configuration value out of its allowed range. what() names the field (by its parameter
// name in config/default.yaml), the value and the allowed range.
class InvalidOption : public std::invalid_argument {
 public:
  InvalidOption(const std::string& field, const std::string& value, const std::string& allowed)
      : std::invalid_argument(field + " = " + value + " is invalid: allowed " + allowed),
        field_(field) {}
  const std::string& field() const { return field_; }

 private:
  std::string field_;
};

// Each struct is one component's parameters. validate() throws InvalidOption naming the field;
// forEachParameter(self, visit) calls visit(name, description, field) for each of them, the
// field a double&, int& or bool& (const when `self` is const), so one table serves reading and
// writing them.

struct GridOptions {
  double resolution = 0.05;  // m per cell
  int theta_bins = 180;      // direction bins over 2*pi (180 = 2 deg)
  int tile_cells = 16;       // cells per tile side: unit of scrolling and archiving
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("resolution", "cell size (m)", self.resolution);
    visit("theta_bins", "direction bins over 2*pi", self.theta_bins);
    visit("tile_cells", "cells per tile side", self.tile_cells);
  }
};

// Binary Bayes filter per (x, y, theta) bin, in log-odds, prior 0.5 (log-odds 0).
struct LogOddsOptions {
  double log_odds_hit = 0.85;   // added when a ray ends in the bin
  double log_odds_miss = -0.4;  // added when a ray passes through the bin
  double log_odds_min = -2.0;   // clamping keeps the filter responsive to change
  double log_odds_max = 3.5;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("log_odds_hit", "log-odds added by a hit", self.log_odds_hit);
    visit("log_odds_miss", "log-odds added by a miss", self.log_odds_miss);
    visit("log_odds_min", "lower clamp of a bin", self.log_odds_min);
    visit("log_odds_max", "upper clamp of a bin", self.log_odds_max);
  }
};

struct InsertionOptions {
  // Misses are added up to this distance for beams with nothing within range (+inf or
  // >= range_max, REP-117), and no hit.
  double clearing_distance = 4.0;  // m
  // Threads that insert a scan, each taking its own theta bins (1 = the caller only).
  int insertion_threads = 2;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("clearing_distance", "misses for beams with no return (m)", self.clearing_distance);
    visit("insertion_threads", "threads inserting a scan, split by theta bin",
          self.insertion_threads);
  }
};

struct ActiveRegionOptions {
  // m: rays add evidence within this distance of their sensor, into a robot-centred window.
  double active_region_radius = 10.0;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("active_region_radius", "robot-centred region updated each scan (m)",
          self.active_region_radius);
  }
};

struct OccupancyOptions {
  // eq. 5: occupied when the reflective angle (bins with p > 0.5) exceeds alpha.
  double alpha = 0.017453292519943295;  // rad (1 deg)
  // eq. 7: widely visible when sum over theta of odds * dtheta exceeds beta (odds-radians).
  // An unobserved cell sums to 2*pi (prior odds 1 everywhere), so beta must exceed that.
  double beta = 30.0;
  // Glassy cells reflective over at least this angle are reported as metal (wider lobe).
  double metal_min_angle = 0.2792526803190927;  // rad (16 deg): glass lobes are narrower
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("alpha", "eq. 5: min reflective angle of an obstacle (rad)", self.alpha);
    visit("beta", "eq. 7: min marginal odds of a widely visible cell (rad)", self.beta);
    visit("metal_min_angle", "min reflective angle of metal (rad)", self.metal_min_angle);
  }
};

struct MotionRemovalOptions {
  bool motion_removal_enabled = true;
  double motion_removal_rate = 2.0;  // Hz, passes on the scans' clock (live)
  // Cells reflective and hit again throughout this long anchor their component like widely
  // visible ones: a sensor that does not move sees walls from one direction only. Not in a
  // component with solid_min_share of its runs in solid cells that arrived where the field had
  // seen free space: a person who walked in and stood this long is confirmed too. Measured in
  // ticks of the motion-removal rate, on the scans' clock.
  double persistence_time = 12.0;  // s, 0 disables
  // Such cells anchor only components at least this long (m, longer bounding-box side): a
  // person standing still is smaller than most walls. 0 (default): any size, because the end of
  // a corridor seen from afar is as short as a person (the real stationary recording).
  double persistence_min_length = 0.0;
  // A widely visible, long-confirmed or solid cell stops anchoring once rays have confidently
  // passed through it in this much of the angle it was reflective in at a persistence tick:
  // whatever stood there has gone (a person who stood still, then walked away). Opaque
  // structure is never seen through from a direction it reflects in; glass reflects only where
  // it is not seen through. rad, 0 disables.
  double departure_min_angle = 0.10471975511965977;  // 6 deg: 3 bins at the default 2 deg
  // Such a cell also stops anchoring after this long (and 4 scans) seen through in new
  // directions while neither it nor a cell within 25 cm of it is hit (checked at persistence
  // ticks): the robot looking back, from directions it never saw them from, at where a person
  // stood. Structure seen at all is hit in or near its cell. s, 0 disables.
  double departure_vacant_time = 1.0;
  // A reflective cell missed in at most this many bins per reflective bin is solid: it returns
  // from nearly wherever it is seen. A component at least `solid_min_share` of whose runs lie in
  // solid cells (that neither departed nor arrived where the field had seen free space) is
  // structure, however sparse the scans, and its solid cells are static. Moving objects are seen
  // through where they were, glass and metal away from their lobe. 0 disables.
  double solid_max_missed_ratio = 2.0;
  double solid_min_share = 0.5;
  // A solid cell reflective over at least this angle anchors its component as a widely visible
  // one does: a window frame or pillar, solid over a wide angle but seen too briefly for eq. 7
  // (sparse scans, the batch's strided passes), carries the glass beside it. rad, 0 disables.
  double solid_anchor_min_angle = 0.2792526803190927;  // 16 deg
  // A cell that would be glass or metal with more static neighbours (of 8) than this lies
  // against structure: it is that structure's surface blurred by pose error, and static. Glass
  // is a thin surface with open space on both sides. -1 disables.
  int glass_max_static_neighbours = 2;
  // A component whose cells lie on a circle of at most this radius, each returning along the
  // circle's normal from outside, is a round column: structure. Polished metal returns a beam
  // only near its normal and folds the others away through its cells, so no cell of such a
  // column is solid or widely visible, and with no frame beside it nothing else anchors it.
  // m, 0 disables.
  double column_max_radius = 1.0;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("motion_removal_enabled", "run Alg. 2", self.motion_removal_enabled);
    visit("motion_removal_rate", "motion removal passes per s of the scans' clock (Hz)",
          self.motion_removal_rate);
    visit("persistence_time", "reflective this long without a break anchors like V (s, 0 off)",
          self.persistence_time);
    visit("persistence_min_length", "persistent cells anchor components at least this long (m)",
          self.persistence_min_length);
    visit(
        "departure_min_angle",
        "seen through over this much of its former reflective angle: anchors no more (rad, 0 off)",
        self.departure_min_angle);
    visit("departure_vacant_time",
          "seen through in new directions, never hit, this long: anchors no more (s, 0 off)",
          self.departure_vacant_time);
    visit("solid_max_missed_ratio", "missed bins per reflective bin of a solid cell (0 off)",
          self.solid_max_missed_ratio);
    visit("solid_min_share", "share of a component's runs in solid cells that makes structure",
          self.solid_min_share);
    visit("solid_anchor_min_angle", "solid cells reflective over this anchor (rad, 0 off)",
          self.solid_anchor_min_angle);
    visit("glass_max_static_neighbours", "static neighbours of a cell that can be glass (-1 off)",
          self.glass_max_static_neighbours);
    visit("column_max_radius", "max radius of a round column found by its normals (m, 0 off)",
          self.column_max_radius);
  }
};

struct ReflectionRemovalOptions {
  bool reflection_removal_enabled = true;
  // A ray may end this far beyond a glass/static cell before it counts as passing through it.
  double penetration_tolerance = 0.15;  // m
  // A static cell blocks a ray (not reflective in its direction) only once it is reflective over
  // at least this angle: only then are the directions it returns in known well enough to say it
  // would have returned the ray. A wall seen from one or two places (sparse scans) is crossed
  // by rays that pose error or its corners let pass. rad.
  double static_blocking_min_angle = 0.2792526803190927;  // 16 deg
  // Free stretches of a glass line, never faced, up to this long between structure are glass
  // (GlassCompletion; 0: off).
  double glass_completion_max_gap = 2.0;  // m
  int scan_buffer_size = 400;             // online ring buffer of recent scans (per mapper)
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("reflection_removal_enabled", "run Alg. 3", self.reflection_removal_enabled);
    visit("penetration_tolerance", "ray may end this far past glass (m)",
          self.penetration_tolerance);
    visit("static_blocking_min_angle", "reflective angle from which static cells block (rad)",
          self.static_blocking_min_angle);
    visit("glass_completion_max_gap", "free stretch of a glass line taken as glass (m, 0 off)",
          self.glass_completion_max_gap);
    visit("scan_buffer_size", "scans kept for online re-processing", self.scan_buffer_size);
  }
};

struct MapperOptions {
  GridOptions grid;
  LogOddsOptions log_odds;
  InsertionOptions insertion;
  ActiveRegionOptions active_region;
  OccupancyOptions occupancy;
  MotionRemovalOptions motion_removal;
  ReflectionRemovalOptions reflection_removal;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    GridOptions::forEachParameter(self.grid, visit);
    LogOddsOptions::forEachParameter(self.log_odds, visit);
    InsertionOptions::forEachParameter(self.insertion, visit);
    ActiveRegionOptions::forEachParameter(self.active_region, visit);
    OccupancyOptions::forEachParameter(self.occupancy, visit);
    MotionRemovalOptions::forEachParameter(self.motion_removal, visit);
    ReflectionRemovalOptions::forEachParameter(self.reflection_removal, visit);
  }
};

// The offline batch's own tuning (processBatch): the live node never reads these. They sit in
// config/default.yaml beside the others, under the same names.
struct BatchOptions {
  // The batch's eq. 7 threshold, in place of OccupancyOptions::beta. It classifies having seen
  // the whole recording, so it can ask for more: 40 is reflective over 62-70 deg at the clamp,
  // wider than a person who stood still while the robot drove past. Live, `beta` anchors a frame
  // glimpsed in passing sooner, and glass with it.
  double batch_beta = 40.0;
  // Alg. 3 re-processing passes (the paper's 1 loses glass on the shipped scenes, 3 changes
  // nothing there).
  int max_reflection_iterations = 2;
  // The passes before the last only find the glass that the last one cuts rays at, and
  // neighbouring scans of a sensor (25 ms apart at 40 Hz) see nearly the same: those passes
  // insert every Nth scan of each sensor. The first (no glass known yet) every
  // `first_pass_scan_stride`th, the others every `search_pass_scan_stride`th; the last pass
  // inserts and labels every scan. 1: every scan in every pass, as Alg. 3 reads. Glass returns
  // only near its normal: sparser than every 3rd scan, the second pass misses panes.
  int first_pass_scan_stride = 16;
  int search_pass_scan_stride = 3;
  void validate() const;
  template <typename Self, typename Visit>
  static void forEachParameter(Self& self, Visit&& visit) {
    visit("batch_beta", "batch: eq. 7 threshold of the offline tool (rad)", self.batch_beta);
    visit("max_reflection_iterations", "batch re-processing passes",
          self.max_reflection_iterations);
    visit("first_pass_scan_stride", "batch: first pass inserts every Nth scan of each sensor",
          self.first_pass_scan_stride);
    visit("search_pass_scan_stride",
          "batch: later passes but the last insert every Nth scan of each sensor",
          self.search_pass_scan_stride);
  }
};

// Every parameter of an options struct (MapperOptions, BatchOptions) by name, so ROS parameters
// and YAML files are read through one table. Booleans are 0/1, integers are rounded.
struct OptionField {
  std::string name;
  std::string description;
  enum class Type { kDouble, kInt, kBool } type;
};
// MapperOptions' table.
const std::vector<OptionField>& optionFields();
// BatchOptions' table.
const std::vector<OptionField>& batchOptionFields();
// False when `name` is not a parameter.
bool setOption(MapperOptions& options, const std::string& name, double value);
bool setOption(BatchOptions& options, const std::string& name, double value);
// Throws std::invalid_argument when `name` is not a parameter.
double getOption(const MapperOptions& options, const std::string& name);
double getOption(const BatchOptions& options, const std::string& name);

}  // namespace rfm
