#include "bag_byte_source.h"

#include <algorithm>
#include <cstring>

namespace rfm {
namespace offline {
namespace detail {

FileSource::FileSource(const std::string& path) {
  // Unbuffered: the window below is the only buffer, so a seek never discards read bytes twice.
  file_.rdbuf()->pubsetbuf(nullptr, 0);
  file_.open(path, std::ios::binary);
  if (!file_) return;
  file_.seekg(0, std::ios::end);
  const std::streamoff end = file_.tellg();
  if (!file_ || end < 0) return;
  size_ = static_cast<uint64_t>(end);
  open_ = true;
}

void FileSource::readDirect(uint64_t at, size_t length, char* out) {
  file_.clear();
  file_.seekg(static_cast<std::streamoff>(at));
  file_.read(out, static_cast<std::streamsize>(length));
  if (static_cast<size_t>(file_.gcount()) != length) {
    throw BagStructureError(describe(at) + ": the file cannot be read there (it changed while " +
                            "being checked, or a read error)");
  }
}

void FileSource::read(uint64_t at, size_t length, char* out) {
  if (at >= window_start_ && at - window_start_ + length <= window_length_) {
    std::memcpy(out, window_.data() + (at - window_start_), length);
    return;
  }
  if (length >= kWindowBytes) {
    readDirect(at, length, out);
    return;
  }
  window_.resize(kWindowBytes);
  window_start_ = at;
  window_length_ = 0;  // an exception below leaves no stale window
  const size_t filled = static_cast<size_t>(std::min<uint64_t>(kWindowBytes, size_ - at));
  if (filled < length) throw BagStructureError(describe(at) + ": read past the end of the file");
  readDirect(at, filled, window_.data());
  window_length_ = filled;
  std::memcpy(out, window_.data(), length);
}

std::string FileSource::describe(uint64_t at) const {
  return "byte " + std::to_string(at);
}

void ByteBuffer::resize(size_t size) {
  if (size > capacity_) {
    data_.reset(new char[size]);  // default-initialised: not filled
    capacity_ = size;
  }
  size_ = size;
}

void ChunkSource::read(uint64_t at, size_t length, char* out) {
  std::memcpy(out, bytes_.data() + at, length);
}

std::string ChunkSource::describe(uint64_t at) const {
  return "byte " + std::to_string(at) + " of the " + compression_ + " chunk at byte " +
         std::to_string(chunk_record_) + ", decompressed";
}

}  // namespace detail
}  // namespace offline
}  // namespace rfm
