#include "bag_record_reader.h"

#include <cstring>

namespace rfm {
namespace offline {
namespace detail {
namespace {

uint32_t readUint32(ByteSource& source, uint64_t at) {
  char bytes[4];
  source.read(at, sizeof(bytes), bytes);
  uint32_t value = 0;
  std::memcpy(&value, bytes, sizeof(value));  // little-endian, as rosbag writes and reads it
  return value;
}

template <typename T>
std::optional<T> asNumber(std::optional<std::string_view> value) {
  if (!value || value->size() != sizeof(T)) return std::nullopt;
  T number = 0;
  std::memcpy(&number, value->data(), sizeof(T));
  return number;
}

}  // namespace

void HeaderFields::read(ByteSource& source, uint64_t at, uint32_t length, const char* what) {
  bytes_.resize(length);
  source.read(at, length, bytes_.data());
  fields_.clear();
  for (size_t field = 0; field < length;) {
    const size_t left = length - field;
    if (left < 4) {
      throw BagStructureError(source.describe(at + field) + ": the last " + std::to_string(left) +
                              " bytes of a " + what + " are too few for a field's 4-byte length");
    }
    uint32_t field_length = 0;
    std::memcpy(&field_length, bytes_.data() + field, 4);
    if (field_length > left - 4) {
      throw BagStructureError(source.describe(at + field) + ": a " + what + " field claims " +
                              std::to_string(field_length) + " bytes, past the end of its " + what +
                              " (" + std::to_string(left - 4) + " bytes left)");
    }
    const size_t begin = field + 4;
    const void* equals = std::memchr(bytes_.data() + begin, '=', field_length);
    if (equals == nullptr) {
      throw BagStructureError(source.describe(at + field) + ": a " + what +
                              " field has no '=' (fields are name=value)");
    }
    const size_t name_length = static_cast<const char*>(equals) - (bytes_.data() + begin);
    fields_.push_back(
        Field{begin, name_length, begin + name_length + 1, field_length - name_length - 1});
    field = begin + field_length;
  }
}

std::optional<std::string_view> HeaderFields::find(std::string_view name) const {
  for (auto field = fields_.rbegin(); field != fields_.rend(); ++field) {
    if (std::string_view(bytes_.data() + field->name_at, field->name_length) == name) {
      return std::string_view(bytes_.data() + field->value_at, field->value_length);
    }
  }
  return std::nullopt;
}

std::optional<uint32_t> HeaderFields::findUint32(std::string_view name) const {
  return asNumber<uint32_t>(find(name));
}

std::optional<uint64_t> HeaderFields::findUint64(std::string_view name) const {
  return asNumber<uint64_t>(find(name));
}

int HeaderFields::op() const {
  const std::optional<std::string_view> value = find(rosbag::OP_FIELD_NAME);
  if (!value || value->size() != 1) return -1;
  return static_cast<unsigned char>((*value)[0]);
}

RecordLayout readRecord(const ByteRange& range, uint64_t at, HeaderFields& fields) {
  ByteSource& source = range.source;
  auto left = [&](uint64_t from) { return std::to_string(range.end - from) + " bytes left"; };
  if (range.end - at < 4) {
    throw BagStructureError(source.describe(at) + ": " + left(at) + " in " + range.name +
                            ", too few for a record's 4-byte header length");
  }
  const uint32_t header_length = readUint32(source, at);
  const uint64_t header_start = at + 4;
  if (header_length > range.end - header_start) {
    throw BagStructureError(source.describe(at) + ": the record's header claims " +
                            std::to_string(header_length) + " bytes, past the end of " +
                            range.name + " (" + left(header_start) + ")");
  }
  if (header_length > kMaxHeaderBytes) {
    throw BagStructureError(source.describe(at) + ": the record's header claims " +
                            std::to_string(header_length) + " bytes, more than the " +
                            std::to_string(kMaxHeaderBytes) + " a record header may have");
  }
  fields.read(source, header_start, header_length, "header");
  const uint64_t length_at = header_start + header_length;
  if (range.end - length_at < 4) {
    throw BagStructureError(source.describe(length_at) + ": " + left(length_at) + " in " +
                            range.name + ", too few for the record's 4-byte data length");
  }
  RecordLayout record;
  record.start = at;
  record.data_length = readUint32(source, length_at);
  record.data_start = length_at + 4;
  if (record.data_length > range.end - record.data_start) {
    throw BagStructureError(source.describe(at) + ": the record's data claims " +
                            std::to_string(record.data_length) + " bytes, past the end of " +
                            range.name + " (" + left(record.data_start) + ")");
  }
  return record;
}

void readConnectionHeader(const ByteRange& range, const RecordLayout& record,
                          HeaderFields& fields) {
  if (record.data_length > kMaxHeaderBytes) {
    throw BagStructureError(range.source.describe(record.start) +
                            ": the connection record's header claims " +
                            std::to_string(record.data_length) + " bytes, more than the " +
                            std::to_string(kMaxHeaderBytes) + " a header may have");
  }
  fields.read(range.source, record.data_start, record.data_length, "connection header");
}

}  // namespace detail
}  // namespace offline
}  // namespace rfm
