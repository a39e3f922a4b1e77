#include "bag_chunk_decompression.h"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

namespace rfm {
namespace offline {
namespace detail {
namespace {

constexpr uint32_t kLz4Magic = 0x184D2204;
constexpr size_t kLz4HeaderBytes = 7;  // magic, flags, block size byte, header checksum
// Version 1, independent blocks, a stream checksum; no block checksums, content size or
// dictionary: the only flags roslz4 reads.
constexpr unsigned char kLz4Flags = 0x64;
constexpr uint32_t kLz4UncompressedBlockBit = 0x80000000u;

std::string hexByte(unsigned char byte) {
  char text[8];
  std::snprintf(text, sizeof(text), "0x%02x", byte);
  return text;
}

uint32_t uint32At(const char* bytes, size_t at) {
  uint32_t value = 0;
  std::memcpy(&value, bytes + at, 4);
  return value;
}

std::string sizeMismatch(unsigned int produced, size_t size) {
  return "they decompress to " + std::to_string(produced) + " bytes, not the chunk's size field (" +
         std::to_string(size) + ")";
}

std::string decompressBz2(ByteBuffer& compressed, ByteBuffer& decompressed) {
  unsigned int produced = static_cast<unsigned int>(decompressed.size());
  const int result = BZ2_bzBuffToBuffDecompress(decompressed.data(), &produced, compressed.data(),
                                                static_cast<unsigned int>(compressed.size()), 0, 0);
  if (result == BZ_OUTBUFF_FULL) {
    return "they decompress to more than the chunk's size field (" +
           std::to_string(decompressed.size()) + ")";
  }
  if (result != BZ_OK) return "libbz2 refuses them (error " + std::to_string(result) + ")";
  if (produced != decompressed.size()) return sizeMismatch(produced, decompressed.size());
  return {};
}

std::string decompressLz4(ByteBuffer& compressed, ByteBuffer& decompressed) {
  const std::string frame_problem = checkLz4Frame(compressed.data(), compressed.size());
  if (!frame_problem.empty()) return frame_problem;
  unsigned int produced = static_cast<unsigned int>(decompressed.size());
  const int result =
      roslz4_buffToBuffDecompress(compressed.data(), static_cast<unsigned int>(compressed.size()),
                                  decompressed.data(), &produced);
  if (result != ROSLZ4_OK) {
    return "roslz4 refuses them, or they decompress to more than the chunk's size field (" +
           std::to_string(decompressed.size()) + "; roslz4 error " + std::to_string(result) + ")";
  }
  if (produced != decompressed.size()) return sizeMismatch(produced, decompressed.size());
  return {};
}

}  // namespace

uint64_t maxDecompressedChunkBytes(uint64_t compressed_bytes) {
  const uint64_t by_ratio = compressed_bytes > kMaxChunkBytes / kMaxCompressionRatio
                                ? kMaxChunkBytes
                                : compressed_bytes * kMaxCompressionRatio;
  return std::min(kMaxChunkBytes, std::max(kSmallChunkBytes, by_ratio));
}

std::string checkLz4Frame(const char* frame, size_t size) {
  if (size < kLz4HeaderBytes) {
    return std::to_string(size) + " bytes, too few for an lz4 frame's 7-byte header";
  }
  if (uint32At(frame, 0) != kLz4Magic) return "frame byte 0: no lz4 frame magic number";
  const auto flags = static_cast<unsigned char>(frame[4]);
  if (flags != kLz4Flags) {
    return "frame byte 4: flags " + hexByte(flags) + ", not the " + hexByte(kLz4Flags) +
           " roslz4 reads";
  }
  const auto block_size_byte = static_cast<unsigned char>(frame[5]);
  const int block_size_id = (block_size_byte >> 4) & 0x07;
  if ((block_size_byte & 0x8F) != 0 || block_size_id < 4) {
    return "frame byte 5: block size byte " + hexByte(block_size_byte) + " is not one roslz4 reads";
  }
  const uint32_t max_block = uint32_t{1} << (8 + 2 * block_size_id);
  for (size_t at = kLz4HeaderBytes;;) {
    if (size - at < 4) {
      return "frame byte " + std::to_string(at) + ": the frame ends inside a block size";
    }
    const uint32_t block = uint32At(frame, at) & ~kLz4UncompressedBlockBit;
    if (block == 0) {  // the end mark, then the stream checksum
      if (size - at != 8) {
        return "frame byte " + std::to_string(at) + ": the end mark is followed by " +
               std::to_string(size - at - 4) + " bytes, not the 4-byte checksum";
      }
      return {};
    }
    if (block > max_block) {
      return "frame byte " + std::to_string(at) + ": a block of " + std::to_string(block) +
             " bytes, larger than the frame's block size (" + std::to_string(max_block) + ")";
    }
    at += 4;
    if (block > size - at) {
      return "frame byte " + std::to_string(at - 4) + ": a block of " + std::to_string(block) +
             " bytes runs past the end of the frame (" + std::to_string(size - at) + " bytes left)";
    }
    at += block;
  }
}

std::string decompressChunk(const std::string& compression, ByteBuffer& compressed,
                            ByteBuffer& decompressed) {
  if (compression == "bz2") return decompressBz2(compressed, decompressed);
  if (compression == "lz4") return decompressLz4(compressed, decompressed);
  return "compression '" + compression + "' is neither bz2 nor lz4";
}

}  // namespace detail
}  // namespace offline
}  // namespace rfm
