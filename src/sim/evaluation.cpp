#include "reflectance_field_map/sim/evaluation.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <iomanip>
#include <map>
#include <sstream>
#include <stdexcept>

namespace rfm::sim {
namespace {

constexpr std::uint8_t kTruthNoReturn = 0;
constexpr std::uint8_t kTruthMaxClass = 5;

std::string percent(double value) {
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << value;
  return out.str();
}

// Percentage cell of a report table: "-" for a class without rays.
std::string rate(const ClassCounts& counts, bool kept) {
  if (counts.total == 0) return "-";
  return percent(kept ? counts.keptPercent() : counts.removedPercent());
}

std::uint64_t readCount(const YAML::Node& node, const std::string& key) {
  if (!node[key]) throw std::runtime_error("evaluation JSON: missing '" + key + "'");
  return node[key].as<std::uint64_t>();
}

}  // namespace

ClassCounts& ClassCounts::operator+=(const ClassCounts& other) {
  total += other.total;
  kept += other.kept;
  removed_motion += other.removed_motion;
  removed_reflection += other.removed_reflection;
  removed_no_return += other.removed_no_return;
  return *this;
}

bool ClassCounts::operator==(const ClassCounts& other) const {
  return total == other.total && kept == other.kept && removed_motion == other.removed_motion &&
         removed_reflection == other.removed_reflection &&
         removed_no_return == other.removed_no_return;
}

void ConfusionMatrix::addScan(const std::vector<std::uint8_t>& truth_classes,
                              const std::vector<std::uint8_t>& labels) {
  if (truth_classes.size() != labels.size()) {
    throw std::invalid_argument("truth has " + std::to_string(truth_classes.size()) +
                                " beams but labels have " + std::to_string(labels.size()));
  }
  ++scans_;
  for (std::size_t i = 0; i < truth_classes.size(); ++i) {
    const std::uint8_t truth = truth_classes[i];
    if (truth == kTruthNoReturn) {
      ++excluded_no_return_truth_;
      if (labels[i] != static_cast<std::uint8_t>(RayLabel::kNoReturn)) ++no_return_mislabelled_;
      continue;
    }
    if (truth > kTruthMaxClass || labels[i] > static_cast<std::uint8_t>(RayLabel::kReflection)) {
      ++invalid_beams_;
      continue;
    }
    ClassCounts& counts = rows_[truth - 1];
    ++counts.total;
    switch (static_cast<RayLabel>(labels[i])) {
      case RayLabel::kKept:
        ++counts.kept;
        break;
      case RayLabel::kMotion:
        ++counts.removed_motion;
        break;
      case RayLabel::kReflection:
        ++counts.removed_reflection;
        break;
      case RayLabel::kNoReturn:
        ++counts.removed_no_return;
        break;
    }
  }
}

void ConfusionMatrix::merge(const ConfusionMatrix& other) {
  for (std::size_t i = 0; i < rows_.size(); ++i)
    rows_[i] += other.rows_[i];
  scans_ += other.scans_;
  excluded_no_return_truth_ += other.excluded_no_return_truth_;
  no_return_mislabelled_ += other.no_return_mislabelled_;
  invalid_beams_ += other.invalid_beams_;
}

std::uint64_t ConfusionMatrix::scoredRays() const {
  std::uint64_t sum = 0;
  for (const ClassCounts& counts : rows_)
    sum += counts.total;
  return sum;
}

bool ConfusionMatrix::operator==(const ConfusionMatrix& other) const {
  return rows_ == other.rows_ && scans_ == other.scans_ &&
         excluded_no_return_truth_ == other.excluded_no_return_truth_ &&
         no_return_mislabelled_ == other.no_return_mislabelled_ &&
         invalid_beams_ == other.invalid_beams_;
}

std::string ConfusionMatrix::toMarkdownTable() const {
  std::ostringstream out;
  out << "| True class | Total | Kept (%) | Removed (%) | as motion | as reflection | "
         "as no-return |\n"
      << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const ClassCounts& c = rows_[i];
    out << "| " << kScoredClassNames[i] << " | " << c.total << " | " << rate(c, true) << " | "
        << rate(c, false) << " | " << c.removed_motion << " | " << c.removed_reflection << " | "
        << c.removed_no_return << " |\n";
  }
  return out.str();
}

std::string ConfusionMatrix::toJson() const {
  std::ostringstream out;
  out << "{\n  \"scans\": " << scans_ << ",\n  \"scored_rays\": " << scoredRays()
      << ",\n  \"excluded_no_return_truth\": " << excluded_no_return_truth_
      << ",\n  \"no_return_mislabelled\": " << no_return_mislabelled_
      << ",\n  \"invalid_beams\": " << invalid_beams_ << ",\n  \"classes\": {\n";
  for (std::size_t i = 0; i < rows_.size(); ++i) {
    const ClassCounts& c = rows_[i];
    out << "    \"" << kScoredClassNames[i] << "\": {\"total\": " << c.total
        << ", \"kept\": " << c.kept << ", \"removed\": " << c.removed()
        << ", \"removed_motion\": " << c.removed_motion
        << ", \"removed_reflection\": " << c.removed_reflection
        << ", \"removed_no_return\": " << c.removed_no_return
        << ", \"kept_percent\": " << percent(c.keptPercent())
        << ", \"removed_percent\": " << percent(c.removedPercent()) << "}"
        << (i + 1 < rows_.size() ? "," : "") << "\n";
  }
  out << "  }\n}\n";
  return out.str();
}

ConfusionMatrix ConfusionMatrix::fromJson(const std::string& json_text) {
  ConfusionMatrix matrix;
  try {
    const YAML::Node root = YAML::Load(json_text);  // JSON is valid YAML 1.2 flow syntax
    if (!root.IsMap()) throw std::runtime_error("evaluation JSON: expected an object");
    matrix.scans_ = readCount(root, "scans");
    matrix.excluded_no_return_truth_ = readCount(root, "excluded_no_return_truth");
    matrix.invalid_beams_ = readCount(root, "invalid_beams");
    if (root["no_return_mislabelled"]) {
      matrix.no_return_mislabelled_ = readCount(root, "no_return_mislabelled");
    }
    const YAML::Node classes = root["classes"];
    if (!classes || !classes.IsMap()) throw std::runtime_error("evaluation JSON: no 'classes'");
    for (std::size_t i = 0; i < kScoredClassNames.size(); ++i) {
      const YAML::Node row = classes[kScoredClassNames[i]];
      if (!row) {
        throw std::runtime_error(std::string("evaluation JSON: missing class ") +
                                 kScoredClassNames[i]);
      }
      ClassCounts& c = matrix.rows_[i];
      c.total = readCount(row, "total");
      c.kept = readCount(row, "kept");
      c.removed_motion = readCount(row, "removed_motion");
      c.removed_reflection = readCount(row, "removed_reflection");
      c.removed_no_return = readCount(row, "removed_no_return");
      if (c.kept + c.removed() != c.total) {
        throw std::runtime_error(std::string("evaluation JSON: counts of ") + kScoredClassNames[i] +
                                 " do not add up to total");
      }
    }
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("evaluation JSON: ") + error.what());
  }
  return matrix;
}

std::string buildEvaluationReport(const std::vector<EvaluationEntry>& entries,
                                  const std::string& preamble) {
  std::vector<std::string> configs;
  std::vector<std::string> scenes;
  std::map<std::string, ConfusionMatrix> totals;
  for (const EvaluationEntry& entry : entries) {
    if (!totals.count(entry.config)) configs.push_back(entry.config);
    if (std::find(scenes.begin(), scenes.end(), entry.scene) == scenes.end()) {
      scenes.push_back(entry.scene);
    }
    totals[entry.config].merge(entry.matrix);
  }
  // The per-scene tables list the entries scene by scene, configurations in first-seen order.
  std::vector<const EvaluationEntry*> by_scene;
  for (const std::string& scene : scenes)
    for (const std::string& config : configs)
      for (const EvaluationEntry& entry : entries)
        if (entry.scene == scene && entry.config == config) by_scene.push_back(&entry);

  std::ostringstream out;
  out << "# Ray classification evaluation on simulated scenes\n\n" << preamble;
  if (!preamble.empty() && preamble.back() != '\n') out << "\n";
  out << "\nRays are scored per beam against the simulator's ground truth (the paper's Tables "
         "I-III)."
         " Kept = labelled KEPT; removed = labelled MOTION, REFLECTION or NO_RETURN (the last also"
         " counted separately). Beams with no true echo are excluded. Totals are summed over all"
         " scenes (ray-weighted).\n\n";

  out << "## Ablation (Table III style)\n\n"
      << "| Configuration | Recall diffuse (%) | Recall glass (%) | Recall metal (%) | "
         "Motion removed (%) | Reflection removed (%) | Scored rays |\n"
      << "|---|---:|---:|---:|---:|---:|---:|\n";
  for (const std::string& config : configs) {
    const ConfusionMatrix& m = totals[config];
    out << "| " << config << " | " << rate(m.row(0), true) << " | " << rate(m.row(1), true) << " | "
        << rate(m.row(2), true) << " | " << rate(m.row(3), false) << " | " << rate(m.row(4), false)
        << " | " << m.scoredRays() << " |\n";
  }

  out << "\n## Confusion matrices (all scenes)\n";
  for (const std::string& config : configs) {
    const ConfusionMatrix& m = totals[config];
    out << "\n### " << config << "\n\n"
        << m.scans() << " scans, " << m.scoredRays() << " scored rays, "
        << m.excludedNoReturnTruth() << " beams without a true echo excluded";
    if (m.invalidBeams()) out << ", " << m.invalidBeams() << " beams with invalid values skipped";
    out << ".\n\n" << m.toMarkdownTable();
  }

  out << "\n## Per scene\n\nKept (%) per true class; motion and reflection columns give the removed"
         " (%) share.\n\n"
      << "| Scene | Configuration | Diffuse kept | Glass kept | Metal kept | Motion removed | "
         "Reflection removed | Rays (diffuse/glass/metal/motion/reflection) |\n"
      << "|---|---|---:|---:|---:|---:|---:|---|\n";
  for (const EvaluationEntry* entry : by_scene) {
    const ConfusionMatrix& m = entry->matrix;
    out << "| " << entry->scene << " | " << entry->config << " | " << rate(m.row(0), true) << " | "
        << rate(m.row(1), true) << " | " << rate(m.row(2), true) << " | " << rate(m.row(3), false)
        << " | " << rate(m.row(4), false) << " | " << m.row(0).total << "/" << m.row(1).total << "/"
        << m.row(2).total << "/" << m.row(3).total << "/" << m.row(4).total << " |\n";
  }

  std::map<std::string, CellConfusion> cells;
  for (const EvaluationEntry& entry : entries)
    if (entry.cells) cells[entry.config].merge(*entry.cells);
  if (!cells.empty()) {
    out << "\n## Class metrics (cells)\n\nThe class drawn in classes.pgm at every cell a true "
           "surface passes through, against its material, summed over the scenes that have it "
           "(see doc/simulator.md for the definitions).\n";
    for (const std::string& config : configs) {
      if (!cells.count(config)) continue;
      out << "\n### " << config << "\n\n" << cells[config].toMarkdown();
    }
    out << "\n### Per scene\n\n| Scene | Configuration | " << CellConfusion::kSummaryColumnNames
        << " |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const EvaluationEntry* entry : by_scene)
      if (entry->cells)
        out << "| " << entry->scene << " | " << entry->config << " | "
            << entry->cells->summaryColumns() << " |\n";
  }
  return out.str();
}

}  // namespace rfm::sim
