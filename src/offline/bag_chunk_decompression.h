#pragma once

// A compressed chunk of a ROS bag decompressed as rosbag decompresses it (libbz2, roslz4), after
// checks that keep both this and rosbag's own decompression inside their buffers.

#include "bag_byte_source.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace rfm {
namespace offline {
namespace detail {

// rosbag closes a chunk once it holds 768 KiB of records, so only a chunk holding one very large
// message comes near this; rosbag's buffers count in uint32 and this one is allocated whole.
constexpr uint64_t kMaxChunkBytes = uint64_t{1} << 30;

// The most bytes a chunk of `compressed_bytes` may claim to decompress to (its size field, the
// buffer rosbag allocates before decompressing). Up to kSmallChunkBytes any claim is taken: every
// chunk of ordinary messages is far below it, and a small file then makes no one allocate more
// than that. Above it, at most kMaxCompressionRatio times the compressed bytes: LZ4 cannot
// compress beyond 255:1, so no lz4 chunk is refused; a bz2 chunk over kSmallChunkBytes that
// compresses better than 256:1 (a large, nearly constant message) is. Never over kMaxChunkBytes.
constexpr uint64_t kSmallChunkBytes = uint64_t{16} << 20;
constexpr uint64_t kMaxCompressionRatio = 256;
uint64_t maxDecompressedChunkBytes(uint64_t compressed_bytes);

// Decompresses `compressed` ("bz2" or "lz4" as `compression` says) into `decompressed`, which
// the caller has sized to the chunk's size field. Returns an empty string when the data
// decompress to exactly that size, else what is wrong with them (after "the chunk's data: ").
std::string decompressChunk(const std::string& compression, ByteBuffer& compressed,
                            ByteBuffer& decompressed);

// What is wrong with an lz4 chunk's frame as roslz4 reads it (its 7-byte header, then blocks of
// a 4-byte size and that many bytes, ended by a zero size and a 4-byte checksum), or an empty
// string. A block larger than the frame's block size would overflow roslz4's block buffer.
std::string checkLz4Frame(const char* frame, size_t size);

}  // namespace detail
}  // namespace offline
}  // namespace rfm
