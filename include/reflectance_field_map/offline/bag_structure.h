#pragma once

#include <string>

namespace rfm {
namespace offline {

// Checks that a bag file is one rosbag can open and read the messages of without trusting a
// length or position the file claims (rosbag allocates, parses and seeks at those unchecked):
// returns an empty string when it is, else a one-line reason naming the byte offset and what is
// wrong there. The file's records are checked first, then the inside of each chunk, two chunks at
// a time. Reads the file in bounded pieces: memory does not follow the lengths the file claims
// (at most a 256 KiB window, a 1 MiB header, and per thread one compressed chunk and its
// decompressed data, at most 1 GiB, the size rosbag itself allocates for it).
//
// What it checks, as rosbag 1.15 reads a bag of format 2.0:
// - the version line is exactly "#ROSBAG V2.0\n" (rosbag's sscanf takes any
//   "#ROS<word> V<n>.<m>");
// - every record of the file and of every chunk: its 4-byte header length, the header (at most
//   1 MiB) and its fields (a 4-byte length, then "name=value"), its 4-byte data length and the
//   data lie inside the file or the chunk; a connection record's data (at most 1 MiB) are
//   well-formed header fields too;
// - the first record is the bag header, with index_pos, conn_count and chunk_count, naming no
//   encryptor (an encrypted bag's records cannot be checked); index_pos 0 (a bag never closed)
//   is refused;
// - index_pos is where a record starts, and conn_count connection records then chunk_count
//   chunk info records follow it;
// - each chunk info's chunk_pos is where a chunk record starts, and its count of 8-byte entries
//   fills its data exactly (rosbag reads by the count);
// - each index data record's count of 12-byte entries fills its data exactly, and each entry's
//   offset is where a message data record starts in the chunk before it;
// - chunks are "none", "bz2" or "lz4"; a compressed chunk's size field (the buffer rosbag
//   allocates) is at most 16 MiB, or 256 times its compressed bytes, and never over 1 GiB; an lz4
//   chunk's frame holds no block larger than the frame's block size (roslz4 copies a block into
//   a buffer of that size unchecked); the chunk decompresses to exactly its size field.
// Not checked: message contents (readBagScans decodes each with its own bounds), chunks inside
// chunks, and fields rosbag reads and refuses cleanly itself (a message record's conn and time,
// a connection record's topic).
std::string checkBagStructure(const std::string& path);

}  // namespace offline
}  // namespace rfm
