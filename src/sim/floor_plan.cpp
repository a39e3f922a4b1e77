#include "reflectance_field_map/sim/floor_plan.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>
#include <string>

namespace rfm::sim {
namespace {

using Vec = Eigen::Vector2d;

constexpr double kDoorMargin = 0.5;  // wall kept between a door and a junction or corner, m

struct Box {
  Vec low, high;
  double width() const { return high.x() - low.x(); }
  double height() const { return high.y() - low.y(); }
  double area() const { return width() * height(); }
  Box grown(double margin) const {
    return {low - Vec::Constant(margin), high + Vec::Constant(margin)};
  }
  bool overlaps(const Box& other) const {
    return low.x() < other.high.x() && other.low.x() < high.x() && low.y() < other.high.y() &&
           other.low.y() < high.y();
  }
};

// What fills a stretch of a wall line; the rest of the line is diffuse wall.
struct Insert {
  enum class Kind { kDoor, kGlass, kMetal, kMirror };
  double start, end;
  Kind kind;
  double frame = 0.0, mullion_spacing = 0.0;
};

// An axis-aligned wall from a to b. Other walls end on it at `junctions` (distances from a); a
// bay is the stretch between two junctions, and doors and inserts stay within one bay.
struct Line {
  Vec a, b;
  bool exterior = false;
  bool facade = false;
  bool corridor_front = false;  // every bay needs a door (each opens a room onto the corridor)
  std::vector<double> junctions;
  std::vector<Insert> inserts;

  double length() const { return (b - a).norm(); }
  Vec direction() const { return (b - a) / length(); }
  Vec at(double s) const { return a + s * direction(); }
  std::vector<std::pair<double, double>> bays() const {
    std::vector<double> cuts = junctions;
    cuts.push_back(0.0);
    cuts.push_back(length());
    std::sort(cuts.begin(), cuts.end());
    std::vector<std::pair<double, double>> result;
    for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
      if (cuts[i + 1] - cuts[i] > 1e-6) result.push_back({cuts[i], cuts[i + 1]});
    }
    return result;
  }
  bool free(double start, double end, double margin) const {
    for (const Insert& insert : inserts) {
      if (start < insert.end + margin && insert.start - margin < end) return false;
    }
    return true;
  }
};

class FloorPlanBuilder {
 public:
  explicit FloorPlanBuilder(Dice& dice) : dice_(dice) {}

  FloorPlan build() {
    const bool corridor = dice_.chance(0.45);
    width_ = rounded(dice_.uniform(14.0, 30.0), 10);
    height_ = rounded(dice_.uniform(10.0, 22.0), 10);
    if (corridor && height_ > width_) std::swap(width_, height_);
    addShell();
    if (corridor) {
      buildCorridorLayout();
    } else {
      split({Vec(0, 0), Vec(width_, height_)}, 0);
    }
    placeDoors();
    chooseFacade();
    styleInteriorBays();
    placeWallFeatures();
    emitLines();
    placeRoomFeatures();
    if (facade_line_ >= 0) buildStreet();

    plan_.building_low = Vec(0, 0);
    plan_.building_high = Vec(width_, height_);
    plan_.world_low = plan_.world_low.cwiseMin(plan_.building_low);
    plan_.world_high = plan_.world_high.cwiseMax(plan_.building_high);
    for (const Box& room : rooms_)
      plan_.areas.push_back({room.low, room.high, false});
    std::ostringstream summary;
    summary << (corridor ? "corridor" : "halls") << " building " << width_ << " m x " << height_
            << " m, " << rooms_.size() << " rooms";
    for (const std::string& feature : features_)
      summary << ", " << feature;
    plan_.summary = summary.str();
    return plan_;
  }

 private:
  // --- layout -------------------------------------------------------------------------------

  void addShell() {
    const Vec corners[4] = {Vec(0, 0), Vec(width_, 0), Vec(width_, height_), Vec(0, height_)};
    for (int side = 0; side < 4; ++side) {  // south, east, north, west
      Line line;
      // Lines run in the increasing direction of their axis.
      line.a = corners[side];
      line.b = corners[(side + 1) % 4];
      if (line.b.x() < line.a.x() || line.b.y() < line.a.y()) std::swap(line.a, line.b);
      line.exterior = true;
      lines_.push_back(line);
    }
  }

  // A new wall from a to b, registering where it ends on existing walls.
  int addLine(const Vec& a, const Vec& b, bool corridor_front = false) {
    for (Line& other : lines_) {
      for (const Vec& end : {a, b}) {
        const double along = (end - other.a).dot(other.direction());
        const Vec foot = other.at(along);
        if ((foot - end).norm() < 1e-6 && along > 1e-6 && along < other.length() - 1e-6) {
          other.junctions.push_back(along);
        }
      }
    }
    Line line;
    line.a = a;
    line.b = b;
    line.corridor_front = corridor_front;
    lines_.push_back(line);
    return static_cast<int>(lines_.size()) - 1;
  }

  void split(const Box& box, int depth) {
    const double area = box.area();
    const bool small = std::max(box.width(), box.height()) < 7.0;
    if (depth >= 4 || small || (area < 45.0 && dice_.chance(0.5)) ||
        (depth >= 1 && area < 160.0 && dice_.chance(0.25))) {
      rooms_.push_back(box);
      return;
    }
    bool vertical = box.width() >= box.height();  // a vertical wall splits the longer side
    if (dice_.chance(0.2) && std::min(box.width(), box.height()) >= 7.0) vertical = !vertical;
    const double from = vertical ? box.low.x() : box.low.y();
    const double span = vertical ? box.width() : box.height();
    const double at = rounded(from + span * dice_.uniform(0.3, 0.7), 10);
    if (at - from < 3.0 || from + span - at < 3.0) {
      rooms_.push_back(box);
      return;
    }
    Box first = box, second = box;
    if (vertical) {
      addLine(Vec(at, box.low.y()), Vec(at, box.high.y()));
      first.high.x() = at;
      second.low.x() = at;
    } else {
      addLine(Vec(box.low.x(), at), Vec(box.high.x(), at));
      first.high.y() = at;
      second.low.y() = at;
    }
    split(first, depth + 1);
    split(second, depth + 1);
  }

  // A corridor along x with rooms on one or both sides, each room's front opening onto it.
  void buildCorridorLayout() {
    const double corridor_width = rounded(dice_.uniform(1.8, 3.0), 10);
    double south = 0.0, north = corridor_width;  // the corridor's walls
    const bool two_sides = height_ >= 2.0 * 3.2 + corridor_width;
    if (two_sides) {
      const double centre =
          rounded(dice_.uniform(3.2 + corridor_width / 2, height_ - 3.2 - corridor_width / 2), 10);
      south = centre - corridor_width / 2;
      north = centre + corridor_width / 2;
      addLine(Vec(0, south), Vec(width_, south), true);
    }
    addLine(Vec(0, north), Vec(width_, north), true);
    rooms_.push_back({Vec(0, south), Vec(width_, north)});
    features_.push_back("corridor " + std::to_string(corridor_width).substr(0, 3) + " m wide");
    if (two_sides) addRoomRow(0.0, south);
    addRoomRow(north, height_);
  }

  // Rooms side by side between y = low and y = high.
  void addRoomRow(double low, double high) {
    double x = 0.0;
    while (x < width_ - 1e-6) {
      double room = dice_.chance(0.2) ? dice_.uniform(7.0, 12.0) : dice_.uniform(3.0, 6.5);
      room = rounded(room, 10);
      if (width_ - (x + room) < 3.0) room = width_ - x;
      const double end = x + room;
      rooms_.push_back({Vec(x, low), Vec(end, high)});
      if (end < width_ - 1e-6) {
        const int wall = addLine(Vec(end, low), Vec(end, high));
        if (dice_.chance(0.25)) lines_[wall].corridor_front = true;  // a door to the next room
      }
      x = end;
    }
  }

  // Every interior wall gets a door (one per bay on corridor fronts), so every room is reachable.
  void placeDoors() {
    for (Line& line : lines_) {
      if (line.exterior) continue;
      std::vector<std::pair<double, double>> bays = line.bays();
      if (!line.corridor_front) {  // one door, in a bay long enough
        std::vector<std::pair<double, double>> roomy;
        for (const auto& bay : bays)
          if (bay.second - bay.first >= 1.2 + 2 * kDoorMargin) roomy.push_back(bay);
        bays.clear();
        if (!roomy.empty()) bays.push_back(dice_.pick(roomy));
      }
      for (const auto& [start, end] : bays) {
        const double room = end - start - 2 * kDoorMargin;
        if (room < 1.1) continue;
        const double width = rounded(std::min(room, dice_.uniform(1.2, 1.8)), 100);
        const double at =
            rounded(dice_.uniform(start + kDoorMargin, end - kDoorMargin - width), 100);
        line.inserts.push_back({at, at + width, Insert::Kind::kDoor});
      }
    }
  }

  // --- glass, metal and mirrors on the walls ---------------------------------------------------

  Insert glassRun(double start, double end) {
    Insert run{start, end, Insert::Kind::kGlass};
    run.frame = rounded(dice_.uniform(0.03, 0.1), 1000);
    run.mullion_spacing = dice_.chance(0.2) ? 0.0 : rounded(dice_.uniform(0.9, 1.8), 100);
    return run;
  }

  // Glass from `start` to `end`, split round any door already in that stretch (the door's jambs
  // stay diffuse).
  void glaze(Line& line, double start, double end) {
    std::vector<std::pair<double, double>> runs{{start, end}};
    for (const Insert& door : line.inserts) {
      if (door.kind != Insert::Kind::kDoor) continue;
      std::vector<std::pair<double, double>> next;
      for (const auto& [s, e] : runs) {
        if (door.end + 0.08 <= s || door.start - 0.08 >= e) {
          next.push_back({s, e});
          continue;
        }
        if (door.start - 0.08 - s > 0.4) next.push_back({s, door.start - 0.08});
        if (e - (door.end + 0.08) > 0.4) next.push_back({door.end + 0.08, e});
      }
      runs = next;
    }
    for (const auto& [s, e] : runs)
      line.inserts.push_back(glassRun(rounded(s, 100), rounded(e, 100)));
  }

  void chooseFacade() {
    if (!dice_.chance(0.6)) return;
    facade_line_ = dice_.integer(0, 3);
    Line& line = lines_[facade_line_];
    line.facade = true;
    if (dice_.chance(0.6)) {  // an entrance to the street
      std::vector<std::pair<double, double>> roomy;
      for (const auto& bay : line.bays())
        if (bay.second - bay.first >= 1.6 + 2 * kDoorMargin) roomy.push_back(bay);
      if (!roomy.empty()) {
        const auto [start, end] = dice_.pick(roomy);
        const double width = std::min(end - start - 2 * kDoorMargin, dice_.uniform(1.6, 3.0));
        const double at =
            rounded(dice_.uniform(start + kDoorMargin, end - kDoorMargin - width), 100);
        line.inserts.push_back({at, rounded(at + width, 100), Insert::Kind::kDoor});
        street_entrance_ = true;
      }
    }
    for (const auto& [start, end] : line.bays()) {
      const double edge = dice_.uniform(0.1, 0.4);
      if (end - start > 2 * edge + 0.6) glaze(line, start + edge, end - edge);
    }
    features_.push_back(std::string("glass facade") +
                        (street_entrance_ ? " with an entrance" : ""));
  }

  void styleInteriorBays() {
    int fronts = 0, windows = 0;
    for (Line& line : lines_) {
      if (line.exterior) continue;
      for (const auto& [start, end] : line.bays()) {
        const double edge = dice_.uniform(0.15, 0.5);
        if (end - start < 2 * edge + 1.0) continue;
        const double roll = dice_.uniform(0.0, 1.0);
        if (roll < (line.corridor_front ? 0.4 : 0.2)) {  // a glass front, door included
          glaze(line, start + edge, end - edge);
          ++fronts;
        } else if (roll < (line.corridor_front ? 0.55 : 0.35)) {  // a window in the wall
          const double length = std::min(end - start - 2 * edge, dice_.uniform(1.2, 4.0));
          const double at = dice_.uniform(start + edge, end - edge - length);
          if (line.free(at, at + length, 0.15)) {
            line.inserts.push_back(glassRun(rounded(at, 100), rounded(at + length, 100)));
            ++windows;
          }
        }
      }
    }
    if (fronts) features_.push_back(std::to_string(fronts) + " glass fronts");
    if (windows) features_.push_back(std::to_string(windows) + " interior windows");
  }

  // A stretch of `length` m of plain wall, away from doors, glass and junctions, on a wall that is
  // not the facade; nothing when there is none.
  std::optional<std::pair<int, double>> plainStretch(double length) {
    for (int attempt = 0; attempt < 40; ++attempt) {
      const int index = dice_.integer(0, static_cast<int>(lines_.size()) - 1);
      Line& line = lines_[index];
      if (line.facade) continue;
      const auto bays = line.bays();
      const auto [start, end] = dice_.pick(bays);
      if (end - start < length + 0.6) continue;
      const double at = rounded(dice_.uniform(start + 0.3, end - 0.3 - length), 100);
      if (line.free(at, at + length, 0.3)) return std::make_pair(index, at);
    }
    return std::nullopt;
  }

  void placeWallFeatures() {
    if (dice_.chance(0.55)) {  // a bank of metal elevator doors
      const int doors = dice_.integer(1, 3);
      const double width = rounded(dice_.uniform(0.9, 1.2), 100);
      const double gap = rounded(dice_.uniform(0.3, 0.6), 100);
      if (const auto where = plainStretch(doors * width + (doors - 1) * gap)) {
        for (int k = 0; k < doors; ++k) {
          const double at = where->second + k * (width + gap);
          lines_[where->first].inserts.push_back({at, at + width, Insert::Kind::kMetal});
        }
        features_.push_back(std::to_string(doors) + " metal doors");
      }
    }
    if (dice_.chance(0.2)) {  // stainless cladding
      const double length = rounded(dice_.uniform(1.5, 4.0), 100);
      if (const auto where = plainStretch(length)) {
        lines_[where->first].inserts.push_back(
            {where->second, where->second + length, Insert::Kind::kMetal});
        features_.push_back("metal cladding");
      }
    }
    const int mirrors = dice_.chance(0.5) ? dice_.integer(1, 2) : 0;
    for (int k = 0; k < mirrors; ++k) {
      const double length = rounded(dice_.uniform(0.8, 3.0), 100);
      if (const auto where = plainStretch(length)) {
        Insert mirror{where->second, where->second + length, Insert::Kind::kMirror};
        mirror.frame = dice_.chance(0.5) ? 0.0 : rounded(dice_.uniform(0.01, 0.03), 1000);
        lines_[where->first].inserts.push_back(mirror);
        features_.push_back("mirror");
      }
    }
  }

  // --- surfaces ---------------------------------------------------------------------------------

  WallDescription segment(const Vec& a, const Vec& b, Material material) {
    WallDescription wall;
    wall.type = WallDescription::Type::kSegment;
    wall.material = material;
    wall.points = {a, b};
    return wall;
  }

  // Panes are never quite plumb, and some are dirty.
  void finishSpecular(WallDescription& wall) {
    wall.tilt_deg = rounded(std::clamp(dice_.normal(0.0, 0.3), -1.0, 1.0), 100);
    if (wall.material == Material::kGlass && dice_.chance(0.5)) {
      wall.dirt = rounded(dice_.uniform(0.002, 0.03), 10000);
    } else if (wall.material == Material::kMirror) {
      wall.dirt = rounded(dice_.uniform(0.0, 0.005), 10000);
    }
  }

  void emitLines() {
    for (Line& line : lines_) {
      std::sort(line.inserts.begin(), line.inserts.end(),
                [](const Insert& x, const Insert& y) { return x.start < y.start; });
      double cursor = 0.0;
      for (const Insert& insert : line.inserts) {
        if (insert.start > cursor + 1e-6) {
          plan_.walls.push_back(
              segment(line.at(cursor), line.at(insert.start), Material::kDiffuse));
        }
        cursor = std::max(cursor, insert.end);
        if (insert.kind == Insert::Kind::kDoor) continue;
        const Material material = insert.kind == Insert::Kind::kGlass   ? Material::kGlass
                                  : insert.kind == Insert::Kind::kMetal ? Material::kMetal
                                                                        : Material::kMirror;
        WallDescription wall = segment(line.at(insert.start), line.at(insert.end), material);
        wall.frame = insert.frame;
        wall.mullion_spacing = insert.mullion_spacing;
        finishSpecular(wall);
        plan_.walls.push_back(wall);
      }
      if (cursor < line.length() - 1e-6) {
        plan_.walls.push_back(segment(line.at(cursor), line.b, Material::kDiffuse));
      }
      for (const Insert& insert : line.inserts) {
        if (insert.kind != Insert::Kind::kDoor) continue;
        // Keep the doorway's approach clear on both sides.
        const Vec normal(-line.direction().y(), line.direction().x());
        const Vec from = line.at(insert.start), to = line.at(insert.end);
        Box zone{from.cwiseMin(to), from.cwiseMax(to)};
        zone.low = zone.low.cwiseMin(from - 1.5 * normal.cwiseAbs());
        zone.high = zone.high.cwiseMax(to + 1.5 * normal.cwiseAbs());
        keep_out_.push_back(zone.grown(0.3));
      }
    }
  }

  // --- furniture and freestanding glass -------------------------------------------------------

  // A random box of the given size inside `room` (kept `margin` from its walls) that overlaps
  // nothing placed so far, grown by `clearance`; nothing after a few tries.
  std::optional<Box> place(const Box& room, double width, double height, double margin,
                           double clearance) {
    const Box inner{room.low + Vec::Constant(margin), room.high - Vec::Constant(margin)};
    if (inner.width() < width || inner.height() < height) return std::nullopt;
    for (int attempt = 0; attempt < 30; ++attempt) {
      const Vec low(rounded(dice_.uniform(inner.low.x(), inner.high.x() - width), 100),
                    rounded(dice_.uniform(inner.low.y(), inner.high.y() - height), 100));
      const Box box{low, low + Vec(width, height)};
      const Box claimed = box.grown(clearance);
      bool clear = true;
      for (const Box& other : keep_out_)
        clear = clear && !claimed.overlaps(other);
      if (!clear) continue;
      keep_out_.push_back(claimed);
      return box;
    }
    return std::nullopt;
  }

  void addCircle(const Vec& centre, double radius, Material material) {
    WallDescription wall;
    wall.type = WallDescription::Type::kArc;
    wall.material = material;
    wall.center = centre;
    wall.radius = radius;
    wall.start_deg = 0.0;
    wall.end_deg = 360.0;
    if (material != Material::kDiffuse) finishSpecular(wall);
    plan_.walls.push_back(wall);
  }

  void addBlock(const Box& box) {
    WallDescription wall;
    wall.type = WallDescription::Type::kPolyline;
    wall.material = Material::kDiffuse;
    wall.closed = true;
    wall.points = {box.low, Vec(box.high.x(), box.low.y()), box.high,
                   Vec(box.low.x(), box.high.y())};
    plan_.walls.push_back(wall);
  }

  void placeRoomFeatures() {
    int curved = 0, panes = 0, boxes = 0, pillars = 0, tables = 0;
    for (const Box& room : rooms_) {
      const bool hall = room.area() >= 40.0 && std::min(room.width(), room.height()) >= 5.0;
      if (hall && dice_.chance(0.35)) curved += addCurvedGlass(room);
      if (hall && dice_.chance(0.4)) panes += addFreestandingPanes(room);
      if (hall && dice_.chance(0.2)) boxes += addGlassBox(room);
      const int pillar_count = hall ? dice_.integer(0, 4) : (dice_.chance(0.2) ? 1 : 0);
      for (int k = 0; k < pillar_count; ++k)
        pillars += addPillar(room);
      const int table_count = dice_.integer(0, room.area() > 20.0 ? 2 : 1);
      for (int k = 0; k < table_count; ++k)
        tables += addTable(room);
      if (dice_.chance(0.4)) addCabinet(room);
    }
    if (curved) features_.push_back(std::to_string(curved) + " curved glass");
    if (panes) features_.push_back(std::to_string(panes) + " freestanding panes");
    if (boxes) features_.push_back(std::to_string(boxes) + " glass boxes");
    if (pillars) features_.push_back(std::to_string(pillars) + " pillars");
    if (tables) features_.push_back(std::to_string(tables) + " tables");
  }

  int addCurvedGlass(const Box& room) {
    const double radius = rounded(dice_.uniform(1.5, 3.5), 100);
    const auto box = place(room, 2 * radius, 2 * radius, 1.2, 1.0);
    if (!box) return 0;
    const Vec centre = 0.5 * (box->low + box->high);
    const double opening_deg = (dice_.uniform(1.2, 2.0) / radius) * 180.0 / M_PI;
    const double start = rounded(dice_.uniform(0.0, 360.0), 10);
    const double sweep =
        rounded(std::min(330.0, 360.0 - opening_deg) - dice_.uniform(0.0, 120.0), 10);
    WallDescription wall;
    wall.type = WallDescription::Type::kArc;
    wall.material = Material::kGlass;
    wall.center = centre;
    wall.radius = radius;
    wall.start_deg = start;
    wall.end_deg = rounded(start + sweep, 10);
    wall.frame = rounded(dice_.uniform(0.03, 0.08), 1000);
    wall.mullion_spacing = dice_.chance(0.3) ? 0.0 : rounded(dice_.uniform(0.8, 1.6), 100);
    finishSpecular(wall);
    plan_.walls.push_back(wall);
    if (radius > 2.0 && dice_.chance(0.5)) {  // a stair core inside
      addCircle(centre, rounded(dice_.uniform(0.25, 0.6), 100), Material::kDiffuse);
    }
    return 1;
  }

  int addFreestandingPanes(const Box& room) {
    const double length = rounded(dice_.uniform(2.0, 5.0), 100);
    const bool pair = dice_.chance(0.3);
    const double spacing = pair ? rounded(dice_.uniform(1.0, 2.0), 100) : 0.0;
    const bool along_x = dice_.chance(0.5);
    const auto box = along_x ? place(room, length, spacing + 0.1, 1.0, 1.0)
                             : place(room, spacing + 0.1, length, 1.0, 1.0);
    if (!box) return 0;
    for (int k = 0; k < (pair ? 2 : 1); ++k) {
      const Vec offset = along_x ? Vec(0.0, 0.05 + k * spacing) : Vec(0.05 + k * spacing, 0.0);
      const Vec a = box->low + offset;
      const Vec b = a + (along_x ? Vec(length, 0.0) : Vec(0.0, length));
      WallDescription wall = segment(a, b, Material::kGlass);
      wall.frame = rounded(dice_.uniform(0.03, 0.1), 1000);
      wall.mullion_spacing = dice_.chance(0.4) ? 0.0 : rounded(dice_.uniform(0.9, 1.8), 100);
      finishSpecular(wall);
      plan_.walls.push_back(wall);
    }
    return pair ? 2 : 1;
  }

  // A glass meeting room: four framed glass sides, a doorway in one.
  int addGlassBox(const Box& room) {
    const double w = rounded(dice_.uniform(2.5, 4.5), 100),
                 h = rounded(dice_.uniform(2.5, 4.0), 100);
    const auto box = place(room, w, h, 1.3, 1.0);
    if (!box) return 0;
    const Vec corners[4] = {box->low, Vec(box->high.x(), box->low.y()), box->high,
                            Vec(box->low.x(), box->high.y())};
    const int door_side = dice_.integer(0, 3);
    const double frame = rounded(dice_.uniform(0.04, 0.1), 1000);
    const double mullions = rounded(dice_.uniform(0.9, 1.5), 100);
    for (int side = 0; side < 4; ++side) {
      const Vec a = corners[side], b = corners[(side + 1) % 4];
      std::vector<std::pair<Vec, Vec>> runs{{a, b}};
      if (side == door_side) {
        const double length = (b - a).norm(), door = 1.1;
        const double at = rounded(dice_.uniform(0.4, length - 0.4 - door), 100);
        const Vec u = (b - a) / length;
        runs = {{a, a + at * u}, {a + (at + door) * u, b}};
        rooms_.push_back({box->low, box->high});  // people may meet inside
      }
      for (const auto& [from, to] : runs) {
        WallDescription wall = segment(from, to, Material::kGlass);
        wall.frame = frame;
        wall.mullion_spacing = mullions;
        finishSpecular(wall);
        plan_.walls.push_back(wall);
      }
    }
    return 1;
  }

  int addPillar(const Box& room) {
    const double size = rounded(dice_.uniform(0.3, 0.7), 100);
    const auto box = place(room, size, size, 0.9, 0.9);
    if (!box) return 0;
    if (dice_.chance(0.4)) {
      addBlock(*box);
    } else {  // round; some are clad in stainless steel
      addCircle(0.5 * (box->low + box->high), size / 2,
                dice_.chance(0.2) ? Material::kMetal : Material::kDiffuse);
    }
    return 1;
  }

  // A table seen at a lidar's height: four thin legs.
  int addTable(const Box& room) {
    const double w = rounded(dice_.uniform(1.2, 2.0), 100),
                 h = rounded(dice_.uniform(0.7, 1.0), 100);
    const bool turned = dice_.chance(0.5);
    const auto box = turned ? place(room, h, w, 0.6, 0.8) : place(room, w, h, 0.6, 0.8);
    if (!box) return 0;
    const double leg = rounded(dice_.uniform(0.015, 0.035), 1000);
    const Vec inset = Vec::Constant(0.08);
    const Vec low = box->low + inset, high = box->high - inset;
    for (const Vec& corner : {low, Vec(high.x(), low.y()), high, Vec(low.x(), high.y())})
      addCircle(corner, leg, Material::kDiffuse);
    return 1;
  }

  // A cabinet or sofa against a wall.
  void addCabinet(const Box& room) {
    const double length = rounded(dice_.uniform(1.0, 2.5), 100);
    const double depth = rounded(dice_.uniform(0.4, 0.9), 100);
    const int wall = dice_.integer(0, 3);
    const bool along_x = wall % 2 == 0;
    const double w = along_x ? length : depth, h = along_x ? depth : length;
    const double span = along_x ? room.width() : room.height();
    if (span < length + 1.0) return;
    const double at = rounded(dice_.uniform(0.5, span - 0.5 - length), 100);
    Vec low;
    switch (wall) {
      case 0:
        low = Vec(room.low.x() + at, room.low.y() + 0.03);
        break;
      case 1:
        low = Vec(room.high.x() - 0.03 - w, room.low.y() + at);
        break;
      case 2:
        low = Vec(room.low.x() + at, room.high.y() - 0.03 - h);
        break;
      default:
        low = Vec(room.low.x() + 0.03, room.low.y() + at);
        break;
    }
    const Box box{low, low + Vec(w, h)};
    for (const Box& other : keep_out_)
      if (box.grown(0.6).overlaps(other)) return;
    keep_out_.push_back(box.grown(0.6));
    addBlock(box);
  }

  // --- the street beyond the facade -----------------------------------------------------------

  void buildStreet() {
    const Line& facade = lines_[facade_line_];
    const Vec along = facade.direction();
    // Outward normal: away from the building's centre.
    Vec outward(-along.y(), along.x());
    const Vec centre(width_ / 2, height_ / 2);
    if ((facade.at(facade.length() / 2) - centre).dot(outward) < 0) outward = -outward;
    const double depth = rounded(dice_.uniform(6.0, 18.0), 10);
    const double overhang = rounded(dice_.uniform(3.0, 8.0), 10);
    const Vec a = facade.a - overhang * along, b = facade.b + overhang * along;
    if (dice_.chance(0.6)) {  // the building across the street; otherwise open space
      plan_.walls.push_back(segment(a + depth * outward, b + depth * outward, Material::kDiffuse));
      features_.push_back("street " + std::to_string(static_cast<int>(depth)) + " m deep");
    } else {
      features_.push_back("open space beyond the facade");
    }
    Box street{(a + 0.6 * outward).cwiseMin(b + (depth - 0.6) * outward),
               (a + 0.6 * outward).cwiseMax(b + (depth - 0.6) * outward)};
    const int objects = dice_.integer(2, 8);
    for (int k = 0; k < objects; ++k) {  // trees, poles, bollards
      const double radius = rounded(dice_.uniform(0.08, 0.4), 100);
      const double s = dice_.uniform(0.0, 1.0), t = dice_.uniform(1.5, depth - 1.0);
      const Vec centre_point = a + s * (b - a) + t * outward;
      const Box claimed = Box{centre_point, centre_point}.grown(radius + 1.0);
      bool clear = true;
      for (const Box& other : keep_out_)
        clear = clear && !claimed.overlaps(other);
      if (!clear) continue;
      keep_out_.push_back(claimed);
      addCircle(Vec(rounded(centre_point.x(), 100), rounded(centre_point.y(), 100)), radius,
                Material::kDiffuse);
    }
    plan_.areas.push_back({street.low, street.high, true});
    plan_.world_low = street.low.cwiseMin(a + depth * outward).cwiseMin(a);
    plan_.world_high = street.high.cwiseMax(b + depth * outward).cwiseMax(b);
  }

  Dice& dice_;
  double width_ = 0.0, height_ = 0.0;
  std::vector<Line> lines_;
  std::vector<Box> rooms_;
  std::vector<Box> keep_out_;
  std::vector<std::string> features_;
  int facade_line_ = -1;
  bool street_entrance_ = false;
  FloorPlan plan_;
};

}  // namespace

FloorPlan generateFloorPlan(Dice& dice) {
  return FloorPlanBuilder(dice).build();
}

}  // namespace rfm::sim
