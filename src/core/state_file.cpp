#include "reflectance_field_map/core/state_file.h"

#include <algorithm>
#include <cstring>
#include <istream>
#include <ostream>

namespace rfm {
namespace {

constexpr char kMagic[8] = {'R', 'F', 'M', 'S', 'T', 'A', 'T', 'E'};
// Payloads arrive in pieces of this size, so a forged length costs no more than the file holds.
constexpr size_t kReadPiece = size_t{1} << 20;

void putU32(char* out, uint32_t value) {
  for (int i = 0; i < 4; ++i)
    out[i] = static_cast<char>((value >> (8 * i)) & 0xffu);
}

void putU64(char* out, uint64_t value) {
  for (int i = 0; i < 8; ++i)
    out[i] = static_cast<char>((value >> (8 * i)) & 0xffu);
}

uint32_t getU32(const char* in) {
  uint32_t value = 0;
  for (int i = 0; i < 4; ++i)
    value |= static_cast<uint32_t>(static_cast<unsigned char>(in[i])) << (8 * i);
  return value;
}

uint64_t getU64(const char* in) {
  uint64_t value = 0;
  for (int i = 0; i < 8; ++i)
    value |= static_cast<uint64_t>(static_cast<unsigned char>(in[i])) << (8 * i);
  return value;
}

bool fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

}  // namespace

uint64_t fnv1a64(const void* data, size_t size, uint64_t hash) {
  const auto* bytes = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash ^= bytes[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

void writeStateFile(std::ostream& out, const std::string& payload) {
  char header[kStateFileHeaderBytes] = {};
  std::memcpy(header, kMagic, sizeof(kMagic));
  putU32(header + 8, kStateFileVersion);
  putU32(header + 12, 0);
  putU64(header + 16, payload.size());
  putU64(header + 24, fnv1a64(payload.data(), payload.size()));
  out.write(header, sizeof(header));
  out.write(payload.data(), static_cast<std::streamsize>(payload.size()));
}

bool readStateFile(std::istream& in, uint64_t max_payload_bytes, std::string& payload,
                   std::string* error) {
  payload.clear();
  char header[kStateFileHeaderBytes];
  if (!in.read(header, sizeof(header))) {
    return fail(error, "too short for a saved state (" + std::to_string(in.gcount()) + " bytes)");
  }
  if (std::memcmp(header, kMagic, sizeof(kMagic)) != 0) {
    if (std::memcmp(header, "SMFR", 4) == 0) {
      return fail(error,
                  "saved without a checksum by an older version of rfm: it cannot be verified "
                  "(map again and save)");
    }
    return fail(error, "not a saved rfm state (no RFMSTATE header)");
  }
  const uint32_t version = getU32(header + 8);
  if (version != kStateFileVersion) {
    return fail(error, "saved state format version " + std::to_string(version) +
                           ", this build reads version " + std::to_string(kStateFileVersion));
  }
  const uint64_t length = getU64(header + 16);
  const uint64_t checksum = getU64(header + 24);
  if (length > max_payload_bytes) {
    return fail(error, "the header claims " + std::to_string(length) +
                           " bytes of state, more than the limit of " +
                           std::to_string(max_payload_bytes));
  }
  uint64_t hash = kFnvOffsetBasis;
  while (payload.size() < length) {
    const size_t piece =
        static_cast<size_t>(std::min<uint64_t>(kReadPiece, length - payload.size()));
    const size_t start = payload.size();
    payload.resize(start + piece);
    in.read(&payload[start], static_cast<std::streamsize>(piece));
    const size_t got = static_cast<size_t>(in.gcount());
    hash = fnv1a64(&payload[start], got, hash);
    if (got < piece) {
      const uint64_t have = start + got;
      payload.clear();
      payload.shrink_to_fit();
      return fail(error, "truncated: " + std::to_string(have) + " of " + std::to_string(length) +
                             " bytes of state");
    }
  }
  if (in.peek() != std::char_traits<char>::eof()) {
    payload.clear();
    return fail(error, "data after the end of the saved state");
  }
  if (hash != checksum) {
    payload.clear();
    payload.shrink_to_fit();
    return fail(error, "checksum mismatch: the file is corrupt");
  }
  return true;
}

}  // namespace rfm
