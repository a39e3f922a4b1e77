// checkBagStructure: bags written here with rosbag (uncompressed, bz2, lz4) pass; the crafted
// bags of the fuzz corpus, truncations and lengths changed in place (also inside a compressed
// chunk) are refused with a reason that says where; readBagScans refuses them before rosbag.

#include "reflectance_field_map/offline/bag_structure.h"
#include "../scratch_directory_test.h"
#include "reflectance_field_map/offline/bag_input.h"

#include <bzlib.h>
#include <rosbag/bag.h>
#include <roslz4/lz4s.h>
#include <sensor_msgs/LaserScan.h>
#include <tf2_msgs/TFMessage.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using rfm::offline::checkBagStructure;

constexpr size_t kBagHeaderStart = 13;  // after "#ROSBAG V2.0\n"

std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream all;
  all << in.rdbuf();
  return all.str();
}

void writeFile(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
}

uint32_t uint32At(const std::string& bytes, size_t at) {
  uint32_t value = 0;
  std::memcpy(&value, bytes.data() + at, 4);
  return value;
}

void putUint32(std::string& bytes, size_t at, uint32_t value) {
  std::memcpy(&bytes[at], &value, 4);
}

void putUint64(std::string& bytes, size_t at, uint64_t value) {
  std::memcpy(&bytes[at], &value, 8);
}

// Where a record's parts are in `bytes` (trusted: the bags here are written by rosbag).
struct RawRecord {
  size_t start = 0, header_start = 0, header_length = 0, data_start = 0, data_length = 0;
  size_t end() const { return data_start + data_length; }
};

RawRecord recordAt(const std::string& bytes, size_t at) {
  RawRecord record;
  record.start = at;
  record.header_start = at + 4;
  record.header_length = uint32At(bytes, at);
  record.data_length = uint32At(bytes, record.header_start + record.header_length);
  record.data_start = record.header_start + record.header_length + 4;
  return record;
}

// Where the value of the header field `name` starts.
std::optional<size_t> fieldValueAt(const std::string& bytes, const RawRecord& record,
                                   const std::string& name) {
  for (size_t at = record.header_start; at < record.header_start + record.header_length;) {
    const uint32_t length = uint32At(bytes, at);
    if (bytes.compare(at + 4, name.size() + 1, name + "=") == 0) return at + 4 + name.size() + 1;
    at += 4 + length;
  }
  return std::nullopt;
}

int opOf(const std::string& bytes, const RawRecord& record) {
  const std::optional<size_t> op = fieldValueAt(bytes, record, "op");
  return op ? static_cast<unsigned char>(bytes[*op]) : -1;
}

std::vector<RawRecord> records(const std::string& bytes, size_t from, size_t to) {
  std::vector<RawRecord> found;
  for (size_t at = from; at < to; at = found.back().end())
    found.push_back(recordAt(bytes, at));
  return found;
}

RawRecord firstWithOp(const std::string& bytes, const std::vector<RawRecord>& all, int op) {
  for (const RawRecord& record : all)
    if (opOf(bytes, record) == op) return record;
  ADD_FAILURE() << "no record of op " << op;
  return {};
}

std::string bz2Compress(std::string data) {
  std::string out(data.size() + data.size() / 100 + 1024, '\0');
  unsigned int length = static_cast<unsigned int>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffCompress(out.data(), &length, data.data(),
                                     static_cast<unsigned int>(data.size()), 9, 0, 30),
            BZ_OK);
  out.resize(length);
  return out;
}

std::string bz2Decompress(std::string data, size_t size) {
  std::string out(size, '\0');
  unsigned int length = static_cast<unsigned int>(size);
  EXPECT_EQ(BZ2_bzBuffToBuffDecompress(out.data(), &length, data.data(),
                                       static_cast<unsigned int>(data.size()), 0, 0),
            BZ_OK);
  return out;
}

std::string lz4Compress(std::string data) {
  std::string out(data.size() + data.size() / 100 + (1 << 20), '\0');
  unsigned int length = static_cast<unsigned int>(out.size());
  EXPECT_EQ(roslz4_buffToBuffCompress(data.data(), static_cast<unsigned int>(data.size()),
                                      out.data(), &length, 6),
            ROSLZ4_OK);
  out.resize(length);
  return out;
}

std::string lz4Decompress(std::string data, size_t size) {
  std::string out(size, '\0');
  unsigned int length = static_cast<unsigned int>(size);
  EXPECT_EQ(roslz4_buffToBuffDecompress(data.data(), static_cast<unsigned int>(data.size()),
                                        out.data(), &length),
            ROSLZ4_OK);
  return out;
}

struct Compression {
  rosbag::CompressionType type;
  const char* name;
};
const Compression kCompressions[] = {{rosbag::compression::Uncompressed, "none"},
                                     {rosbag::compression::BZ2, "bz2"},
                                     {rosbag::compression::LZ4, "lz4"}};

class BagStructure : public rfm_test::ScratchDirectoryTest {
 protected:
  // 40 scans of 360 beams on /scan_front and a TF message before each; `chunk_bytes` small
  // gives several chunks.
  std::string writeBag(const std::string& name, rosbag::CompressionType compression,
                       uint32_t chunk_bytes = 768 * 1024) {
    const std::string file = path(name);
    rosbag::Bag bag(file, rosbag::bagmode::Write);
    bag.setCompression(compression);
    bag.setChunkThreshold(chunk_bytes);
    for (int i = 0; i < 40; ++i) {
      const ros::Time stamp(1000.0 + 0.1 * i);
      tf2_msgs::TFMessage tf;
      tf.transforms.resize(1);
      tf.transforms[0].header.stamp = stamp;
      tf.transforms[0].header.frame_id = "odom";
      tf.transforms[0].child_frame_id = "laser";
      tf.transforms[0].transform.translation.x = 0.01 * i;
      tf.transforms[0].transform.rotation.w = 1.0;
      bag.write("/tf", stamp, tf);
      sensor_msgs::LaserScan scan;
      scan.header.stamp = stamp;
      scan.header.frame_id = "laser";
      scan.angle_min = -3.1f;
      scan.angle_increment = 6.2f / 360;
      scan.angle_max = scan.angle_min + 359 * scan.angle_increment;
      scan.range_max = 30.0f;
      for (int b = 0; b < 360; ++b) {
        scan.ranges.push_back(2.0f + 0.001f * static_cast<float>((b * 7 + i * 13) % 1000));
        scan.intensities.push_back(static_cast<float>((b + i) % 50));
      }
      bag.write("/scan_front", stamp, scan);
    }
    bag.close();
    return file;
  }

  // Writes `bytes` as `name` and returns checkBagStructure's reason for it.
  std::string check(const std::string& name, const std::string& bytes) {
    writeFile(path(name), bytes);
    return checkBagStructure(path(name));
  }
};

TEST_F(BagStructure, BagsWrittenByRosbagPass) {
  for (const Compression& compression : kCompressions) {
    for (uint32_t chunk_bytes : {768u * 1024u, 16u * 1024u}) {
      const std::string name = std::string(compression.name) + std::to_string(chunk_bytes);
      const std::string bag = writeBag(name + ".bag", compression.type, chunk_bytes);
      const std::string bytes = readFile(bag);
      const std::vector<RawRecord> all = records(bytes, kBagHeaderStart, bytes.size());
      const RawRecord chunk = firstWithOp(bytes, all, 0x05);
      ASSERT_EQ(bytes.compare(*fieldValueAt(bytes, chunk, "compression"),
                              std::strlen(compression.name), compression.name),
                0);
      EXPECT_EQ(checkBagStructure(bag), "") << name;
    }
  }
}

TEST_F(BagStructure, AnEmptyBagPasses) {
  { rosbag::Bag bag(path("empty.bag"), rosbag::bagmode::Write); }
  EXPECT_EQ(checkBagStructure(path("empty.bag")), "");
}

TEST_F(BagStructure, AMissingFileIsRefused) {
  EXPECT_EQ(checkBagStructure(path("missing.bag")), "the file cannot be opened for reading");
}

// The crafted bags that crash or exhaust rosbag (doc/fuzzing.md, Findings), each refused at its
// first problem: the file's records are checked before the inside of its chunks.
TEST_F(BagStructure, TheFuzzFindingsAreRefused) {
  const std::string corpus = RFM_SOURCE_DIR "/test/fuzz/corpus/bag_scans/";
  const std::pair<const char*, const char*> findings[] = {
      {"crash_oom_connection_header_length.bag",
       "byte 6956: the record's header claims 2248839796 bytes, past the end of the file (2607 "
       "bytes left)"},
      {"crash_overflow_header_field_length.bag",
       "byte 17: a header field claims 65540 bytes, past the end of its header (65 bytes left)"},
      {"crash_overflow_connection_field_length.bag",
       "byte 9336: a connection header field claims 64794 bytes, past the end of its connection "
       "header (26 bytes left)"},
      {"crash_lz4_block_past_frame_block_size.bag",
       "byte 4117: the lz4 chunk's data: frame byte 7: a block of 131072 bytes, larger than the "
       "frame's block size (65536)"},
      {"crash_overflow_loose_version_line.bag",
       "byte 0: the file does not start with the line #ROSBAG V2.0 of a ROS bag (format 2.0)"},
  };
  for (const auto& [file, reason] : findings) {
    ASSERT_TRUE(fs::is_regular_file(corpus + file)) << file;
    EXPECT_EQ(checkBagStructure(corpus + file), reason) << file;
  }
}

TEST_F(BagStructure, VersionLinesOtherThanExactly2Point0AreRefused) {
  const std::string bytes = readFile(writeBag("good.bag", rosbag::compression::Uncompressed));
  for (const char* line :
       {"#ROSBAG V1.2\n", "#ROSBAG\tV2.0\n", "#ROSBAQ V2.0\n", "#ROSBAG V2.0 ", "#ROSBAG  V2.0"}) {
    std::string changed = bytes;
    changed.replace(0, kBagHeaderStart, line);
    EXPECT_NE(check("version.bag", changed).find("does not start with the line #ROSBAG V2.0"),
              std::string::npos)
        << line;
  }
  EXPECT_NE(check("text.bag", "this is not a bag\n").find("does not start"), std::string::npos);
  EXPECT_NE(check("empty.bag", "").find("does not start"), std::string::npos);
}

TEST_F(BagStructure, TruncationsAreRefused) {
  for (const Compression& compression : kCompressions) {
    const std::string bytes =
        readFile(writeBag(std::string(compression.name) + ".bag", compression.type, 16 * 1024));
    std::vector<size_t> cuts = {1, 12, 13, 16, 40, 4000, bytes.size() - 1};
    for (size_t part = 1; part < 40; ++part)
      cuts.push_back(bytes.size() * part / 40);
    for (const RawRecord& record : records(bytes, kBagHeaderStart, bytes.size()))
      cuts.push_back(record.start);  // at a record boundary: the index is gone
    for (size_t cut : cuts) {
      EXPECT_NE(check("cut.bag", bytes.substr(0, cut)), "")
          << compression.name << " cut at " << cut;
    }
  }
}

TEST_F(BagStructure, ALengthChangedInAnUncompressedChunkIsRefused) {
  const std::string bytes = readFile(writeBag("good.bag", rosbag::compression::Uncompressed));
  const RawRecord chunk = firstWithOp(bytes, records(bytes, kBagHeaderStart, bytes.size()), 0x05);
  const RawRecord message = firstWithOp(bytes, records(bytes, chunk.data_start, chunk.end()), 0x02);
  std::string changed = bytes;
  putUint32(changed, message.data_start - 4, 0x7FFFFF00u);
  const std::string reason = check("changed.bag", changed);
  EXPECT_NE(reason.find("byte " + std::to_string(message.start) +
                        ": the record's data claims 2147483392 bytes, past the end of its chunk"),
            std::string::npos)
      << reason;
}

// Chunks are checked two at a time: with two bad chunks, the earlier one is named, every time.
TEST_F(BagStructure, TheFirstBadChunkIsNamed) {
  const std::string bytes =
      readFile(writeBag("good.bag", rosbag::compression::Uncompressed, 16 * 1024));
  std::vector<RawRecord> chunks;
  for (const RawRecord& record : records(bytes, kBagHeaderStart, bytes.size()))
    if (opOf(bytes, record) == 0x05) chunks.push_back(record);
  ASSERT_GE(chunks.size(), 5u);
  std::string changed = bytes;
  size_t first_bad = 0;
  for (size_t bad : {size_t{4}, size_t{2}}) {
    const RawRecord message =
        firstWithOp(bytes, records(bytes, chunks[bad].data_start, chunks[bad].end()), 0x02);
    putUint32(changed, message.data_start - 4, 0x7FFFFF00u);
    first_bad = message.start;
  }
  for (int run = 0; run < 20; ++run) {
    EXPECT_EQ(check("two_bad.bag", changed).rfind("byte " + std::to_string(first_bad) + ": ", 0),
              0u);
  }
}

uint64_t uint64At(const std::string& bytes, size_t at) {
  uint64_t value = 0;
  std::memcpy(&value, bytes.data() + at, 8);
  return value;
}

// A message record's data length inside a compressed chunk made huge, the chunk compressed
// again and spliced in (index_pos moved by the change in size): refused, naming the position in
// the decompressed chunk. The same splice without the change passes.
TEST_F(BagStructure, ALengthChangedInACompressedChunkIsRefused) {
  for (const Compression& compression : kCompressions) {
    const std::string kind = compression.name;
    if (kind == "none") continue;
    const std::string bytes = readFile(writeBag(kind + ".bag", compression.type));
    const std::vector<RawRecord> all = records(bytes, kBagHeaderStart, bytes.size());
    ASSERT_EQ(opOf(bytes, all[1]), 0x05);
    ASSERT_NE(opOf(bytes, all[2]), 0x05) << "one chunk, right after the bag header";
    const RawRecord& chunk = all[1];
    const size_t size = uint32At(bytes, *fieldValueAt(bytes, chunk, "size"));
    const std::string data = bytes.substr(chunk.data_start, chunk.data_length);
    const std::string decompressed =
        kind == "lz4" ? lz4Decompress(data, size) : bz2Decompress(data, size);
    const RawRecord message = firstWithOp(decompressed, records(decompressed, 0, size), 0x02);

    auto splice = [&](const std::string& chunk_data) {
      const std::string compressed =
          kind == "lz4" ? lz4Compress(chunk_data) : bz2Compress(chunk_data);
      std::string spliced = bytes.substr(0, chunk.data_start - 4) + std::string(4, '\0') +
                            compressed + bytes.substr(chunk.end());
      putUint32(spliced, chunk.data_start - 4, static_cast<uint32_t>(compressed.size()));
      const size_t index_pos =
          *fieldValueAt(spliced, recordAt(spliced, kBagHeaderStart), "index_pos");
      putUint64(spliced, index_pos,
                uint64At(spliced, index_pos) + compressed.size() - chunk.data_length);
      return spliced;
    };
    EXPECT_EQ(check("same.bag", splice(decompressed)), "") << kind;
    std::string changed = decompressed;
    putUint32(changed, message.data_start - 4, 0x7FFFFF00u);
    const std::string reason = check("changed.bag", splice(changed));
    EXPECT_NE(reason.find("byte " + std::to_string(message.start) + " of the " + kind +
                          " chunk at byte " + std::to_string(chunk.start) +
                          ", decompressed: the record's data claims 2147483392 bytes, past the "
                          "end of its chunk"),
              std::string::npos)
        << reason;
  }
}

// The first lz4 block's size made larger than the frame's block size (1 MiB, as rosbag writes
// it): roslz4 copies a block into a buffer of the frame's block size without comparing them.
TEST_F(BagStructure, AnLz4BlockLargerThanItsFrameAllowsIsRefused) {
  const std::string bytes = readFile(writeBag("lz4.bag", rosbag::compression::LZ4));
  const RawRecord chunk = firstWithOp(bytes, records(bytes, kBagHeaderStart, bytes.size()), 0x05);
  std::string changed = bytes;
  const size_t first_block = chunk.data_start + 7;
  ASSERT_LT(uint32At(bytes, first_block) & 0x7FFFFFFFu, 1u << 20);
  putUint32(changed, first_block, (1u << 20) + 1u);
  const std::string reason = check("block.bag", changed);
  EXPECT_NE(reason.find("byte " + std::to_string(chunk.start) +
                        ": the lz4 chunk's data: frame byte 7: a block of 1048577 bytes, larger "
                        "than the frame's block size (1048576)"),
            std::string::npos)
      << reason;
}

TEST_F(BagStructure, AChunkClaimingMoreThanItsDataCanHoldIsRefused) {
  for (const Compression& compression : kCompressions) {
    const std::string kind = compression.name;
    if (kind == "none") continue;
    const std::string bytes = readFile(writeBag(kind + ".bag", compression.type));
    const RawRecord chunk = firstWithOp(bytes, records(bytes, kBagHeaderStart, bytes.size()), 0x05);
    const size_t size_at = *fieldValueAt(bytes, chunk, "size");
    std::string changed = bytes;
    putUint32(changed, size_at, 0xFFFFFFF0u);
    std::string reason = check("huge.bag", changed);
    EXPECT_NE(reason.find("claims 4294967280 bytes decompressed, more than the 16777216 taken"),
              std::string::npos)
        << reason;
    // One byte more than the data hold: decompression shows it.
    changed = bytes;
    putUint32(changed, size_at, uint32At(bytes, size_at) + 1);
    reason = check("one_more.bag", changed);
    EXPECT_NE(
        reason.find("chunk's data: they decompress to " + std::to_string(uint32At(bytes, size_at)) +
                    " bytes, not the chunk's size field"),
        std::string::npos)
        << reason;
  }
}

TEST_F(BagStructure, PositionsThatMissARecordAreRefused) {
  const std::string bytes =
      readFile(writeBag("good.bag", rosbag::compression::Uncompressed, 16 * 1024));
  const std::vector<RawRecord> all = records(bytes, kBagHeaderStart, bytes.size());
  const size_t index_pos = *fieldValueAt(bytes, all[0], "index_pos");

  std::string changed = bytes;
  putUint64(changed, index_pos, uint64At(bytes, index_pos) + 1);
  EXPECT_NE(check("index_pos.bag", changed).find("is inside the record at byte"),
            std::string::npos);

  changed = bytes;
  putUint64(changed, index_pos, 0);
  EXPECT_NE(check("unindexed.bag", changed).find("index_pos is 0: the bag was never closed"),
            std::string::npos);

  const RawRecord chunk_info = firstWithOp(bytes, all, 0x06);
  const size_t chunk_pos = *fieldValueAt(bytes, chunk_info, "chunk_pos");
  changed = bytes;
  putUint64(changed, chunk_pos, uint64At(bytes, chunk_pos) + 4);
  EXPECT_NE(check("chunk_pos.bag", changed)
                .find("byte " + std::to_string(chunk_info.start) + ": the chunk info's chunk_pos"),
            std::string::npos);

  const RawRecord index = firstWithOp(bytes, all, 0x04);
  changed = bytes;
  putUint32(changed, index.data_start + 8, uint32At(bytes, index.data_start + 8) + 1);
  EXPECT_NE(check("entry.bag", changed)
                .find("byte " + std::to_string(index.data_start) + ": the index entry's offset"),
            std::string::npos);
}

TEST_F(BagStructure, CountsThatDisagreeWithTheDataAreRefused) {
  const std::string bytes =
      readFile(writeBag("good.bag", rosbag::compression::Uncompressed, 16 * 1024));
  const std::vector<RawRecord> all = records(bytes, kBagHeaderStart, bytes.size());

  std::string changed = bytes;
  const size_t connections = *fieldValueAt(bytes, all[0], "conn_count");
  putUint32(changed, connections, uint32At(bytes, connections) + 1);
  EXPECT_NE(check("conn_count.bag", changed).find("is not a connection record"), std::string::npos);

  changed = bytes;
  const size_t chunk_infos = *fieldValueAt(bytes, all[0], "chunk_count");
  putUint32(changed, chunk_infos, uint32At(bytes, chunk_infos) + 1);
  EXPECT_NE(check("chunk_count.bag", changed).find("the file ends after"), std::string::npos);

  const RawRecord index = firstWithOp(bytes, all, 0x04);
  changed = bytes;
  const size_t index_count = *fieldValueAt(bytes, index, "count");
  putUint32(changed, index_count, uint32At(bytes, index_count) + 1);
  EXPECT_NE(check("index_count.bag", changed).find("entries of 12 bytes, but its data holds"),
            std::string::npos);

  const RawRecord chunk_info = firstWithOp(bytes, all, 0x06);
  changed = bytes;
  const size_t info_count = *fieldValueAt(bytes, chunk_info, "count");
  putUint32(changed, info_count, uint32At(bytes, info_count) + 1);
  EXPECT_NE(check("info_count.bag", changed).find("connections of 8 bytes, but its data holds"),
            std::string::npos);
}

TEST_F(BagStructure, AnEncryptedBagIsRefused) {
  std::string bytes = readFile(writeBag("good.bag", rosbag::compression::Uncompressed));
  const RawRecord header = recordAt(bytes, kBagHeaderStart);
  // Replace the padding's first bytes by an encryptor field: the header grows, the data shrinks.
  const std::string field = "encryptor=rosbag/AesCbcEncryptor";
  std::string grown(4, '\0');
  putUint32(grown, 0, static_cast<uint32_t>(field.size()));
  grown += field;
  std::string changed = bytes.substr(0, header.header_start + header.header_length) + grown +
                        bytes.substr(header.header_start + header.header_length);
  putUint32(changed, header.start, static_cast<uint32_t>(header.header_length + grown.size()));
  const size_t length_at = header.header_start + header.header_length + grown.size();
  putUint32(changed, length_at, static_cast<uint32_t>(header.data_length - grown.size()));
  changed.erase(length_at + 4, grown.size());
  ASSERT_EQ(changed.size(), bytes.size());
  EXPECT_NE(check("encrypted.bag", changed).find("the bag is encrypted (rosbag/AesCbcEncryptor)"),
            std::string::npos);
}

// readBagScans refuses a bag the check refuses, before rosbag opens it, and keeps its advice for
// a recording cut short.
TEST_F(BagStructure, ReadBagScansRefusesWhatTheCheckRefuses) {
  rfm::offline::BagInputOptions options;
  options.scan_topics = {"/scan_front"};
  options.fixed_frame = "laser";
  options.base_frame = "laser";
  options.bag = RFM_SOURCE_DIR "/test/fuzz/corpus/bag_scans/crash_oom_connection_header_length.bag";
  try {
    rfm::offline::readBagScans(options);
    ADD_FAILURE() << "a crafted bag was read";
  } catch (const rfm::offline::BagInputError& error) {
    EXPECT_NE(
        std::string(error.what())
            .find("cannot read bag " + options.bag + ": byte 6956: the record's header claims"),
        std::string::npos)
        << error.what();
  }

  const std::string bytes = readFile(writeBag("good.bag", rosbag::compression::LZ4));
  options.bag = path("good.bag");
  EXPECT_EQ(rfm::offline::readBagScans(options).scans.size(), 40u);
  writeFile(path("cut.bag"), bytes.substr(0, bytes.size() * 2 / 3));
  options.bag = path("cut.bag");
  try {
    rfm::offline::readBagScans(options);
    ADD_FAILURE() << "a truncated bag was read";
  } catch (const rfm::offline::BagInputError& error) {
    EXPECT_NE(std::string(error.what()).find("rosbag reindex " + options.bag), std::string::npos)
        << error.what();
  }
}

}  // namespace
