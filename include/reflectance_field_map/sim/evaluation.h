// Ray classification scoring (the paper's Tables I-III): compares per-beam ground truth (RayTruth
// classes) with a mapper's per-beam labels (RayLabels) and aggregates confusion matrices over
// scenes into a markdown report. ROS-free.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "reflectance_field_map/sim/cell_evaluation.h"

namespace rfm::sim {

// Label values of msg/RayLabels.msg.
enum class RayLabel : std::uint8_t { kNoReturn = 0, kKept = 1, kMotion = 2, kReflection = 3 };

// The five true classes scored (RayTruth values 1..5); NO_RETURN truth beams are not scored.
constexpr std::array<const char*, 5> kScoredClassNames = {"diffuse", "glass", "metal", "motion",
                                                          "reflection"};

struct ClassCounts {
  std::uint64_t total = 0;
  std::uint64_t kept = 0;
  std::uint64_t removed_motion = 0;      // labelled MOTION
  std::uint64_t removed_reflection = 0;  // labelled REFLECTION
  std::uint64_t removed_no_return = 0;   // a true return the mapper labelled NO_RETURN

  std::uint64_t removed() const { return removed_motion + removed_reflection + removed_no_return; }
  double keptPercent() const { return total ? 100.0 * kept / total : 0.0; }
  double removedPercent() const { return total ? 100.0 * removed() / total : 0.0; }
  ClassCounts& operator+=(const ClassCounts& other);
  bool operator==(const ClassCounts& other) const;
};

class ConfusionMatrix {
 public:
  // Scores one scan. Throws std::invalid_argument if the sizes differ. Truth NO_RETURN beams are
  // counted as excluded; labels or truth values outside the message constants count as invalid.
  void addScan(const std::vector<std::uint8_t>& truth_classes,
               const std::vector<std::uint8_t>& labels);
  void merge(const ConfusionMatrix& other);

  // Row for a scored class, index 0..4 = diffuse, glass, metal, motion, reflection.
  const ClassCounts& row(std::size_t scored_index) const { return rows_.at(scored_index); }
  ClassCounts& row(std::size_t scored_index) { return rows_.at(scored_index); }
  std::uint64_t scans() const { return scans_; }
  std::uint64_t excludedNoReturnTruth() const { return excluded_no_return_truth_; }
  // Beams without a true echo that the labels do not call NO_RETURN. A mapper cannot label a beam
  // with an infinite range otherwise, so a large count means truth and labels are mispaired.
  std::uint64_t noReturnMislabelled() const { return no_return_mislabelled_; }
  std::uint64_t invalidBeams() const { return invalid_beams_; }
  std::uint64_t scoredRays() const;

  // Table I-style markdown table (no heading).
  std::string toMarkdownTable() const;
  // Machine-readable form; fromJson() reads it back (throws std::runtime_error on bad input).
  std::string toJson() const;
  static ConfusionMatrix fromJson(const std::string& json_text);

  bool operator==(const ConfusionMatrix& other) const;

 private:
  std::array<ClassCounts, 5> rows_{};
  std::uint64_t scans_ = 0;
  std::uint64_t excluded_no_return_truth_ = 0;
  std::uint64_t no_return_mislabelled_ = 0;
  std::uint64_t invalid_beams_ = 0;
};

// One (configuration, scene) result for the aggregated report.
struct EvaluationEntry {
  std::string config;  // e.g. "baseline", "basic", "motion", "full"
  std::string scene;
  ConfusionMatrix matrix;
  std::optional<CellConfusion> cells;  // class metrics, when the scene's world was given
  std::string setup;                   // grouped reports: the sensor setup, and the seeds' split
  std::string split;                   // (tuning or checking)
};

// Markdown report: per-configuration confusion matrices summed (ray-weighted) over scenes, the
// Table III-style ablation table and a per-scene breakdown, and the class metrics summed
// (cell-weighted) when entries have them. Configurations appear in the order of their first
// entry; `preamble` is inserted verbatim after the title (how to reproduce, etc.).
std::string buildEvaluationReport(const std::vector<EvaluationEntry>& entries,
                                  const std::string& preamble);

// Markdown report of random scenes grouped by sensor setup and seed split: a summary of every
// (setup, split, configuration) beside issue 35's targets, then per setup the summed confusion of
// rays and of cells, and a row per scene.
std::string buildGroupedReport(const std::vector<EvaluationEntry>& entries,
                               const std::string& title, const std::string& preamble);

}  // namespace rfm::sim
