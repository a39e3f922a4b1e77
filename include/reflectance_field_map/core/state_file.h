#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>

namespace rfm {

// The envelope of a saved mapper state (PATH.rfm): a header that names the format, its version,
// the payload's length and a checksum over it, then the payload (Mapper::save's bytes). A reader
// verifies all of it before the payload reaches Mapper::load, so a truncated, flipped or foreign
// file is refused with a reason instead of being parsed.
//
// Layout, little-endian:
//   8 bytes  "RFMSTATE"
//   uint32   format version (kStateFileVersion)
//   uint32   reserved (0)
//   uint64   payload length in bytes
//   uint64   FNV-1a 64 of the payload
//   payload
constexpr uint32_t kStateFileVersion = 1;
constexpr size_t kStateFileHeaderBytes = 32;

// 64-bit FNV-1a of `size` bytes, continuing from `hash` (start with kFnvOffsetBasis).
constexpr uint64_t kFnvOffsetBasis = 0xcbf29ce484222325ull;
uint64_t fnv1a64(const void* data, size_t size, uint64_t hash = kFnvOffsetBasis);

void writeStateFile(std::ostream& out, const std::string& payload);

// Reads an envelope into `payload`. Memory grows only with bytes actually read, never with the
// length the header claims, and never past `max_payload_bytes`. False with `error` saying why
// (not a state file, an unknown version, too large, truncated, checksum mismatch, trailing data).
bool readStateFile(std::istream& in, uint64_t max_payload_bytes, std::string& payload,
                   std::string* error);

}  // namespace rfm
