#include "reflectance_field_map/sim/cell_evaluation.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace rfm::sim {
namespace {

constexpr int kMaxSide = 100000;
constexpr std::array<MapClass, 3> kScoredDrawn = {MapClass::kGlass, MapClass::kMetal,
                                                  MapClass::kStatic};

bool isObstacle(std::uint8_t code) {
  return code == static_cast<std::uint8_t>(MapClass::kStatic) ||
         code == static_cast<std::uint8_t>(MapClass::kGlass) ||
         code == static_cast<std::uint8_t>(MapClass::kMetal);
}

// Surface bits a drawn obstacle class stands for.
std::uint8_t acceptedBits(MapClass drawn) {
  switch (drawn) {
    case MapClass::kGlass:
      return kGlassBit | kMirrorBit;
    case MapClass::kMetal:
      return kMetalBit | kMirrorBit;
    case MapClass::kStatic:
      return kDiffuseBit;
    default:
      return 0;
  }
}

SurfaceRow rowOf(std::uint8_t bits) {
  switch (bits) {
    case kDiffuseBit:
      return SurfaceRow::kWall;
    case kGlassBit:
      return SurfaceRow::kGlass;
    case kMetalBit:
      return SurfaceRow::kMetal;
    case kMirrorBit:
      return SurfaceRow::kMirror;
    default:
      return SurfaceRow::kMixed;
  }
}

// Whether drawing `code` is right for a cell of true materials `bits`.
bool matches(std::uint8_t code, std::uint8_t bits) {
  return isObstacle(code) && (acceptedBits(static_cast<MapClass>(code)) & bits) != 0;
}

std::string percent(double value) {
  if (value < 0.0) return "-";
  std::ostringstream out;
  out << std::fixed << std::setprecision(1) << value;
  return out.str();
}

double ratio(std::uint64_t part, std::uint64_t whole) {
  return whole ? 100.0 * static_cast<double>(part) / static_cast<double>(whole) : -1.0;
}

std::string readAll(const std::string& path, std::ios::openmode mode = std::ios::in) {
  std::ifstream file(path, mode);
  if (!file) throw std::runtime_error("cannot read '" + path + "'");
  std::ostringstream contents;
  contents << file.rdbuf();
  return contents.str();
}

// Reads the next whitespace-separated header token of a PGM, skipping '#' comments.
std::string headerToken(const std::string& bytes, std::size_t& position) {
  while (position < bytes.size()) {
    const char c = bytes[position];
    if (c == '#') {
      while (position < bytes.size() && bytes[position] != '\n')
        ++position;
    } else if (std::isspace(static_cast<unsigned char>(c))) {
      ++position;
    } else {
      break;
    }
  }
  std::string token;
  while (position < bytes.size() && !std::isspace(static_cast<unsigned char>(bytes[position])) &&
         token.size() < 16) {
    token += bytes[position++];
  }
  return token;
}

int headerNumber(const std::string& token, const std::string& what, const std::string& source) {
  if (token.empty() || token.size() > 6 ||
      !std::all_of(token.begin(), token.end(), [](char c) { return c >= '0' && c <= '9'; })) {
    throw std::runtime_error(source + ": bad PGM " + what + " '" + token + "'");
  }
  return std::stoi(token);
}

std::uint64_t readCount(const YAML::Node& node, const std::string& key) {
  if (!node[key]) throw std::runtime_error("cell evaluation JSON: missing '" + key + "'");
  return node[key].as<std::uint64_t>();
}

const char* const kDrawnKeys[3] = {"glass", "metal", "static"};

}  // namespace

const char* mapClassName(MapClass map_class) {
  switch (map_class) {
    case MapClass::kUnknown:
      return "unknown";
    case MapClass::kFree:
      return "free";
    case MapClass::kStatic:
      return "static";
    case MapClass::kGlass:
      return "glass";
    case MapClass::kMetal:
      return "metal";
    case MapClass::kMotion:
      return "motion";
  }
  return "invalid";
}

const char* surfaceRowName(SurfaceRow row) {
  switch (row) {
    case SurfaceRow::kWall:
      return "wall";
    case SurfaceRow::kGlass:
      return "glass";
    case SurfaceRow::kMetal:
      return "metal";
    case SurfaceRow::kMirror:
      return "mirror";
    case SurfaceRow::kMixed:
      return "mixed";
  }
  return "invalid";
}

ClassGrid parseClassPgm(const std::string& bytes, double resolution, const Eigen::Vector2d& origin,
                        const std::string& source) {
  std::size_t position = 0;
  if (headerToken(bytes, position) != "P5") {
    throw std::runtime_error(source + ": not a binary PGM (P5)");
  }
  ClassGrid grid;
  grid.width = headerNumber(headerToken(bytes, position), "width", source);
  grid.height = headerNumber(headerToken(bytes, position), "height", source);
  const int max_value = headerNumber(headerToken(bytes, position), "maxval", source);
  if (grid.width < 1 || grid.height < 1 || grid.width > kMaxSide || grid.height > kMaxSide) {
    throw std::runtime_error(source + ": PGM size " + std::to_string(grid.width) + " x " +
                             std::to_string(grid.height) + " out of range");
  }
  if (max_value != 255) throw std::runtime_error(source + ": PGM maxval must be 255");
  ++position;  // the single whitespace byte after maxval
  const std::size_t count = static_cast<std::size_t>(grid.width) * grid.height;
  if (position > bytes.size() || bytes.size() - position < count) {
    throw std::runtime_error(source + ": PGM holds fewer than " + std::to_string(count) + " cells");
  }
  if (!(resolution > 0.0) || !std::isfinite(resolution) || !origin.allFinite()) {
    throw std::runtime_error(source + ": resolution and origin must be finite, resolution > 0");
  }
  grid.resolution = resolution;
  grid.origin = origin;
  grid.cells.resize(count);
  for (int row = 0; row < grid.height; ++row) {  // the picture's top row is the map's highest y
    const int y = grid.height - 1 - row;
    for (int x = 0; x < grid.width; ++x) {
      const auto code = static_cast<std::uint8_t>(
          bytes[position + static_cast<std::size_t>(row) * grid.width + x]);
      if (code >= kMapClassCount) {
        throw std::runtime_error(source + ": class code " + std::to_string(code) +
                                 " at picture row " + std::to_string(row) + ", column " +
                                 std::to_string(x) + " (codes are 0-5)");
      }
      grid.cells[static_cast<std::size_t>(y) * grid.width + x] = code;
    }
  }
  return grid;
}

ClassGrid readClassGrid(const std::string& directory) {
  const std::string yaml_path = (std::filesystem::path(directory) / "map.yaml").string();
  const std::string pgm_path = (std::filesystem::path(directory) / "classes.pgm").string();
  double resolution = 0.0;
  Eigen::Vector2d origin;
  const std::string yaml_text = readAll(yaml_path);
  try {
    const YAML::Node map = YAML::Load(yaml_text);
    if (!map["resolution"] || !map["origin"] || !map["origin"].IsSequence() ||
        map["origin"].size() < 2) {
      throw std::runtime_error("needs resolution and origin [x, y, yaw]");
    }
    resolution = map["resolution"].as<double>();
    origin = {map["origin"][0].as<double>(), map["origin"][1].as<double>()};
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(yaml_path + ": " + error.what());
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(yaml_path + ": " + error.what());
  }
  return parseClassPgm(readAll(pgm_path, std::ios::binary), resolution, origin, pgm_path);
}

std::vector<std::uint8_t> rasterizeSurfaces(const World& world, const ClassGrid& grid) {
  std::vector<std::uint8_t> bits(static_cast<std::size_t>(grid.width) * grid.height, 0);
  const double step = grid.resolution / 16.0;  // fine enough to meet every cell a surface crosses
  auto mark = [&](const Eigen::Vector2d& p, Material material) {
    const Eigen::Vector2d cell = (p - grid.origin) / grid.resolution;
    const int x = static_cast<int>(std::floor(cell.x())),
              y = static_cast<int>(std::floor(cell.y()));
    if (x < 0 || y < 0 || x >= grid.width || y >= grid.height) return;
    const std::uint8_t bit = material == Material::kDiffuse ? kDiffuseBit
                             : material == Material::kGlass ? kGlassBit
                             : material == Material::kMetal ? kMetalBit
                                                            : kMirrorBit;
    bits[static_cast<std::size_t>(y) * grid.width + x] |= bit;
  };
  for (const World::SegmentPrimitive& segment : world.segments()) {
    const int samples =
        std::max(1, static_cast<int>(std::ceil((segment.b - segment.a).norm() / step)));
    for (int i = 0; i <= samples; ++i)
      mark(segment.a + (segment.b - segment.a) * (static_cast<double>(i) / samples),
           segment.material);
  }
  for (const World::ArcPrimitive& arc : world.arcs()) {
    const int samples = std::max(1, static_cast<int>(std::ceil(arc.radius * arc.sweep / step)));
    for (int i = 0; i <= samples; ++i) {
      const double angle = arc.start_angle + arc.sweep * i / samples;
      mark(arc.center + arc.radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)),
           arc.material);
    }
  }
  return bits;
}

std::string surfacesPgm(const ClassGrid& grid, const std::vector<std::uint8_t>& truth) {
  const std::size_t width = static_cast<std::size_t>(grid.width);
  if (truth.size() != width * static_cast<std::size_t>(grid.height)) {
    throw std::invalid_argument("truth has " + std::to_string(truth.size()) + " cells, the map " +
                                std::to_string(width * grid.height));
  }
  std::string pgm =
      "P5\n# true materials per cell: 1 diffuse, 2 glass, 4 metal, 8 mirror (bits)\n" +
      std::to_string(grid.width) + " " + std::to_string(grid.height) + "\n255\n";
  for (int y = grid.height - 1; y >= 0; --y) {  // the picture's top row is the map's highest y
    const auto row = truth.begin() + static_cast<std::ptrdiff_t>(y * width);
    pgm.append(row, row + static_cast<std::ptrdiff_t>(width));
  }
  return pgm;
}

CellConfusion CellConfusion::evaluate(const ClassGrid& classes,
                                      const std::vector<std::uint8_t>& truth, int tolerance) {
  if (truth.size() != classes.cells.size()) {
    throw std::invalid_argument("truth has " + std::to_string(truth.size()) + " cells, the map " +
                                std::to_string(classes.cells.size()));
  }
  if (tolerance < 0) throw std::invalid_argument("tolerance must not be negative");
  CellConfusion result;
  const int w = classes.width, h = classes.height;
  auto forNeighbours = [&](int x, int y, auto visit) {
    for (int ny = std::max(0, y - tolerance); ny <= std::min(h - 1, y + tolerance); ++ny)
      for (int nx = std::max(0, x - tolerance); nx <= std::min(w - 1, x + tolerance); ++nx)
        visit(nx, ny);
  };
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      const std::size_t index = static_cast<std::size_t>(y) * w + x;
      const std::uint8_t own = classes.cells[index];
      // The drawn side: is a surface this class stands for within reach?
      const int scored = drawnIndex(static_cast<MapClass>(own));
      if (scored >= 0) {
        ++result.drawn_[scored];
        bool right = false;
        forNeighbours(x, y, [&](int nx, int ny) {
          right = right || (acceptedBits(static_cast<MapClass>(own)) &
                            truth[static_cast<std::size_t>(ny) * w + nx]) != 0;
        });
        if (right) ++result.drawn_right_[scored];
      }
      // The true side: what does the map draw where a surface is?
      const std::uint8_t bits = truth[index];
      if (!bits) continue;
      const int row = static_cast<int>(rowOf(bits));
      bool observed = false, matched = false;
      std::array<int, kMapClassCount> obstacles{};
      forNeighbours(x, y, [&](int nx, int ny) {
        const std::uint8_t code = classes.cells[static_cast<std::size_t>(ny) * w + nx];
        observed = observed || code != static_cast<std::uint8_t>(MapClass::kUnknown);
        if (!isObstacle(code)) return;
        ++obstacles[code];
        if (matches(code, bits)) matched = true;
      });
      if (!observed) {
        ++result.unobserved_[row];
        continue;
      }
      std::uint8_t drawn = own;
      if (matched && !matches(own, bits)) {  // the true class is drawn nearby
        for (const MapClass candidate : kScoredDrawn) {
          const auto code = static_cast<std::uint8_t>(candidate);
          if (obstacles[code] && matches(code, bits)) {
            drawn = code;
            break;
          }
        }
      } else if (!matched && !isObstacle(own)) {  // the commonest obstacle nearby, if any
        int most = 0;
        for (const MapClass candidate : kScoredDrawn) {
          const auto code = static_cast<std::uint8_t>(candidate);
          if (obstacles[code] > most) {
            most = obstacles[code];
            drawn = code;
          }
        }
      }
      ++result.counts_[row][drawn];
    }
  }
  return result;
}

int CellConfusion::drawnIndex(MapClass drawn) {
  for (int i = 0; i < 3; ++i)
    if (kScoredDrawn[i] == drawn) return i;
  return -1;
}

void CellConfusion::merge(const CellConfusion& other) {
  for (int r = 0; r < kSurfaceRowCount; ++r) {
    for (int c = 0; c < kMapClassCount; ++c)
      counts_[r][c] += other.counts_[r][c];
    unobserved_[r] += other.unobserved_[r];
  }
  for (int i = 0; i < 3; ++i) {
    drawn_[i] += other.drawn_[i];
    drawn_right_[i] += other.drawn_right_[i];
  }
}

std::uint64_t CellConfusion::rowTotal(SurfaceRow row) const {
  std::uint64_t total = 0;
  for (const std::uint64_t count : counts_[static_cast<int>(row)])
    total += count;
  return total;
}

std::uint64_t CellConfusion::drawn(MapClass drawn) const {
  const int index = drawnIndex(drawn);
  return index < 0 ? 0 : drawn_[index];
}

std::uint64_t CellConfusion::drawnRight(MapClass drawn) const {
  const int index = drawnIndex(drawn);
  return index < 0 ? 0 : drawn_right_[index];
}

double CellConfusion::precision(MapClass drawn) const {
  return ratio(drawnRight(drawn), this->drawn(drawn));
}

double CellConfusion::recall(MapClass drawn) const {
  const SurfaceRow row = drawn == MapClass::kGlass   ? SurfaceRow::kGlass
                         : drawn == MapClass::kMetal ? SurfaceRow::kMetal
                                                     : SurfaceRow::kWall;
  return ratio(count(row, drawn), rowTotal(row));
}

double CellConfusion::wallsDrawnSpecular() const {
  return ratio(
      count(SurfaceRow::kWall, MapClass::kGlass) + count(SurfaceRow::kWall, MapClass::kMetal),
      rowTotal(SurfaceRow::kWall));
}

double CellConfusion::mirrorsDrawnSpecular() const {
  return ratio(
      count(SurfaceRow::kMirror, MapClass::kGlass) + count(SurfaceRow::kMirror, MapClass::kMetal),
      rowTotal(SurfaceRow::kMirror));
}

const char* const CellConfusion::kSummaryColumnNames =
    "glass P | glass R | metal P | metal R | static P | static R | walls drawn glass/metal";

std::string CellConfusion::summaryColumns() const {
  std::string columns;
  for (const MapClass drawn : {MapClass::kGlass, MapClass::kMetal, MapClass::kStatic})
    columns += percent(precision(drawn)) + " | " + percent(recall(drawn)) + " | ";
  return columns + percent(wallsDrawnSpecular());
}

std::string CellConfusion::toMarkdown() const {
  std::ostringstream out;
  out << "| drawn class | precision (%) | recall (%) | cells drawn | true cells |\n"
      << "|---|---:|---:|---:|---:|\n";
  for (const MapClass drawn : kScoredDrawn) {
    const SurfaceRow row = drawn == MapClass::kGlass   ? SurfaceRow::kGlass
                           : drawn == MapClass::kMetal ? SurfaceRow::kMetal
                                                       : SurfaceRow::kWall;
    out << "| " << mapClassName(drawn) << " | " << percent(precision(drawn)) << " | "
        << percent(recall(drawn)) << " | " << this->drawn(drawn) << " | " << rowTotal(row)
        << " |\n";
  }
  out << "\nWall cells drawn glass or metal: " << percent(wallsDrawnSpecular())
      << " %; mirror cells drawn glass or metal: " << percent(mirrorsDrawnSpecular()) << " %.\n\n"
      << "| true surface | static | glass | metal | motion | free | unknown | not observed |\n"
      << "|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (int r = 0; r < kSurfaceRowCount; ++r) {
    const auto row = static_cast<SurfaceRow>(r);
    out << "| " << surfaceRowName(row);
    for (const MapClass drawn : {MapClass::kStatic, MapClass::kGlass, MapClass::kMetal,
                                 MapClass::kMotion, MapClass::kFree, MapClass::kUnknown}) {
      out << " | " << count(row, drawn);
    }
    out << " | " << unobserved(row) << " |\n";
  }
  return out.str();
}

std::string CellConfusion::toJson() const {
  std::ostringstream out;
  out << "{\"rows\": {";
  for (int r = 0; r < kSurfaceRowCount; ++r) {
    out << (r ? ", " : "") << "\"" << surfaceRowName(static_cast<SurfaceRow>(r)) << "\": {";
    for (int c = 0; c < kMapClassCount; ++c) {
      out << "\"" << mapClassName(static_cast<MapClass>(c)) << "\": " << counts_[r][c] << ", ";
    }
    out << "\"not_observed\": " << unobserved_[r] << "}";
  }
  out << "}, \"drawn\": {";
  for (int i = 0; i < 3; ++i) {
    out << (i ? ", " : "") << "\"" << kDrawnKeys[i] << "\": {\"cells\": " << drawn_[i]
        << ", \"right\": " << drawn_right_[i] << "}";
  }
  out << "}}";
  return out.str();
}

CellConfusion CellConfusion::fromJson(const std::string& json_text) {
  CellConfusion result;
  try {
    const YAML::Node root = YAML::Load(json_text);
    const YAML::Node rows = root["rows"];
    const YAML::Node drawn = root["drawn"];
    if (!rows || !rows.IsMap() || !drawn || !drawn.IsMap()) {
      throw std::runtime_error("cell evaluation JSON: needs 'rows' and 'drawn'");
    }
    for (int r = 0; r < kSurfaceRowCount; ++r) {
      const YAML::Node row = rows[surfaceRowName(static_cast<SurfaceRow>(r))];
      if (!row) throw std::runtime_error("cell evaluation JSON: a row is missing");
      for (int c = 0; c < kMapClassCount; ++c)
        result.counts_[r][c] = readCount(row, mapClassName(static_cast<MapClass>(c)));
      result.unobserved_[r] = readCount(row, "not_observed");
    }
    for (int i = 0; i < 3; ++i) {
      const YAML::Node entry = drawn[kDrawnKeys[i]];
      if (!entry) throw std::runtime_error("cell evaluation JSON: a drawn class is missing");
      result.drawn_[i] = readCount(entry, "cells");
      result.drawn_right_[i] = readCount(entry, "right");
      if (result.drawn_right_[i] > result.drawn_[i]) {
        throw std::runtime_error("cell evaluation JSON: more cells right than drawn");
      }
    }
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("cell evaluation JSON: ") + error.what());
  }
  return result;
}

bool CellConfusion::operator==(const CellConfusion& other) const {
  return counts_ == other.counts_ && unobserved_ == other.unobserved_ && drawn_ == other.drawn_ &&
         drawn_right_ == other.drawn_right_;
}

}  // namespace rfm::sim
