#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <set>
#include <string_view>
#include <utility>
#include <vector>

namespace rfm::fuzz {

// The value of the field `name` in a record header [begin, end) (its fields well formed), or
// empty.
inline std::string_view bagHeaderValue(const uint8_t* begin, const uint8_t* end, const char* name) {
  const size_t name_length = std::strlen(name);
  while (end - begin >= 4) {
    uint32_t length = 0;
    std::memcpy(&length, begin, 4);
    begin += 4;
    if (length > name_length && std::memcmp(begin, name, name_length) == 0 &&
        begin[name_length] == '=') {
      return {reinterpret_cast<const char*>(begin) + name_length + 1, length - name_length - 1};
    }
    begin += length;
  }
  return {};
}

// True when [header, header + length) is a sequence of fields (a 4-byte length, then that many
// bytes) that ends where it should.
inline bool bagFieldsWellFormed(const uint8_t* header, size_t length) {
  for (size_t field = 0; field < length;) {
    if (length - field < 4) return false;
    uint32_t field_length = 0;
    std::memcpy(&field_length, header + field, 4);
    field += 4;
    if (field_length > length - field) return false;
    field += field_length;
  }
  return true;
}

// True when the records in [data + from, data + to) are well formed: each a 4-byte header
// length, the header (fields of a 4-byte length and "name=value", each inside it), a 4-byte data
// length and the data, all inside the range; a connection's data fields as well; chunks
// uncompressed, their records well formed too, and each index entry at a record of its chunk.
// Adds where each record starts to `starts` and the positions records give of others (index_pos,
// chunk_pos) to `pointed`.
inline bool bagRecordsWellFormed(const uint8_t* data, size_t from, size_t to,
                                 std::set<uint64_t>& starts, std::set<uint64_t>& pointed,
                                 std::vector<std::pair<uint64_t, char>>* records = nullptr) {
  auto block = [&](size_t& position, size_t& length) {  // a length-prefixed block
    if (to - position < 4) return false;
    uint32_t claimed = 0;
    std::memcpy(&claimed, data + position, 4);
    position += 4;
    if (claimed > to - position) return false;
    length = claimed;
    return true;
  };
  std::set<uint64_t> chunk_starts;  // where the records of the last chunk start
  size_t chunk_begin = 0;
  for (size_t at = from; at < to;) {
    const size_t record = at;
    starts.insert(record);
    size_t header_length = 0, data_length = 0;
    if (!block(at, header_length)) return false;
    const uint8_t* header = data + at;
    if (!bagFieldsWellFormed(header, header_length)) return false;
    at += header_length;
    if (!block(at, data_length)) return false;
    for (const char* name : {"index_pos", "chunk_pos"}) {
      const std::string_view value = bagHeaderValue(header, header + header_length, name);
      if (value.size() != 8) continue;
      uint64_t position = 0;
      std::memcpy(&position, value.data(), 8);
      pointed.insert(position);
    }
    const std::string_view op = bagHeaderValue(header, header + header_length, "op");
    if (records) records->emplace_back(record, op.size() == 1 ? op[0] : 0);
    // A connection record's data is the connection's header: fields too.
    if (op.size() == 1 && op[0] == 0x07 && !bagFieldsWellFormed(data + at, data_length)) {
      return false;
    }
    if (op.size() == 1 && op[0] == 0x05) {  // a chunk: its records, uncompressed, in its data
      if (bagHeaderValue(header, header + header_length, "compression") != "none") return false;
      std::set<uint64_t> inner_pointed;
      chunk_starts.clear();
      if (!bagRecordsWellFormed(data, at, at + data_length, chunk_starts, inner_pointed)) {
        return false;
      }
      chunk_begin = at;
    }
    if (op.size() == 1 && op[0] == 0x04) {  // index data: (time, offset) of the last chunk's
      for (size_t entry = 0; entry + 12 <= data_length; entry += 12) {
        uint32_t offset = 0;
        std::memcpy(&offset, data + at + entry + 8, 4);
        if (chunk_starts.count(chunk_begin + offset) == 0) return false;
      }
    }
    at += data_length;
  }
  return true;
}

// True when a ROS bag (format 2.0) is well formed as bagRecordsWellFormed says, every position
// one record gives of another is where a record starts (or the file's end), and the bag header's
// conn_count connection records and chunk_count chunk infos follow its index_pos, as rosbag reads
// them. rosbag::Bag::open trusts what a file claims: it allocates a record's header and data at
// their lengths (a 10 KB file can ask for 4 GB), reads the counted records past the file's end,
// and ros::Header::parse reads a field at its claimed length past the header's end. The bag target
// feeds rosbag only well-formed files, until readBagScans checks them itself (doc/fuzzing.md,
// open findings); compressed chunks, whose records cannot be checked before rosbag decompresses
// them, are left out for the same reason.
inline bool bagRecordsFitFile(const uint8_t* data, size_t size) {
  // rosbag reads any "#ROS<word> V<major>.<minor>" line (sscanf: whitespace loosely, older formats
  // by other readers): only the exact 2.0 line is checked and fed; others that start so are not.
  static constexpr char kPrefix[] = "#ROS";
  static constexpr char kVersion2[] = "#ROSBAG V2.0\n";
  if (size < sizeof(kPrefix) - 1 || std::memcmp(data, kPrefix, sizeof(kPrefix) - 1) != 0) {
    return true;  // rosbag refuses it
  }
  const size_t first = sizeof(kVersion2) - 1;
  if (size < first || std::memcmp(data, kVersion2, first) != 0) return false;
  std::set<uint64_t> starts, pointed;
  std::vector<std::pair<uint64_t, char>> records;  // top level: start, op
  if (!bagRecordsWellFormed(data, first, size, starts, pointed, &records)) return false;
  for (const uint64_t position : pointed)
    if (position != size && starts.count(position) == 0) return false;
  if (records.empty() || records.front().second != 0x03) return true;  // rosbag refuses it
  const uint8_t* header = data + first + 4;
  uint32_t header_length = 0;
  std::memcpy(&header_length, data + first, 4);
  auto count = [&](const char* name) -> uint64_t {
    const std::string_view value = bagHeaderValue(header, header + header_length, name);
    uint32_t number = 0;
    if (value.size() == 4) std::memcpy(&number, value.data(), 4);
    return number;
  };
  const std::string_view index = bagHeaderValue(header, header + header_length, "index_pos");
  uint64_t index_pos = 0;
  if (index.size() == 8) std::memcpy(&index_pos, index.data(), 8);
  size_t next = 0;
  while (next < records.size() && records[next].first != index_pos)
    ++next;
  for (const auto& [name, op] : {std::pair<const char*, char>{"conn_count", 0x07},
                                 std::pair<const char*, char>{"chunk_count", 0x06}}) {
    for (uint64_t k = count(name); k > 0; --k, ++next) {
      if (next >= records.size() || records[next].second != op) return false;
    }
  }
  return true;
}

}  // namespace rfm::fuzz
