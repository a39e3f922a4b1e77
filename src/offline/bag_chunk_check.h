#pragma once

// The inside of a bag's chunks, checked after the walk over the file's records has checked each
// chunk record itself: the records in its data (decompressed as rosbag decompresses them), and
// the index entries that point into it.

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rfm {
namespace offline {
namespace detail {

struct ChunkToCheck {
  uint64_t record = 0;  // where the chunk record starts
  uint64_t data_start = 0;
  uint32_t data_length = 0;
  std::string compression;  // "none", "bz2" or "lz4"
  uint32_t size = 0;        // its size field, checked against maxDecompressedChunkBytes
  // The index data records after it: where each one's entries start, and how many it has.
  std::vector<std::pair<uint64_t, uint32_t>> index_entries;
};

// Checks every chunk: its records lie inside its (decompressed) data, as readRecord checks them,
// a connection record's data are header fields, and each of its index entries gives the offset of
// a message data record in it. Two chunks at a time, each reader with its own handle on the file
// at `path`. Throws BagStructureError for the first chunk in file order that fails.
void checkChunks(const std::string& path, const std::vector<ChunkToCheck>& chunks);

}  // namespace detail
}  // namespace offline
}  // namespace rfm
