#include "bag_chunk_check.h"

#include "bag_byte_source.h"
#include "bag_chunk_decompression.h"
#include "bag_record_reader.h"

#include <algorithm>
#include <atomic>
#include <cstring>
#include <exception>
#include <limits>
#include <mutex>
#include <new>
#include <system_error>
#include <thread>

namespace rfm {
namespace offline {
namespace detail {
namespace {

constexpr size_t kIndexEntryBytes = 12;  // time (8), offset in the chunk (4)
// rosbag's own reader (readBagScans) reads with two threads; decompressing a bz2 bag dominates
// the check, so it takes the same two.
constexpr size_t kCheckThreads = 2;

// One thread's reader: its own file handle and buffers, reused from chunk to chunk.
class ChunkChecker {
 public:
  explicit ChunkChecker(const std::string& path) : file_(path) {
    if (!file_.isOpen()) throw BagStructureError("the file cannot be opened for reading");
  }

  void check(const ChunkToCheck& chunk) {
    message_offsets_.clear();
    if (chunk.compression == "none") {
      checkRecords(
          ByteRange{file_, chunk.data_start, chunk.data_start + chunk.data_length, "its chunk"});
    } else {
      decompress(chunk);
      ChunkSource decompressed(decompressed_, chunk.compression, chunk.record);
      checkRecords(ByteRange{decompressed, 0, decompressed_.size(), "its chunk"});
    }
    checkIndexEntries(chunk);
  }

 private:
  void decompress(const ChunkToCheck& chunk) {
    const std::string where = file_.describe(chunk.record);
    try {
      compressed_.resize(chunk.data_length);
      decompressed_.resize(chunk.size);
    } catch (const std::bad_alloc&) {
      throw BagStructureError(where + ": not enough memory to decompress the chunk (" +
                              std::to_string(chunk.size) + " bytes)");
    }
    file_.read(chunk.data_start, chunk.data_length, compressed_.data());
    const std::string problem = decompressChunk(chunk.compression, compressed_, decompressed_);
    if (!problem.empty()) {
      throw BagStructureError(where + ": the " + chunk.compression + " chunk's data: " + problem);
    }
  }

  // Remembers where the message data records start, counted from the data's start.
  void checkRecords(const ByteRange& range) {
    for (uint64_t at = range.begin; at < range.end;) {
      const RecordLayout record = readRecord(range, at, fields_);
      const int op = fields_.op();
      if (op == rosbag::OP_MSG_DATA) {
        message_offsets_.push_back(static_cast<uint32_t>(record.start - range.begin));
      }
      if (op == rosbag::OP_CONNECTION) readConnectionHeader(range, record, connection_fields_);
      at = record.end();
    }
  }

  void checkIndexEntries(const ChunkToCheck& chunk) {
    for (const auto& [entries_start, count] : chunk.index_entries) {
      for (uint32_t entry = 0; entry < count; ++entry) {
        const uint64_t entry_at = entries_start + uint64_t{entry} * kIndexEntryBytes;
        char bytes[kIndexEntryBytes];
        file_.read(entry_at, sizeof(bytes), bytes);
        uint32_t offset = 0;
        std::memcpy(&offset, bytes + 8, sizeof(offset));
        if (!std::binary_search(message_offsets_.begin(), message_offsets_.end(), offset)) {
          throw BagStructureError(file_.describe(entry_at) + ": the index entry's offset " +
                                  std::to_string(offset) +
                                  " is not where a message record starts in the chunk at byte " +
                                  std::to_string(chunk.record));
        }
      }
    }
  }

  FileSource file_;
  HeaderFields fields_;
  HeaderFields connection_fields_;
  std::vector<uint32_t> message_offsets_;  // ascending: records are read in order
  ByteBuffer compressed_;
  ByteBuffer decompressed_;
};

// The first failure in chunk order, whichever thread finds it.
class FirstFailure {
 public:
  static constexpr size_t kNone = std::numeric_limits<size_t>::max();

  void record(size_t chunk, const std::string& reason) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (chunk < chunk_) {
      chunk_ = chunk;
      reason_ = reason;
    }
    earliest_.store(chunk_);
  }
  // Chunks after a failed one need no check: chunks are taken in order, so every earlier one is
  // already being checked.
  bool makesMoot(size_t chunk) const { return chunk > earliest_.load(); }
  void rethrow() const {
    if (chunk_ != kNone) throw BagStructureError(reason_);
  }

 private:
  std::mutex mutex_;
  size_t chunk_ = kNone;
  std::string reason_;
  std::atomic<size_t> earliest_{kNone};
};

}  // namespace

void checkChunks(const std::string& path, const std::vector<ChunkToCheck>& chunks) {
  std::atomic<size_t> next{0};
  FirstFailure failure;
  auto work = [&] {
    try {
      ChunkChecker checker(path);
      for (size_t chunk = next++; chunk < chunks.size() && !failure.makesMoot(chunk);
           chunk = next++) {
        try {
          checker.check(chunks[chunk]);
        } catch (const BagStructureError& error) {
          failure.record(chunk, error.what());
        } catch (const std::bad_alloc&) {
          failure.record(chunk, "byte " + std::to_string(chunks[chunk].record) +
                                    ": not enough memory to check the chunk");
        } catch (const std::exception& error) {  // nothing may leave a thread
          failure.record(chunk, "byte " + std::to_string(chunks[chunk].record) +
                                    ": the chunk cannot be checked: " + error.what());
        }
      }
    } catch (const BagStructureError& error) {  // the file cannot be opened again
      failure.record(0, error.what());
    }
  };
  if (chunks.empty()) return;
  std::vector<std::thread> threads;
  for (size_t t = 1; t < std::min(kCheckThreads, chunks.size()); ++t) {
    try {
      threads.emplace_back(work);
    } catch (const std::system_error&) {
      break;  // no thread to spare: this one checks them all
    }
  }
  work();
  for (std::thread& thread : threads)
    thread.join();
  failure.rethrow();
}

}  // namespace detail
}  // namespace offline
}  // namespace rfm
