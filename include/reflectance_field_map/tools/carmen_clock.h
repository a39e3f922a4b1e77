#pragma once

// A monotonic clock for the lines of a CARMEN log, whose stamps may be all 0, run backwards,
// start below zero or wrap round. ROS-free.

#include <cstddef>
#include <string>
#include <vector>

namespace rfm::tools {

// One line with a time, in file order.
struct StampedLine {
  double ipc_timestamp = 0.0;
  double logger_timestamp = 0.0;
  bool is_scan = false;  // scans define the clock; other lines (odometry) fit into it
  std::size_t line_number = 0;
};

enum class ClockSource { kIpcStamps, kLoggerStamps, kSynthetic };

const char* toString(ClockSource source);

struct ClockOptions {
  // Seconds between scans when the stamps are unusable.
  double synthetic_period = 1.0;
  // The earliest time of the clock: ROS reads a zero stamp as "no stamp".
  double earliest = 1.0;
};

struct CarmenClock {
  std::vector<double> times;  // one per line: scans strictly increasing, all non-decreasing
  ClockSource source = ClockSource::kSynthetic;
  std::size_t repaired_scan_steps = 0;   // scan steps not forward, replaced
  std::size_t refitted_other_lines = 0;  // other lines whose stamp did not fit between scans
  std::vector<std::string> notes;        // what was done, for the user
};

// The clock:
// - The scans' ipc stamps if usable, else their logger stamps, else a synthetic clock at
//   options.synthetic_period in scan order. Stamps are usable when at least 90 % of the steps
//   from one scan to the next go forward.
// - With stamps, every forward step of less than an hour is kept as it is; any other step
//   (backwards, repeated, a wrap, not finite, an hour or more forward) becomes the median
//   forward step, so the times after it keep their intervals.
// - A line that is not a scan keeps its stamp (moved with the scan before it) when that lies
//   between the time of the line before it and the next scan's time; otherwise it takes the
//   time of the line before it. With a synthetic clock such lines are spread evenly between
//   the scans around them.
// - Everything is shifted later when needed so the earliest time is options.earliest.
CarmenClock buildCarmenClock(const std::vector<StampedLine>& lines, const ClockOptions& options);

}  // namespace rfm::tools
