#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <set>
#include <string_view>

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

// True when the records in [data + from, data + to) are well formed: each a 4-byte header
// length, the header (fields of a 4-byte length and "name=value", each inside it), a 4-byte data
// length and the data, all inside the range; chunks uncompressed, their records well formed too,
// and each index entry at a record of its chunk.
// Adds where each record starts to `starts` and the positions records give of others (index_pos,
// chunk_pos) to `pointed`.
inline bool bagRecordsWellFormed(const uint8_t* data, size_t from, size_t to,
                                 std::set<uint64_t>& starts, std::set<uint64_t>& pointed) {
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
    starts.insert(at);
    size_t header_length = 0, data_length = 0;
    if (!block(at, header_length)) return false;
    const uint8_t* header = data + at;
    for (size_t field = 0; field < header_length;) {
      if (header_length - field < 4) return false;
      uint32_t field_length = 0;
      std::memcpy(&field_length, header + field, 4);
      field += 4;
      if (field_length > header_length - field) return false;
      field += field_length;
    }
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

// True when a ROS bag (format 2.0) is well formed as bagRecordsWellFormed says and every
// position one record gives of another is where a record starts (or the file's end).
// rosbag::Bag::open trusts the lengths a file claims: it allocates a record's header and data at
// them (a 10 KB file can ask for 4 GB), and ros::Header::parse reads a field at its claimed
// length past the header's end. The bag target feeds rosbag only well-formed files, until
// readBagScans checks them itself (doc/fuzzing.md, open findings); compressed chunks, whose
// records cannot be checked before rosbag decompresses them, are left out for the same reason.
inline bool bagRecordsFitFile(const uint8_t* data, size_t size) {
  static constexpr char kMagic[] = "#ROSBAG V2.0\n";
  constexpr size_t kMagicLength = sizeof(kMagic) - 1;
  if (size < kMagicLength || std::memcmp(data, kMagic, kMagicLength) != 0) return true;
  std::set<uint64_t> starts, pointed;
  if (!bagRecordsWellFormed(data, kMagicLength, size, starts, pointed)) return false;
  for (const uint64_t position : pointed)
    if (position != size && starts.count(position) == 0) return false;
  return true;
}

}  // namespace rfm::fuzz
