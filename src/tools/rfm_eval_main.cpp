// rfm_eval: scores a mapper's per-beam labels against the simulator's ground truth, and with the
// scene's world the classes its map draws.
//
//   rfm_eval --truth SIM.bag --labels DIR/labels.bag [--out PREFIX]
//            [--scene SCENE.yaml [--map-dir DIR] [--tolerance-cells N] [--truth-cells FILE.pgm]]
//       Matches /rfm/ray_labels to /sim/ray_truth by (scan_topic, header.stamp), prints the
//       confusion matrix and writes PREFIX.md and PREFIX.json (default PREFIX = DIR/eval). With
//       --scene (the file the bag was simulated from; rfm_sim --write-scene writes it for random
//       scenes) it also compares DIR/classes.pgm, placed by DIR/map.yaml, with the world's
//       materials cell by cell (tolerance 1 cell by default); --truth-cells also writes those
//       materials in classes.pgm's layout (rfm::sim::surfacesPgm), for scripts/unseen_glass.py.
//   rfm_eval --report MANIFEST --out REPORT.md [--preamble FILE] [--title TEXT]
//       Aggregates eval.json files listed in MANIFEST (lines: "config scene path/eval.json", or
//       "config scene path/eval.json setup split" for a report grouped by sensor setup and seed
//       split) into one markdown report.
#include <reflectance_field_map/RayLabels.h>
#include <reflectance_field_map/RayTruth.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <yaml-cpp/yaml.h>

#include <optional>
#include <set>

#include "reflectance_field_map/sim/cell_evaluation.h"
#include "reflectance_field_map/sim/evaluation.h"
#include "reflectance_field_map/sim/scene.h"

namespace {

const char* const kTruthTopic = "/sim/ray_truth";
const char* const kLabelsTopic = "/rfm/ray_labels";

void printUsage(std::ostream& out) {
  out << "usage: rfm_eval --truth SIM.bag --labels DIR/labels.bag [--out PREFIX]\n"
         "                [--scene SCENE.yaml [--map-dir DIR] [--tolerance-cells N]\n"
         "                 [--truth-cells FILE.pgm]]\n"
         "       rfm_eval --report MANIFEST --out REPORT.md [--preamble FILE] [--title TEXT]\n";
}

std::string readFile(const std::string& path) {
  std::ifstream file(path);
  if (!file) throw std::runtime_error("cannot read '" + path + "'");
  std::ostringstream contents;
  contents << file.rdbuf();
  return contents.str();
}

void writeFile(const std::string& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
  if (!file) throw std::runtime_error("cannot write '" + path + "'");
}

std::string directoryOf(const std::string& path) {
  const std::size_t slash = path.find_last_of('/');
  return slash == std::string::npos ? "." : path.substr(0, slash);
}

using ScanKey = std::pair<std::string, std::uint64_t>;  // (scan_topic, stamp in ns)

struct CellOptions {
  std::string scene_path;  // empty: no class metrics
  std::string map_dir;
  int tolerance = 1;
  std::string truth_cells_path;  // empty: the true materials are not written
};

// The class metrics of the map in `options.map_dir` against the scene's world. The scene must be
// the one the bag was simulated from: its lidars' topics must be the truth's.
rfm::sim::CellConfusion evaluateCells(const CellOptions& options,
                                      const std::set<std::string>& truth_topics) {
  const rfm::sim::Scene scene = rfm::sim::loadScene(options.scene_path);
  std::set<std::string> scene_topics;
  for (const rfm::sim::LidarSpec& lidar : scene.lidars)
    scene_topics.insert(lidar.topic);
  for (const std::string& topic : truth_topics) {
    if (!scene_topics.count(topic)) {
      throw std::runtime_error("the truth bag has scans on " + topic + ", which scene '" +
                               options.scene_path + "' has no lidar for: not this bag's scene?");
    }
  }
  const rfm::sim::ClassGrid classes = rfm::sim::readClassGrid(options.map_dir);
  const std::vector<std::uint8_t> truth = rfm::sim::rasterizeSurfaces(scene.world, classes);
  if (!options.truth_cells_path.empty()) {
    writeFile(options.truth_cells_path, rfm::sim::surfacesPgm(classes, truth));
  }
  return rfm::sim::CellConfusion::evaluate(classes, truth, options.tolerance);
}

// eval.json: the ray confusion matrix's object, with the class metrics under "cells".
std::string evaluationJson(const rfm::sim::ConfusionMatrix& matrix,
                           const std::optional<rfm::sim::CellConfusion>& cells) {
  std::string json = matrix.toJson();
  if (!cells) return json;
  const std::size_t close = json.rfind('}');
  return json.substr(0, close) + ",\"cells\": " + cells->toJson() + "\n}\n";
}

int evaluate(const std::string& truth_path, const std::string& labels_path,
             const std::string& prefix, const CellOptions& cell_options) {
  std::map<ScanKey, std::vector<std::uint8_t>> truth_by_scan;
  std::set<std::string> truth_topics;
  std::size_t duplicate_truth = 0;
  {
    rosbag::Bag bag(truth_path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(kTruthTopic));
    for (const rosbag::MessageInstance& instance : view) {
      const auto truth = instance.instantiate<reflectance_field_map::RayTruth>();
      if (!truth) continue;
      const ScanKey key{truth->scan_topic, truth->header.stamp.toNSec()};
      truth_topics.insert(truth->scan_topic);
      if (!truth_by_scan.emplace(key, truth->classes).second) ++duplicate_truth;
    }
  }
  if (truth_by_scan.empty()) {
    std::cerr << "rfm_eval: no " << kTruthTopic << " messages in '" << truth_path << "'\n";
    return 1;
  }

  rfm::sim::ConfusionMatrix matrix;
  std::size_t label_messages = 0, unmatched_labels = 0;
  std::map<ScanKey, bool> matched;
  {
    rosbag::Bag bag(labels_path, rosbag::bagmode::Read);
    rosbag::View view(bag, rosbag::TopicQuery(kLabelsTopic));
    for (const rosbag::MessageInstance& instance : view) {
      const auto labels = instance.instantiate<reflectance_field_map::RayLabels>();
      if (!labels) continue;
      ++label_messages;
      const ScanKey key{labels->scan_topic, labels->header.stamp.toNSec()};
      const auto truth = truth_by_scan.find(key);
      if (truth == truth_by_scan.end() || matched[key]) {
        ++unmatched_labels;
        continue;
      }
      if (truth->second.size() != labels->labels.size()) {
        std::cerr << "rfm_eval: beam count mismatch for " << key.first << " at stamp "
                  << labels->header.stamp << ": truth " << truth->second.size() << ", labels "
                  << labels->labels.size() << "\n";
        return 1;
      }
      matrix.addScan(truth->second, labels->labels);
      matched[key] = true;
    }
  }
  const std::size_t unmatched_truth = truth_by_scan.size() - matrix.scans();
  if (matrix.scans() == 0) {
    std::cerr << "rfm_eval: no label message matches a truth message (" << label_messages << " on "
              << kLabelsTopic << " in '" << labels_path << "', " << truth_by_scan.size()
              << " truth scans)\n";
    return 1;
  }

  std::ostringstream summary;
  summary << "Truth: `" << truth_path << "`, labels: `" << labels_path << "`.\n\n"
          << matrix.scans() << " scans matched; " << unmatched_truth
          << " truth scans without labels; " << unmatched_labels
          << " label messages without truth (or duplicates)";
  if (duplicate_truth) summary << "; " << duplicate_truth << " duplicate truth messages ignored";
  summary << ".\n\n";
  if (matrix.noReturnMislabelled() * 100 > matrix.excludedNoReturnTruth()) {
    summary << "**Warning**: " << matrix.noReturnMislabelled() << " of "
            << matrix.excludedNoReturnTruth()
            << " beams without an echo are not labelled NO_RETURN: are these labels from this "
               "truth bag?\n\n";
  }
  std::string markdown = "# Ray classification\n\n" + summary.str() + matrix.toMarkdownTable();
  std::optional<rfm::sim::CellConfusion> cells;
  if (!cell_options.scene_path.empty()) {
    cells = evaluateCells(cell_options, truth_topics);
    markdown += "\n# Class metrics\n\nScene `" + cell_options.scene_path + "`, map `" +
                cell_options.map_dir + "/classes.pgm`, tolerance " +
                std::to_string(cell_options.tolerance) + " cell(s).\n\n" + cells->toMarkdown();
  }
  std::cout << markdown;
  writeFile(prefix + ".md", markdown);
  writeFile(prefix + ".json", evaluationJson(matrix, cells));
  std::cout << "\nwrote " << prefix << ".md and " << prefix << ".json\n";
  return 0;
}

int report(const std::string& manifest_path, const std::string& out_path,
           const std::string& preamble_path, const std::string& title) {
  std::vector<rfm::sim::EvaluationEntry> entries;
  std::istringstream manifest(readFile(manifest_path));
  std::string line;
  int line_number = 0;
  while (std::getline(manifest, line)) {
    ++line_number;
    if (line.empty() || line[0] == '#') continue;
    std::istringstream fields(line);
    rfm::sim::EvaluationEntry entry;
    std::string json_path;
    if (!(fields >> entry.config >> entry.scene >> json_path)) {
      throw std::runtime_error(manifest_path + ":" + std::to_string(line_number) +
                               ": expected 'config scene path/eval.json [setup split]'");
    }
    if ((fields >> entry.setup) && !(fields >> entry.split)) {
      throw std::runtime_error(manifest_path + ":" + std::to_string(line_number) +
                               ": a setup needs its seed split after it");
    }
    try {
      const std::string json = readFile(json_path);
      entry.matrix = rfm::sim::ConfusionMatrix::fromJson(json);
      const YAML::Node cells = YAML::Load(json)["cells"];
      if (cells) entry.cells = rfm::sim::CellConfusion::fromJson(YAML::Dump(cells));
    } catch (const YAML::Exception& error) {
      throw std::runtime_error(json_path + ": " + error.what());
    } catch (const std::exception& error) {
      throw std::runtime_error(json_path + ": " + error.what());
    }
    entries.push_back(std::move(entry));
  }
  if (entries.empty()) throw std::runtime_error(manifest_path + ": no entries");
  const std::string preamble = preamble_path.empty() ? "" : readFile(preamble_path);
  const bool grouped = !entries.front().setup.empty();
  for (const rfm::sim::EvaluationEntry& entry : entries) {
    if (entry.setup.empty() == grouped) {
      throw std::runtime_error(manifest_path + ": give a setup and split on every line or none");
    }
  }
  writeFile(out_path, grouped ? rfm::sim::buildGroupedReport(entries, title, preamble)
                              : rfm::sim::buildEvaluationReport(entries, preamble));
  std::cout << "rfm_eval: wrote " << out_path << " from " << entries.size() << " results\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::map<std::string, std::string> options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "-h" || arg == "--help") {
      printUsage(std::cout);
      return 0;
    }
    if ((arg == "--truth" || arg == "--labels" || arg == "--out" || arg == "--report" ||
         arg == "--preamble" || arg == "--title" || arg == "--scene" || arg == "--map-dir" ||
         arg == "--tolerance-cells" || arg == "--truth-cells") &&
        i + 1 < argc) {
      options[arg] = argv[++i];
    } else {
      std::cerr << "rfm_eval: unexpected argument '" << arg << "'\n";
      printUsage(std::cerr);
      return 2;
    }
  }
  try {
    if (options.count("--report")) {
      if (!options.count("--out")) {
        std::cerr << "rfm_eval: --report needs --out REPORT.md\n";
        return 2;
      }
      const std::string title = options.count("--title")
                                    ? options["--title"]
                                    : "Random scenes: evaluation per sensor setup";
      return report(options["--report"], options["--out"], options["--preamble"], title);
    }
    if (!options.count("--truth") || !options.count("--labels")) {
      std::cerr << "rfm_eval: --truth and --labels are required\n";
      printUsage(std::cerr);
      return 2;
    }
    const std::string prefix =
        options.count("--out") ? options["--out"] : directoryOf(options["--labels"]) + "/eval";
    CellOptions cell_options;
    cell_options.scene_path = options["--scene"];
    cell_options.map_dir =
        options.count("--map-dir") ? options["--map-dir"] : directoryOf(options["--labels"]);
    if (options.count("--tolerance-cells")) {
      const std::string& text = options["--tolerance-cells"];
      if (text.empty() || text.size() > 2 ||
          text.find_first_not_of("0123456789") != std::string::npos) {
        std::cerr << "rfm_eval: --tolerance-cells must be an integer in [0, 99], got '" << text
                  << "'\n";
        return 2;
      }
      cell_options.tolerance = std::stoi(text);
    }
    if (options.count("--truth-cells")) cell_options.truth_cells_path = options["--truth-cells"];
    if (cell_options.scene_path.empty() &&
        (options.count("--map-dir") || options.count("--tolerance-cells") ||
         options.count("--truth-cells"))) {
      std::cerr << "rfm_eval: --map-dir, --tolerance-cells and --truth-cells need --scene\n";
      return 2;
    }
    return evaluate(options["--truth"], options["--labels"], prefix, cell_options);
  } catch (const rosbag::BagException& error) {
    std::cerr << "rfm_eval: " << error.what() << "\n";
  } catch (const rfm::sim::SceneError& error) {
    std::cerr << "rfm_eval: invalid scene: " << error.what() << "\n";
  } catch (const std::exception& error) {
    std::cerr << "rfm_eval: " << error.what() << "\n";
  }
  return 1;
}
