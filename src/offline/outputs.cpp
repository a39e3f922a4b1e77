#include "reflectance_field_map/offline/outputs.h"

#include "json_writer.h"

#include "reflectance_field_map/RayLabels.h"

#include <rosbag/bag.h>
#include <rosbag/exceptions.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rfm {
namespace offline {
namespace {

constexpr uint8_t kPgmOccupied = 0;
constexpr uint8_t kPgmFree = 254;
constexpr uint8_t kPgmUnknown = 205;

uint8_t pgmValue(CellClass c) {
  const int8_t occupancy = occupancyValue(c);
  if (occupancy < 0) return kPgmUnknown;
  return occupancy >= 100 ? kPgmOccupied : kPgmFree;
}

std::string fileName(const std::string& path) {
  return std::filesystem::path(path).filename().string();
}

void checkStream(const std::ofstream& out, const std::string& path) {
  if (!out) throw OutputError("cannot write " + path);
}

// The cells map.pgm and classes.pgm cover: the map's bounds, or one unknown cell at the origin
// when the map is empty.
CellBox pictureBox(const GlobalMap2D& map) {
  const CellBox box = map.bounds();
  return box.empty() ? CellBox{CellIndex(0, 0), CellIndex(1, 1)} : box;
}

// P5 picture of `box`, maxval 255, one byte per cell from value_of, top row = highest y.
template <typename ValueOf>
void writeCellPgm(const std::string& path, const std::string& comment, const CellBox& box,
                  const GlobalMap2D& map, ValueOf value_of) {
  std::vector<CellClass> cells;
  map.extract(box, cells);
  const int width = box.width(), height = box.height();
  std::ofstream out(path, std::ios::binary);
  checkStream(out, path);
  out << "P5\n# " << comment << "\n" << width << ' ' << height << "\n255\n";
  std::vector<uint8_t> row(static_cast<size_t>(width));
  for (int y = height - 1; y >= 0; --y) {  // PGM rows run top down, the map's y up
    const CellClass* cell = &cells[static_cast<size_t>(y) * static_cast<size_t>(width)];
    for (int x = 0; x < width; ++x)
      row[static_cast<size_t>(x)] = value_of(cell[x]);
    out.write(reinterpret_cast<const char*>(row.data()), static_cast<std::streamsize>(width));
  }
  checkStream(out, path);
}

}  // namespace

void makeOutputDirectory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec || !std::filesystem::is_directory(dir)) {
    throw OutputError("cannot create output directory " + dir +
                      (ec ? ": " + ec.message() : ": a file of that name exists"));
  }
}

uint8_t classCode(CellClass c) {
  switch (c) {
    case CellClass::kUnknown:
      return kClassCodeUnknown;
    case CellClass::kFree:
      return kClassCodeFree;
    case CellClass::kStatic:
    case CellClass::kOccupied:  // an obstacle no rule classified: the plain grid's walls
      return kClassCodeStatic;
    case CellClass::kGlass:
      return kClassCodeGlass;
    case CellClass::kMetal:
      return kClassCodeMetal;
    case CellClass::kMotion:
      return kClassCodeMotion;
  }
  return kClassCodeUnknown;
}

void writeMapServerFiles(const std::string& dir, const std::string& stem, const GlobalMap2D& map,
                         double resolution) {
  const CellBox box = pictureBox(map);
  const std::string pgm_path = (std::filesystem::path(dir) / (stem + ".pgm")).string();
  writeCellPgm(pgm_path, "reflectance_field_map rfm_offline", box, map, pgmValue);

  const std::string yaml_path = (std::filesystem::path(dir) / (stem + ".yaml")).string();
  std::ofstream out(yaml_path);
  checkStream(out, yaml_path);
  char origin[128];
  std::snprintf(origin, sizeof(origin), "[%.6f, %.6f, 0.0]", box.min.x() * resolution,
                box.min.y() * resolution);
  char res[32];
  std::snprintf(res, sizeof(res), "%.6f", resolution);
  out << "image: " << fileName(pgm_path) << "\n"
      << "resolution: " << res << "\n"
      << "origin: " << origin << "\n"
      << "negate: 0\n"
      << "occupied_thresh: 0.65\n"
      << "free_thresh: 0.196\n";
  checkStream(out, yaml_path);
}

void writeClassesPgm(const std::string& dir, const GlobalMap2D& map) {
  const std::string path = (std::filesystem::path(dir) / "classes.pgm").string();
  writeCellPgm(path,
               "reflectance_field_map classes: 0 unknown 1 free 2 static 3 glass 4 metal 5 motion",
               pictureBox(map), map, classCode);
}

void writeLabelsBag(const std::string& path, const std::string& topic, const BagScans& input,
                    const std::vector<std::vector<RayLabel>>& labels) {
  if (labels.size() != input.scans.size()) {
    throw OutputError("cannot write " + path + ": " + std::to_string(labels.size()) +
                      " label sets for " + std::to_string(input.scans.size()) + " scans");
  }
  try {
    rosbag::Bag bag;
    bag.open(path, rosbag::bagmode::Write);
    reflectance_field_map::RayLabels msg;
    for (size_t i = 0; i < input.scans.size(); ++i) {
      const ScanSource& source = input.sources[i];
      const std::vector<RayLabel>& scan_labels = labels[i];
      if (scan_labels.size() != input.scans[i].scan.ranges.size()) {
        throw OutputError("cannot write " + path + ": scan " + std::to_string(i) + " has " +
                          std::to_string(input.scans[i].scan.ranges.size()) + " beams but " +
                          std::to_string(scan_labels.size()) + " labels");
      }
      msg.header.seq = source.seq;
      msg.header.stamp = source.stamp;
      msg.header.frame_id = source.frame_id;
      msg.scan_topic = input.topics[source.topic_index];
      msg.labels.resize(scan_labels.size());
      for (size_t b = 0; b < scan_labels.size(); ++b) {
        msg.labels[b] = static_cast<uint8_t>(scan_labels[b]);
      }
      if (source.reversed) std::reverse(msg.labels.begin(), msg.labels.end());
      const ros::Time time = source.bag_time.isZero() ? ros::TIME_MIN : source.bag_time;
      bag.write(topic, time, msg);
    }
    bag.close();
  } catch (const rosbag::BagException& e) {
    throw OutputError("cannot write " + path + ": " + e.what());
  }
}

std::map<std::string, uint64_t> countLabels(const std::vector<std::vector<RayLabel>>& labels) {
  uint64_t counts[4] = {0, 0, 0, 0};
  for (const auto& scan : labels) {
    for (const RayLabel label : scan) {
      const auto index = static_cast<size_t>(label);
      if (index < 4) ++counts[index];
    }
  }
  return {{"no_return", counts[0]},
          {"kept", counts[1]},
          {"motion", counts[2]},
          {"reflection", counts[3]}};
}

std::map<std::string, uint64_t> countClasses(const GlobalMap2D& map) {
  std::map<std::string, uint64_t> counts;
  for (int c = 0; c <= static_cast<int>(CellClass::kOccupied); ++c) {
    counts[toString(static_cast<CellClass>(c))] = 0;
  }
  const CellBox box = map.bounds();
  if (box.empty()) return counts;
  std::vector<CellClass> cells;
  map.extract(box, cells);
  for (const CellClass c : cells)
    ++counts[toString(c)];
  return counts;
}

void writeSummaryJson(const std::string& path, const RunSummary& summary) {
  std::ofstream out(path);
  checkStream(out, path);
  JsonWriter json(out);
  const BagScans& input = *summary.input;
  const BatchResult& result = *summary.result;
  const MapperOptions& options = *summary.options;

  json.beginObject();
  json.key("bag").value(summary.bag);
  json.key("mode").value(summary.mode);
  json.key("batch_mode").value(summary.batch_mode);
  json.key("fixed_frame").value(summary.fixed_frame);
  json.key("base_frame").value(summary.base_frame);

  uint64_t rays = 0;
  for (const TimedScan& scan : input.scans)
    rays += scan.scan.ranges.size();
  json.key("scans").beginObject();
  json.key("total").value(static_cast<uint64_t>(input.scans.size()));
  json.key("per_topic").beginObject();
  for (size_t t = 0; t < input.topics.size(); ++t) {
    json.key(input.topics[t]).value(input.scans_per_topic[t]);
  }
  json.endObject();
  json.key("read").value(input.scansRead());
  // Scans read but not mapped: per topic and reason (BagInputOptions' reasons).
  json.key("skipped").beginObject();
  json.key("total").value(input.scansSkipped());
  json.key("per_topic").beginObject();
  for (size_t t = 0; t < input.topics.size(); ++t) {
    json.key(input.topics[t]).beginObject();
    for (const auto& [reason, tally] : input.skipped) {
      if (tally.per_topic[t] > 0) json.key(reason).value(tally.per_topic[t]);
    }
    json.endObject();
  }
  json.endObject();
  json.key("per_reason").beginObject();
  for (const auto& [reason, tally] : input.skipped)
    json.key(reason).value(tally.total);
  json.endObject();
  json.endObject();
  json.key("missing_topics").beginArray();
  for (const std::string& topic : input.missing_topics)
    json.value(topic);
  json.endArray();
  json.key("tf_messages").value(input.tf_messages);
  json.endObject();
  json.key("rays").value(rays);
  json.key("labels").beginObject();
  for (const auto& [name, count] : countLabels(result.labels))
    json.key(name).value(count);
  json.endObject();

  json.key("timing").beginObject();
  json.key("recording_s").value(input.duration);
  json.key("wall_s").value(summary.wall_seconds);
  json.key("real_time_factor")
      .value(summary.wall_seconds > 0.0 ? input.duration / summary.wall_seconds : 0.0);
  json.key("scans_per_s")
      .value(summary.wall_seconds > 0.0
                 ? static_cast<double>(input.scans.size()) / summary.wall_seconds
                 : 0.0);
  json.key("stages_s").beginObject();
  for (const auto& [stage, seconds] : summary.stage_seconds)
    json.key(stage).value(seconds);
  json.endObject();
  json.key("batch_ms").beginObject();
  json.key("insert").value(result.timings.insert_ms);
  json.key("motion_removal").value(result.timings.motion_removal_ms);
  json.key("reflection_removal").value(result.timings.reflection_removal_ms);
  json.key("labelling").value(result.timings.labelling_ms);
  json.endObject();
  json.key("reflection_iterations").value(result.timings.reflection_iterations);
  json.key("reflection_converged").value(result.timings.reflection_converged);
  json.endObject();

  const CellBox box = result.map.bounds();
  const double res = options.grid.resolution;
  json.key("map").beginObject();
  json.key("width").value(box.empty() ? 0 : box.width());
  json.key("height").value(box.empty() ? 0 : box.height());
  json.key("resolution").value(res);
  json.key("origin").beginArray().value(box.min.x() * res).value(box.min.y() * res).endArray();
  json.key("size_m").beginArray();
  json.value(box.empty() ? 0.0 : box.width() * res).value(box.empty() ? 0.0 : box.height() * res);
  json.endArray();
  json.key("bytes").value(static_cast<uint64_t>(result.map.bytes()));
  json.key("cells").beginObject();
  for (const auto& [name, count] : countClasses(result.map))
    json.key(name).value(count);
  json.endObject();
  json.endObject();

  json.key("parameters").beginObject();
  auto write_parameters = [&json](const std::vector<OptionField>& table, const auto& values) {
    for (const OptionField& field : table) {
      const double value = getOption(values, field.name);
      if (field.type == OptionField::Type::kDouble) {
        json.key(field.name).value(value);
      } else if (field.type == OptionField::Type::kBool) {
        json.key(field.name).value(value != 0.0);
      } else {
        json.key(field.name).value(static_cast<int64_t>(std::llround(value)));
      }
    }
  };
  write_parameters(optionFields(), options);
  write_parameters(batchOptionFields(), *summary.batch);
  json.endObject();

  json.key("notes").beginArray();
  for (const std::string& note : input.notes)
    json.value(note);
  json.endArray();
  json.key("files").beginArray();
  for (const std::string& file : summary.files)
    json.value(file);
  json.endArray();
  json.endObject();
  checkStream(out, path);
}

}  // namespace offline
}  // namespace rfm
