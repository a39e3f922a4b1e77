#include "reflectance_field_map/tools/carmen_clock.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace rfm::tools {
namespace {

// A step forward this long or longer is a broken stamp, not a pause.
constexpr double kLongestStep = 3600.0;
// Share of forward steps that makes stamps usable.
constexpr double kUsableForwardShare = 0.9;

bool isForward(double step) {
  return std::isfinite(step) && step > 0.0 && step < kLongestStep;
}

std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof(text), pattern, value);
  return text;
}

double stampOf(const StampedLine& line, ClockSource source) {
  return source == ClockSource::kIpcStamps ? line.ipc_timestamp : line.logger_timestamp;
}

struct StampJudgement {
  bool usable = false;
  std::string why_not;
};

StampJudgement judge(const std::vector<double>& stamps) {
  StampJudgement judgement;
  if (stamps.size() == 1) {
    judgement.usable = std::isfinite(stamps[0]);
    if (!judgement.usable) judgement.why_not = "not finite";
    return judgement;
  }
  if (std::all_of(stamps.begin(), stamps.end(), [](double s) { return s == 0.0; })) {
    judgement.why_not = "all 0";
    return judgement;
  }
  if (std::all_of(stamps.begin(), stamps.end(), [&](double s) { return s == stamps[0]; })) {
    judgement.why_not = "all equal (" + format("%g", stamps[0]) + ")";
    return judgement;
  }
  std::size_t forward = 0;
  for (std::size_t i = 1; i < stamps.size(); ++i)
    forward += isForward(stamps[i] - stamps[i - 1]);
  const std::size_t steps = stamps.size() - 1;
  judgement.usable = forward >= 1 && static_cast<double>(forward) >=
                                         kUsableForwardShare * static_cast<double>(steps);
  if (!judgement.usable) {
    judgement.why_not =
        "only " + std::to_string(forward) + " of " + std::to_string(steps) + " steps go forward";
  }
  return judgement;
}

double medianForwardStep(const std::vector<double>& stamps) {
  std::vector<double> steps;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    const double step = stamps[i] - stamps[i - 1];
    if (isForward(step)) steps.push_back(step);
  }
  if (steps.empty()) return 1.0;
  std::nth_element(steps.begin(), steps.begin() + static_cast<long>(steps.size() / 2), steps.end());
  return steps[steps.size() / 2];
}

// Scan times from usable stamps: forward steps kept, the others replaced by the median step.
std::vector<double> repairedTimes(const std::vector<double>& stamps,
                                  const std::vector<std::size_t>& line_numbers,
                                  CarmenClock& clock) {
  const double median = medianForwardStep(stamps);
  std::vector<double> times(stamps.size());
  times[0] = std::isfinite(stamps[0]) ? stamps[0] : 0.0;
  std::size_t backwards = 0, repeated = 0, other = 0;
  double largest_back = 0.0;
  std::size_t largest_back_line = 0;
  for (std::size_t i = 1; i < stamps.size(); ++i) {
    const double step = stamps[i] - stamps[i - 1];
    if (isForward(step)) {
      times[i] = times[i - 1] + step;
      continue;
    }
    times[i] = times[i - 1] + median;
    ++clock.repaired_scan_steps;
    if (step < 0.0) {
      ++backwards;
      if (-step > largest_back) {
        largest_back = -step;
        largest_back_line = line_numbers[i];
      }
    } else if (step == 0.0) {
      ++repeated;
    } else {
      ++other;
    }
  }
  if (clock.repaired_scan_steps > 0) {
    std::string note = "clock: " + std::to_string(clock.repaired_scan_steps) +
                       " steps from one scan to the next did not go forward (";
    std::string parts;
    if (backwards > 0) {
      parts += std::to_string(backwards) + " backwards, the largest " +
               format("%.3f s", largest_back) + " at line " + std::to_string(largest_back_line);
    }
    if (repeated > 0) parts += (parts.empty() ? "" : ", ") + std::to_string(repeated) + " repeated";
    if (other > 0) {
      parts += (parts.empty() ? "" : ", ") + std::to_string(other) +
               " not finite or an hour or more forward";
    }
    clock.notes.push_back(note + parts + "): each became the median step " +
                          format("%.3f s", median) + ", later times keep their intervals");
  }
  return times;
}

}  // namespace

const char* toString(ClockSource source) {
  switch (source) {
    case ClockSource::kIpcStamps:
      return "ipc_timestamp";
    case ClockSource::kLoggerStamps:
      return "logger_timestamp";
    case ClockSource::kSynthetic:
      return "synthetic";
  }
  return "?";
}

CarmenClock buildCarmenClock(const std::vector<StampedLine>& lines, const ClockOptions& options) {
  CarmenClock clock;
  clock.times.assign(lines.size(), 0.0);
  if (lines.empty()) return clock;

  // The lines that define the clock: the scans, or every line of a log without scans.
  std::vector<std::size_t> defining;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].is_scan) defining.push_back(i);
  }
  const bool scans_define = !defining.empty();
  if (!scans_define) {
    for (std::size_t i = 0; i < lines.size(); ++i)
      defining.push_back(i);
  }
  const char* defining_name = scans_define ? "scans" : "lines";
  std::vector<std::size_t> defining_line_numbers;
  for (std::size_t i : defining)
    defining_line_numbers.push_back(lines[i].line_number);

  std::vector<double> stamps(defining.size());
  std::string why_not;
  clock.source = ClockSource::kSynthetic;
  for (ClockSource source : {ClockSource::kIpcStamps, ClockSource::kLoggerStamps}) {
    for (std::size_t k = 0; k < defining.size(); ++k)
      stamps[k] = stampOf(lines[defining[k]], source);
    const StampJudgement judgement = judge(stamps);
    if (judgement.usable) {
      clock.source = source;
      break;
    }
    why_not +=
        std::string(why_not.empty() ? "" : "; ") + toString(source) + ": " + judgement.why_not;
  }

  std::vector<double> defining_times;
  if (clock.source == ClockSource::kSynthetic) {
    for (std::size_t k = 0; k < defining.size(); ++k)
      defining_times.push_back(static_cast<double>(k) * options.synthetic_period);
    clock.notes.push_back("clock: the " + std::string(defining_name) + "' stamps are unusable (" +
                          why_not + "): synthesised in file order, one every " +
                          format("%.3f s", options.synthetic_period));
  } else {
    defining_times = repairedTimes(stamps, defining_line_numbers, clock);
    clock.notes.insert(clock.notes.begin(),
                       "clock: the " + std::string(defining_name) + "' " + toString(clock.source) +
                           (why_not.empty() ? "" : " (" + why_not + ")") + ", " +
                           std::to_string(defining.size()) + " " + defining_name + " over " +
                           format("%.3f s", defining_times.back() - defining_times.front()));
  }
  for (std::size_t k = 0; k < defining.size(); ++k)
    clock.times[defining[k]] = defining_times[k];

  // The other lines, gap by gap (gap g lies before defining line g; the last after them all).
  if (scans_define) {
    const std::size_t n = defining.size();
    const double period = options.synthetic_period;
    std::size_t first = 0;
    std::size_t other_lines = 0;
    for (std::size_t gap = 0; gap <= n; ++gap) {
      const std::size_t end = gap < n ? defining[gap] : lines.size();
      const std::size_t count = end - first;
      other_lines += count;
      // Times the gap spans and the stamp that anchors it.
      const std::size_t anchor = gap > 0 ? gap - 1 : 0;
      const double anchor_time = defining_times[anchor];
      const double anchor_stamp = clock.source == ClockSource::kSynthetic
                                      ? 0.0
                                      : stampOf(lines[defining[anchor]], clock.source);
      const double upper = gap < n ? defining_times[gap] : anchor_time + kLongestStep;
      const double lower = gap > 0 ? anchor_time : anchor_time - kLongestStep;
      double previous = gap > 0 ? anchor_time : -std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < count; ++j) {
        const std::size_t i = first + j;
        double time;
        if (clock.source == ClockSource::kSynthetic) {
          const double start = gap > 0 ? anchor_time : anchor_time - period;
          time = start + period * static_cast<double>(j + 1) / static_cast<double>(count + 1);
        } else {
          const double candidate = anchor_time + (stampOf(lines[i], clock.source) - anchor_stamp);
          if (std::isfinite(candidate) && candidate >= lower && candidate >= previous &&
              candidate <= upper) {
            time = candidate;
          } else {
            time = std::isfinite(previous) ? previous : anchor_time;
            ++clock.refitted_other_lines;
          }
        }
        clock.times[i] = time;
        previous = time;
      }
      first = end + 1;
    }
    if (clock.refitted_other_lines > 0) {
      clock.notes.push_back("clock: " + std::to_string(clock.refitted_other_lines) + " of " +
                            std::to_string(other_lines) +
                            " other lines (ODOM) had stamps outside the time between the lines "
                            "around them and took the time of the line before them");
    } else if (clock.source == ClockSource::kSynthetic && other_lines > 0) {
      clock.notes.push_back("clock: the " + std::to_string(other_lines) +
                            " other lines (ODOM) are spread evenly between the scans around them");
    }
  }

  const double earliest = *std::min_element(clock.times.begin(), clock.times.end());
  if (earliest < options.earliest) {
    const double shift = options.earliest - earliest;
    for (double& t : clock.times)
      t += shift;
    clock.notes.push_back("clock: shifted by " + format("%+.3f s", shift) + " to start at " +
                          format("%g s", options.earliest) + " (ROS reads time 0 as no stamp)");
  }
  return clock;
}

}  // namespace rfm::tools
