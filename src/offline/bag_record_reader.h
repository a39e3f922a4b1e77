#pragma once

// One record of a ROS bag (format 2.0) read with every length it claims checked first: a 4-byte
// header length, the header (fields of a 4-byte length and "name=value"), a 4-byte data length
// and the data, all inside the range they are read from.

#include "bag_byte_source.h"

#include <rosbag/constants.h>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace rfm {
namespace offline {
namespace detail {

// A record header or a connection's header is small; rosbag's ros::Header::parse refuses a field
// over 1,000,000 bytes, so nothing rosbag writes comes near this.
constexpr uint32_t kMaxHeaderBytes = 1u << 20;

// The fields of a header as ros::Header::parse reads them: the name is what comes before the
// first '=', and a later field of a name replaces an earlier one.
class HeaderFields {
 public:
  // Reads the `length` bytes at `at` in `source` as fields; throws BagStructureError naming
  // `what` ("header", "connection header") when a field's length or bytes run past the end, or
  // a field has no '='.
  void read(ByteSource& source, uint64_t at, uint32_t length, const char* what);

  std::optional<std::string_view> find(std::string_view name) const;
  // The value of `name` as rosbag's readField reads a number: exactly sizeof(T) bytes, or none.
  std::optional<uint32_t> findUint32(std::string_view name) const;
  std::optional<uint64_t> findUint64(std::string_view name) const;
  // The record's op, or -1 when it has none of one byte (rosbag then refuses it cleanly).
  int op() const;

 private:
  struct Field {
    size_t name_at, name_length, value_at, value_length;
  };
  std::string bytes_;
  std::vector<Field> fields_;
};

struct RecordLayout {
  uint64_t start = 0;        // where its header length is
  uint64_t data_start = 0;   // where its data is (after its data length)
  uint32_t data_length = 0;  //
  uint64_t end() const { return data_start + data_length; }
};

// Reads the record that starts at `at` in `range`, its header into `fields`.
RecordLayout readRecord(const ByteRange& range, uint64_t at, HeaderFields& fields);

// Reads a connection record's data, the connection's header (at most kMaxHeaderBytes), into
// `fields`.
void readConnectionHeader(const ByteRange& range, const RecordLayout& record, HeaderFields& fields);

}  // namespace detail
}  // namespace offline
}  // namespace rfm
