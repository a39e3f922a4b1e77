#pragma once

#include <algorithm>
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

// Each struct is one component's options; validate() throws InvalidOption naming the field.
// Field names match the ROS parameter names of config/default.yaml.

struct GridOptions {
  double resolution = 0.05;  // m per cell
  int theta_bins = 180;      // direction bins over 2*pi (180 = 2 deg)
  int tile_cells = 16;       // cells per tile side: unit of scrolling and archiving
  void validate() const;
};

// Binary Bayes filter per (x, y, theta) bin, in log-odds, prior 0.5 (log-odds 0).
struct LogOddsOptions {
  double log_odds_hit = 0.85;   // added when a ray ends in the bin
  double log_odds_miss = -0.4;  // added when a ray passes through the bin
  double log_odds_min = -2.0;   // clamping keeps the filter responsive to change
  double log_odds_max = 3.5;
  void validate() const;
};

struct InsertionOptions {
  // Misses are added up to this distance for beams with nothing within range (+inf or
  // >= range_max, REP-117), and no hit.
  double clearing_distance = 4.0;  // m
  // Threads that insert a scan, each taking its own theta bins (1 = the caller only).
  int insertion_threads = 2;
  void validate() const;
};

struct ActiveRegionOptions {
  // m: rays add evidence within this distance of their sensor, into a robot-centred window.
  double active_region_radius = 10.0;
  // m: a window larger than the radius needs (0: none). Not a parameter: the batch holds a whole
  // recording in one window, and its rays still add evidence only within the radius.
  double window_radius = 0.0;
  // About 14 GB of field at 5 cm and 180 bins.
  static constexpr double kMaxWindowRadius = 200.0;  // m
  double windowRadius() const { return std::max(active_region_radius, window_radius); }
  void validate() const;
};

struct OccupancyOptions {
  // eq. 5: occupied when the reflective angle (bins with p > 0.5) exceeds alpha.
  double alpha = 0.017453292519943295;  // rad (1 deg)
  // eq. 7: widely visible when sum over theta of odds * dtheta exceeds beta (odds-radians).
  // An unobserved cell sums to 2*pi (prior odds 1 everywhere), so beta must exceed that.
  double beta = 30.0;
  // The offline batch's beta (processBatch). It classifies having seen the whole recording, so
  // it can ask for more: 40 is reflective over 62-70 deg at the clamp, wider than a person who
  // stood still while the robot drove past (README, Results). Live, `beta` anchors a frame
  // glimpsed in passing sooner, and glass with it.
  double batch_beta = 40.0;
  // Glassy cells reflective over at least this angle are reported as metal (wider lobe).
  double metal_min_angle = 0.2792526803190927;  // rad (16 deg): glass lobes are narrower
  void validate() const;
};

struct MotionRemovalOptions {
  bool motion_removal_enabled = true;
  double motion_removal_rate = 2.0;  // Hz, online timer
  // Cells reflective and hit again throughout this long anchor their component like widely
  // visible ones: a sensor that does not move sees walls from one direction only. A person
  // standing this long counts as structure until the misses after they leave clear the cells.
  // Measured in ticks of the motion-removal rate, on the scans' clock.
  double persistence_time = 12.0;  // s, 0 disables
  // Such cells anchor only components at least this long (m, longer bounding-box side): a
  // person standing still is smaller than most walls. 0 (default): any size, because the end of
  // a corridor seen from afar is as short as a person (the real stationary recording).
  double persistence_min_length = 0.0;
  // A widely visible or long-confirmed cell stops anchoring once rays have confidently passed
  // through it in this much of the angle it was reflective in at a persistence tick: whatever
  // stood there has gone (a person who stood still, then walked away). Opaque structure is never
  // seen through from a direction it reflects in; glass reflects only where it is not seen
  // through. rad, 0 disables.
  double departure_min_angle = 0.10471975511965977;  // 6 deg: 3 bins at the default 2 deg
  // Such a cell also stops anchoring after this long seen through in new directions without
  // being hit once (checked at persistence ticks): the robot looking back, from directions it
  // never saw them from, at where a person stood. Structure seen at all is hit. s, 0 disables.
  double departure_vacant_time = 1.0;
  // A cell reflective over at least this angle that no ray ever passed through anchors its
  // component when the component is at least `opaque_min_length` long: a wall glimpsed through
  // a doorway is neither widely visible nor long confirmed, but is never seen through, while a
  // person walking by is soon seen through where they were. rad, 0 disables.
  double opaque_min_angle = 0.10471975511965977;  // 6 deg
  double opaque_min_length = 1.0;                 // m, longer bounding-box side; 0: any size
  void validate() const;
};

struct ReflectionRemovalOptions {
  bool reflection_removal_enabled = true;
  // A ray may end this far beyond a glass/static cell before it counts as passing through it.
  double penetration_tolerance = 0.15;  // m
  // Batch re-processing passes (the paper's 1 loses glass on the shipped scenes, 3 changes
  // nothing there).
  int max_reflection_iterations = 2;
  // The batch's passes before the last only find the glass that the last one cuts rays at, and
  // neighbouring scans of a sensor (25 ms apart at 40 Hz) see nearly the same: those passes
  // insert every Nth scan of each sensor. The first (no glass known yet) every
  // `first_pass_scan_stride`th, the others every `search_pass_scan_stride`th; the last pass
  // inserts and labels every scan. 1: every scan in every pass, as Alg. 3 reads. Glass returns
  // only near its normal: sparser than every 3rd scan, the second pass misses panes.
  int first_pass_scan_stride = 16;
  int search_pass_scan_stride = 3;
  // Free stretches of a glass line, never faced, up to this long between structure are glass
  // (GlassCompletion; 0: off).
  double glass_completion_max_gap = 2.0;  // m
  int scan_buffer_size = 400;             // online ring buffer of recent scans (per mapper)
  // The glass check leaps over cells that cannot block a ray by a clearance map kept in blocks
  // of 2^clearance_block_shift cells a side (ClearanceMap, at most kMaxBlockShift). Not a
  // parameter: blocks of 4 cells keep its rebuild at each online motion removal cheap; the batch
  // rebuilds it once per pass and uses single cells, so rays leap closer to structure.
  int clearance_block_shift = 2;
  void validate() const;
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
};

// Every MapperOptions field by its parameter name, so ROS parameters and YAML files are read
// through one table. Booleans are 0/1, integers are rounded.
struct OptionField {
  std::string name;
  std::string description;
  enum class Type { kDouble, kInt, kBool } type;
};
const std::vector<OptionField>& optionFields();
// False when `name` is not a field.
bool setOption(MapperOptions& options, const std::string& name, double value);
double getOption(const MapperOptions& options, const std::string& name);

}  // namespace rfm
