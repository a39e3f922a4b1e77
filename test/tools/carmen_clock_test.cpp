// The monotonic clock of a CARMEN log: each quirk of real logs' stamps.

#include "reflectance_field_map/tools/carmen_clock.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace {

using rfm::tools::buildCarmenClock;
using rfm::tools::CarmenClock;
using rfm::tools::ClockOptions;
using rfm::tools::ClockSource;
using rfm::tools::StampedLine;

std::vector<StampedLine> scansAt(const std::vector<double>& stamps) {
  std::vector<StampedLine> lines;
  for (size_t i = 0; i < stamps.size(); ++i)
    lines.push_back({stamps[i], stamps[i], true, i + 1});
  return lines;
}

std::string allNotes(const CarmenClock& clock) {
  std::string text;
  for (const std::string& note : clock.notes)
    text += note + "\n";
  return text;
}

void expectScansStrictlyIncreasing(const std::vector<StampedLine>& lines,
                                   const CarmenClock& clock) {
  ASSERT_EQ(clock.times.size(), lines.size());
  double previous_scan = -std::numeric_limits<double>::infinity();
  double previous = -std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < lines.size(); ++i) {
    EXPECT_TRUE(std::isfinite(clock.times[i])) << i;
    EXPECT_GE(clock.times[i], previous) << "line " << i;
    previous = clock.times[i];
    if (lines[i].is_scan) {
      EXPECT_GT(clock.times[i], previous_scan) << "scan line " << i;
      previous_scan = clock.times[i];
    }
  }
}

TEST(CarmenClock, SaneStampsAreKept) {
  const auto lines = scansAt({100.0, 100.5, 101.25, 103.0});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  EXPECT_EQ(clock.times, (std::vector<double>{100.0, 100.5, 101.25, 103.0}));
  EXPECT_EQ(clock.repaired_scan_steps, 0u);
  ASSERT_EQ(clock.notes.size(), 1u);
  EXPECT_NE(clock.notes[0].find("ipc_timestamp, 4 scans over 3.000 s"), std::string::npos)
      << allNotes(clock);
}

TEST(CarmenClock, AllZeroIsSynthesisedInScanOrder) {
  const auto lines = scansAt({0.0, 0.0, 0.0, 0.0});
  ClockOptions options;
  options.synthetic_period = 2.0;
  const CarmenClock clock = buildCarmenClock(lines, options);
  EXPECT_EQ(clock.source, ClockSource::kSynthetic);
  EXPECT_EQ(clock.times, (std::vector<double>{1.0, 3.0, 5.0, 7.0}));  // starts at 1 s
  const std::string notes = allNotes(clock);
  EXPECT_NE(notes.find("ipc_timestamp: all 0"), std::string::npos) << notes;
  EXPECT_NE(notes.find("synthesised in file order, one every 2.000 s"), std::string::npos) << notes;
}

// Stamps printed with 6 significant digits (1.01893e+09) are all equal.
TEST(CarmenClock, CoarseStampsAreSynthesised) {
  const auto lines = scansAt(std::vector<double>(10, 1.01893e+09));
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kSynthetic);
  expectScansStrictlyIncreasing(lines, clock);
  EXPECT_NE(allNotes(clock).find("all equal (1.01893e+09)"), std::string::npos) << allNotes(clock);
}

// Mostly repeated stamps (a clock coarser than the scan rate) are not usable either.
TEST(CarmenClock, MostlyRepeatedStampsAreSynthesised) {
  const auto lines = scansAt({1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kSynthetic);
  EXPECT_NE(allNotes(clock).find("only 2 of 11 steps go forward"), std::string::npos)
      << allNotes(clock);
}

// The intel log: a stamp 0.86 s earlier than the one before it.
TEST(CarmenClock, BackwardStepBecomesTheMedianStep) {
  const auto lines = scansAt(
      {2120.0, 2121.0, 2122.0, 2125.63, 2124.77, 2126.0, 2127.0, 2128.0, 2129.0, 2130.0, 2131.0});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  EXPECT_EQ(clock.repaired_scan_steps, 1u);
  expectScansStrictlyIncreasing(lines, clock);
  EXPECT_DOUBLE_EQ(clock.times[3], 2125.63);
  EXPECT_DOUBLE_EQ(clock.times[4], 2126.63);          // + the median step, 1 s
  EXPECT_NEAR(clock.times[5], 2126.63 + 1.23, 1e-9);  // later intervals kept
  const std::string notes = allNotes(clock);
  EXPECT_NE(notes.find("1 backwards, the largest 0.860 s at line 5"), std::string::npos) << notes;
  EXPECT_NE(notes.find("median step 1.000 s"), std::string::npos) << notes;
}

TEST(CarmenClock, WrapContinuesFromWhereItWas) {
  const auto lines =
      scansAt({4290.0, 4291.0, 4292.0, 4293.0, 4294.0, 4295.0, 0.5, 1.5, 2.5, 3.5, 4.5, 5.5});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_DOUBLE_EQ(clock.times[i], 4290.0 + static_cast<double>(i)) << i;
}

TEST(CarmenClock, StartBelowZeroIsShifted) {
  const auto lines = scansAt({-5.0, -4.5, -4.0});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  EXPECT_EQ(clock.times, (std::vector<double>{1.0, 1.5, 2.0}));
  EXPECT_NE(allNotes(clock).find("shifted by +6.000 s to start at 1 s"), std::string::npos)
      << allNotes(clock);
}

// A stamp that is not a number, and one a billion seconds ahead (two broken steps).
TEST(CarmenClock, BrokenStampsAreRepaired) {
  std::vector<double> stamps;
  for (int i = 0; i <= 40; ++i)
    stamps.push_back(10.0 + i);
  stamps[2] = std::numeric_limits<double>::quiet_NaN();
  stamps[5] = 1e9;
  const auto lines = scansAt(stamps);
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  expectScansStrictlyIncreasing(lines, clock);
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_DOUBLE_EQ(clock.times[i], 10.0 + static_cast<double>(i)) << i;
  EXPECT_NE(allNotes(clock).find("3 not finite or an hour or more forward"), std::string::npos)
      << allNotes(clock);
}

TEST(CarmenClock, LoggerStampsWhenIpcStampsAreUnusable) {
  std::vector<StampedLine> lines;
  for (size_t i = 0; i < 5; ++i)
    lines.push_back({0.0, 10.0 + static_cast<double>(i), true, i + 1});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kLoggerStamps);
  EXPECT_EQ(clock.times, (std::vector<double>{10, 11, 12, 13, 14}));
  EXPECT_NE(allNotes(clock).find("ipc_timestamp: all 0"), std::string::npos) << allNotes(clock);
}

// Corrected logs: raw odometry lines with their own stamps between the scans, and after each
// scan an ODOM line stamped 0 (or garbage) repeating the corrected pose.
TEST(CarmenClock, OdometryFitsBetweenTheScans) {
  const std::vector<StampedLine> lines = {
      {0.2, 0.2, false, 1},    // before the first scan: kept
      {0.5, 0.5, false, 2},    //
      {1.0, 1.0, true, 3},     // scan
      {0.0, 0.0, false, 4},    // echo stamped 0: the scan's time
      {1.4, 1.4, false, 5},    // kept
      {1.3, 1.3, false, 6},    // jitter backwards: the line before's time
      {3.4e-86, 0, false, 7},  // garbage: the line before's time
      {2.0, 2.0, true, 8},     // scan
      {9.0, 9.0, false, 9},    // beyond the next scan: the line before's time
      {3.0, 3.0, true, 10},    // scan
      {3.5, 3.5, false, 11},   // after the last scan: kept
  };
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  expectScansStrictlyIncreasing(lines, clock);
  // Shifted by +0.8 s so the earliest line is at 1 s.
  const std::vector<double> expected = {0.2, 0.5, 1.0, 1.0, 1.4, 1.4, 1.4, 2.0, 2.0, 3.0, 3.5};
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_NEAR(clock.times[i], expected[i] + 0.8, 1e-9) << "line " << i + 1;
  EXPECT_EQ(clock.refitted_other_lines, 4u);
  EXPECT_NE(allNotes(clock).find("4 of 8 other lines (ODOM)"), std::string::npos)
      << allNotes(clock);
}

TEST(CarmenClock, SyntheticClockSpreadsOdometryEvenly) {
  const std::vector<StampedLine> lines = {
      {0, 0, false, 1}, {0, 0, true, 2}, {0, 0, false, 3}, {0, 0, false, 4},
      {0, 0, false, 5}, {0, 0, true, 6}, {0, 0, false, 7},
  };
  ClockOptions options;
  options.synthetic_period = 4.0;
  const CarmenClock clock = buildCarmenClock(lines, options);
  EXPECT_EQ(clock.source, ClockSource::kSynthetic);
  // Before shifting: -2 | 0 | 1 2 3 | 4 | 6.
  const std::vector<double> expected = {-2, 0, 1, 2, 3, 4, 6};
  for (size_t i = 0; i < lines.size(); ++i)
    EXPECT_NEAR(clock.times[i], expected[i] + 3.0, 1e-9) << "line " << i + 1;
}

TEST(CarmenClock, OdometryAloneDefinesTheClock) {
  std::vector<StampedLine> lines;
  for (size_t i = 0; i < 4; ++i)
    lines.push_back({5.0 + static_cast<double>(i), 0.0, false, i + 1});
  const CarmenClock clock = buildCarmenClock(lines, ClockOptions());
  EXPECT_EQ(clock.source, ClockSource::kIpcStamps);
  EXPECT_EQ(clock.times, (std::vector<double>{5, 6, 7, 8}));
}

TEST(CarmenClock, OneScanAndNone) {
  EXPECT_TRUE(buildCarmenClock({}, ClockOptions()).times.empty());
  const CarmenClock one = buildCarmenClock(scansAt({42.0}), ClockOptions());
  EXPECT_EQ(one.source, ClockSource::kIpcStamps);
  EXPECT_EQ(one.times, std::vector<double>{42.0});
  const CarmenClock zero = buildCarmenClock(scansAt({0.0}), ClockOptions());
  EXPECT_EQ(zero.times, std::vector<double>{1.0});
}

}  // namespace
