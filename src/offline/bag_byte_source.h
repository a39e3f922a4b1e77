#pragma once

// Bounded reads of a bag's bytes for the structure check (bag_structure.cpp): from the file
// through a fixed-size window, or from a decompressed chunk in memory. Each read names a range
// the caller has already checked lies inside the source.

#include <cstddef>
#include <cstdint>
#include <fstream>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rfm {
namespace offline {
namespace detail {

// What is wrong with a bag, where: the reason checkBagStructure returns.
class BagStructureError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class ByteSource {
 public:
  virtual ~ByteSource() = default;
  // Copies [at, at + length) into `out`.
  virtual void read(uint64_t at, size_t length, char* out) = 0;
  // Names a position for a reason: "byte 123", or where in which chunk.
  virtual std::string describe(uint64_t at) const = 0;
};

// A file read in pieces of at most kWindowBytes, so a record's skipped data costs no read and
// memory does not grow with the file.
class FileSource : public ByteSource {
 public:
  static constexpr size_t kWindowBytes = 256 * 1024;

  explicit FileSource(const std::string& path);
  bool isOpen() const { return open_; }
  uint64_t size() const { return size_; }
  void read(uint64_t at, size_t length, char* out) override;
  std::string describe(uint64_t at) const override;

 private:
  void readDirect(uint64_t at, size_t length, char* out);

  std::ifstream file_;
  bool open_ = false;
  uint64_t size_ = 0;
  std::vector<char> window_;
  uint64_t window_start_ = 0;
  size_t window_length_ = 0;
};

// Bytes that grow without being zero-filled, kept from chunk to chunk: a chunk's size need not
// cost a fill, and decompression writes every byte the check then reads.
class ByteBuffer {
 public:
  // Makes room for `size` bytes, their values unset.
  void resize(size_t size);
  char* data() { return data_.get(); }
  const char* data() const { return data_.get(); }
  size_t size() const { return size_; }

 private:
  std::unique_ptr<char[]> data_;
  size_t size_ = 0;
  size_t capacity_ = 0;
};

// A chunk's decompressed data, positions counted from its start.
class ChunkSource : public ByteSource {
 public:
  ChunkSource(const ByteBuffer& bytes, std::string compression, uint64_t chunk_record)
      : bytes_(bytes), compression_(std::move(compression)), chunk_record_(chunk_record) {}
  void read(uint64_t at, size_t length, char* out) override;
  std::string describe(uint64_t at) const override;

 private:
  const ByteBuffer& bytes_;
  std::string compression_;
  uint64_t chunk_record_;
};

// The part [begin, end) of a source that records are read from; `name` says what it is in a
// reason ("the file", "its chunk").
struct ByteRange {
  ByteSource& source;
  uint64_t begin;
  uint64_t end;
  const char* name;
};

}  // namespace detail
}  // namespace offline
}  // namespace rfm
