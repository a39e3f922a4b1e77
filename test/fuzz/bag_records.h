#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <set>

namespace rfm::fuzz {

// The value of the 8-byte field `name` in a record header [begin, end), or `fallback`.
inline uint64_t bagHeaderField(const uint8_t* begin, const uint8_t* end, const char* name,
                               uint64_t fallback) {
  const size_t name_length = std::strlen(name);
  while (end - begin >= 4) {
    uint32_t length = 0;
    std::memcpy(&length, begin, 4);
    begin += 4;
    if (length > static_cast<size_t>(end - begin)) break;
    if (length == name_length + 1 + 8 && std::memcmp(begin, name, name_length) == 0 &&
        begin[name_length] == '=') {
      uint64_t value = 0;
      std::memcpy(&value, begin + name_length + 1, 8);
      return value;
    }
    begin += length;
  }
  return fallback;
}

// True when every top-level record of a ROS bag (format 2.0: a 4-byte header length, the
// header, a 4-byte data length, the data) fits in the file, and the positions records give of
// others (the bag header's index_pos, each chunk info's chunk_pos) are where records start.
// rosbag::Bag::open allocates each record's header and data at the lengths the file claims (a
// 10 KB file can ask for 4 GB) before reading them; the bag target feeds rosbag only files whose
// records fit, until readBagScans checks the lengths itself (doc/fuzzing.md, open findings).
inline bool bagRecordsFitFile(const uint8_t* data, size_t size) {
  static constexpr char kMagic[] = "#ROSBAG V2.0\n";
  constexpr size_t kMagicLength = sizeof(kMagic) - 1;
  if (size < kMagicLength || std::memcmp(data, kMagic, kMagicLength) != 0) return true;
  // Skips one length-prefixed block at `position`; false when it runs past the file.
  auto skip = [&](size_t& position) {
    if (size - position < 4) return false;
    uint32_t length = 0;
    std::memcpy(&length, data + position, 4);
    position += 4;
    if (length > size - position) return false;
    position += length;
    return true;
  };
  std::set<uint64_t> starts, pointed;
  for (size_t at = kMagicLength; at < size;) {
    const size_t record = at;
    if (!skip(at)) return false;  // the header
    starts.insert(record);
    for (const char* field : {"index_pos", "chunk_pos"}) {
      const uint64_t position = bagHeaderField(data + record + 4, data + at, field, 0);
      if (position != 0) pointed.insert(position);
    }
    if (!skip(at)) return false;  // the data
  }
  for (const uint64_t position : pointed)
    if (position != size && starts.count(position) == 0) return false;
  return true;
}

}  // namespace rfm::fuzz
