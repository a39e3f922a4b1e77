#include "reflectance_field_map/offline/bag_structure.h"

#include "bag_byte_source.h"
#include "bag_chunk_check.h"
#include "bag_chunk_decompression.h"
#include "bag_record_reader.h"

#include <algorithm>
#include <cstring>
#include <optional>
#include <string_view>
#include <utility>
#include <vector>

namespace rfm {
namespace offline {
namespace {

using detail::BagStructureError;
using detail::ByteRange;
using detail::ByteSource;
using detail::HeaderFields;
using detail::RecordLayout;

constexpr char kVersionLine[] = "#ROSBAG V2.0\n";
constexpr uint64_t kBagHeaderStart = sizeof(kVersionLine) - 1;
constexpr uint32_t kIndexEntryBytes = 12;     // time (8), offset in the chunk (4)
constexpr uint32_t kChunkInfoEntryBytes = 8;  // connection, message count
constexpr uint32_t kIndexVersion = 1;         // rosbag reads no other
constexpr const char* kNoEncryptor = "rosbag/NoEncryptor";

std::string number(uint64_t value) {
  return std::to_string(value);
}

// The records rosbag reads from the bag header's index_pos: conn_count connection records, then
// chunk_count chunk info records, in that order.
class IndexSequence {
 public:
  IndexSequence(uint64_t index_pos, uint32_t connections, uint32_t chunk_infos)
      : index_pos_(index_pos), connections_(connections), chunk_infos_(chunk_infos) {}

  // Called for each top-level record in file order.
  void visit(const RecordLayout& record, int op, ByteSource& source) {
    if (!reached_) {
      if (record.start == index_pos_) {
        reached_ = true;
      } else if (record.end() > index_pos_) {
        throw BagStructureError("byte 13: the bag header's index_pos " + number(index_pos_) +
                                " is inside the record at " + source.describe(record.start) +
                                ", not where a record starts");
      } else {
        return;
      }
    }
    if (seen_ >= uint64_t{connections_} + chunk_infos_) return;
    const bool connection = seen_ < connections_;
    if (op != (connection ? rosbag::OP_CONNECTION : rosbag::OP_CHUNK_INFO)) {
      throw BagStructureError(source.describe(record.start) + ": record " + number(seen_ + 1) +
                              " of the bag's index (at byte " + number(index_pos_) + ") is not a " +
                              (connection ? "connection" : "chunk info") +
                              " record, as the bag header's conn_count " + number(connections_) +
                              " and chunk_count " + number(chunk_infos_) + " say");
    }
    ++seen_;
  }

  // Called at the end of the file.
  void finish(uint64_t file_size) const {
    const uint64_t expected = uint64_t{connections_} + chunk_infos_;
    if (seen_ == expected) return;
    // Not reached: index_pos is the file's end (visit refuses one inside a record).
    throw BagStructureError("byte " + number(file_size) + ": the file ends after " + number(seen_) +
                            " of the " + number(expected) +
                            " records the bag header counts from its index_pos " +
                            number(index_pos_) + " (conn_count " + number(connections_) +
                            ", chunk_count " + number(chunk_infos_) + ")");
  }

 private:
  uint64_t index_pos_;
  uint32_t connections_;
  uint32_t chunk_infos_;
  bool reached_ = false;
  uint64_t seen_ = 0;
};

// A streaming pass over the file's records; the inside of each chunk afterwards (checkChunks).
class BagStructureCheck {
 public:
  BagStructureCheck(detail::FileSource& file, std::string path)
      : file_(file), path_(std::move(path)) {}

  void run() {
    checkVersionLine();
    const ByteRange whole{file_, kBagHeaderStart, file_.size(), "the file"};
    IndexSequence index = readBagHeader(whole);
    for (uint64_t at = bag_header_end_; at < file_.size();) {
      const RecordLayout record = detail::readRecord(whole, at, fields_);
      const int op = fields_.op();
      index.visit(record, op, file_);
      if (op == rosbag::OP_CHUNK) checkChunkRecord(record);
      if (op == rosbag::OP_INDEX_DATA) checkIndexData(record);
      if (op == rosbag::OP_CHUNK_INFO) checkChunkInfo(record);
      if (op == rosbag::OP_CONNECTION) detail::readConnectionHeader(whole, record, fields_);
      at = record.end();
    }
    index.finish(file_.size());
    for (const auto& [chunk_info, chunk_pos] : chunk_positions_) {
      const auto chunk = std::lower_bound(
          chunks_.begin(), chunks_.end(), chunk_pos,
          [](const detail::ChunkToCheck& chunk, uint64_t at) { return chunk.record < at; });
      if (chunk == chunks_.end() || chunk->record != chunk_pos) {
        throw BagStructureError(file_.describe(chunk_info) + ": the chunk info's chunk_pos " +
                                number(chunk_pos) + " is not where a chunk record starts");
      }
    }
    detail::checkChunks(path_, chunks_);
  }

 private:
  void checkVersionLine() {
    char line[sizeof(kVersionLine) - 1] = {};
    if (file_.size() >= sizeof(line)) file_.read(0, sizeof(line), line);
    if (file_.size() < sizeof(line) || std::memcmp(line, kVersionLine, sizeof(line)) != 0) {
      throw BagStructureError(
          "byte 0: the file does not start with the line #ROSBAG V2.0 of a ROS bag "
          "(format 2.0)");
    }
  }

  IndexSequence readBagHeader(const ByteRange& whole) {
    const RecordLayout record = detail::readRecord(whole, kBagHeaderStart, fields_);
    const std::string where = file_.describe(record.start);
    if (fields_.op() != rosbag::OP_FILE_HEADER) {
      throw BagStructureError(where + ": the first record is not the bag header (op 3)");
    }
    const std::optional<uint64_t> index_pos = fields_.findUint64(rosbag::INDEX_POS_FIELD_NAME);
    const std::optional<uint32_t> connections =
        fields_.findUint32(rosbag::CONNECTION_COUNT_FIELD_NAME);
    const std::optional<uint32_t> chunk_infos = fields_.findUint32(rosbag::CHUNK_COUNT_FIELD_NAME);
    if (!index_pos || !connections || !chunk_infos) {
      throw BagStructureError(where +
                              ": the bag header lacks index_pos (8 bytes), conn_count or "
                              "chunk_count (4 bytes each)");
    }
    const std::optional<std::string_view> encryptor = fields_.find(rosbag::ENCRYPTOR_FIELD_NAME);
    if (encryptor && !encryptor->empty() && *encryptor != kNoEncryptor) {
      throw BagStructureError(where + ": the bag is encrypted (" + std::string(*encryptor) +
                              "); rfm_offline reads unencrypted bags only");
    }
    if (*index_pos == 0) {
      throw BagStructureError(where +
                              ": the bag header's index_pos is 0: the bag was never closed, so "
                              "it has no index");
    }
    if (*index_pos > file_.size()) {
      throw BagStructureError(where + ": the bag header's index_pos " + number(*index_pos) +
                              " is past the end of the file (" + number(file_.size()) + " bytes)");
    }
    if (*index_pos < record.end()) {
      throw BagStructureError(where + ": the bag header's index_pos " + number(*index_pos) +
                              " is not after the bag header");
    }
    bag_header_end_ = record.end();
    return IndexSequence(*index_pos, *connections, *chunk_infos);
  }

  // The chunk record itself; its data are checked by checkChunks.
  void checkChunkRecord(const RecordLayout& record) {
    const std::string where = file_.describe(record.start);
    const std::optional<std::string_view> compression =
        fields_.find(rosbag::COMPRESSION_FIELD_NAME);
    const std::optional<uint32_t> size = fields_.findUint32(rosbag::SIZE_FIELD_NAME);
    if (!compression || !size) {
      throw BagStructureError(where + ": the chunk lacks its compression or size (4 bytes)");
    }
    const std::string kind(*compression);
    if (kind != "none" && kind != "bz2" && kind != "lz4") {
      throw BagStructureError(where + ": the chunk's compression '" + kind +
                              "' is not one rosbag reads (none, bz2, lz4)");
    }
    if (kind != "none") {
      const uint64_t limit = detail::maxDecompressedChunkBytes(record.data_length);
      if (record.data_length > detail::kMaxChunkBytes || *size > limit) {
        throw BagStructureError(where + ": the " + kind + " chunk of " +
                                number(record.data_length) + " bytes claims " + number(*size) +
                                " bytes decompressed, more than the " + number(limit) +
                                " taken for it");
      }
    }
    detail::ChunkToCheck chunk;
    chunk.record = record.start;
    chunk.data_start = record.data_start;
    chunk.data_length = record.data_length;
    chunk.compression = kind;
    chunk.size = *size;
    chunks_.push_back(std::move(chunk));
  }

  void checkIndexData(const RecordLayout& record) {
    const std::string where = file_.describe(record.start);
    const std::optional<uint32_t> version = fields_.findUint32(rosbag::VER_FIELD_NAME);
    const std::optional<uint32_t> count = fields_.findUint32(rosbag::COUNT_FIELD_NAME);
    if (!version || *version != kIndexVersion || !count) {
      throw BagStructureError(where + ": the index record lacks ver 1 or its count (4 bytes)");
    }
    if (uint64_t{*count} * kIndexEntryBytes != record.data_length) {
      throw BagStructureError(where + ": the index record counts " + number(*count) +
                              " entries of 12 bytes, but its data holds " +
                              number(record.data_length) + " bytes");
    }
    if (*count == 0) return;
    if (chunks_.empty()) {
      throw BagStructureError(where + ": an index record with entries before any chunk");
    }
    // rosbag reads the index records that follow a chunk as that chunk's.
    chunks_.back().index_entries.emplace_back(record.data_start, *count);
  }

  void checkChunkInfo(const RecordLayout& record) {
    const std::string where = file_.describe(record.start);
    const std::optional<uint32_t> version = fields_.findUint32(rosbag::VER_FIELD_NAME);
    const std::optional<uint64_t> chunk_pos = fields_.findUint64(rosbag::CHUNK_POS_FIELD_NAME);
    const std::optional<uint32_t> count = fields_.findUint32(rosbag::COUNT_FIELD_NAME);
    if (!version || *version != kIndexVersion || !chunk_pos || !count) {
      throw BagStructureError(where +
                              ": the chunk info lacks ver 1, its chunk_pos (8 bytes) or its "
                              "count (4 bytes)");
    }
    if (uint64_t{*count} * kChunkInfoEntryBytes != record.data_length) {
      throw BagStructureError(where + ": the chunk info counts " + number(*count) +
                              " connections of 8 bytes, but its data holds " +
                              number(record.data_length) + " bytes");
    }
    chunk_positions_.emplace_back(record.start, *chunk_pos);
  }

  detail::FileSource& file_;
  std::string path_;
  HeaderFields fields_;  // the current record's
  uint64_t bag_header_end_ = 0;
  std::vector<detail::ChunkToCheck> chunks_;                    // in file order
  std::vector<std::pair<uint64_t, uint64_t>> chunk_positions_;  // chunk info record, chunk_pos
};

}  // namespace

std::string checkBagStructure(const std::string& path) {
  detail::FileSource file(path);
  if (!file.isOpen()) return "the file cannot be opened for reading";
  try {
    BagStructureCheck(file, path).run();
  } catch (const BagStructureError& error) {
    return error.what();
  }
  return {};
}

}  // namespace offline
}  // namespace rfm
