#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

// The fuzz targets' view of libFuzzer's bytes: fixed-size values taken from the front, raw (so
// NaN, infinities and extreme values come as easily as ordinary ones), zero once exhausted.
namespace rfm::fuzz {

class FuzzInput {
 public:
  FuzzInput(const uint8_t* data, size_t size) : data_(data), size_(size) {}

  template <typename T>
  T take() {
    T value{};
    const size_t count = std::min(sizeof(T), size_ - used_);
    if (count > 0) std::memcpy(&value, data_ + used_, count);
    used_ += count;
    return value;
  }

  // The rest of the bytes as values of T (a trailing partial value is dropped).
  template <typename T>
  std::vector<T> takeRest() {
    std::vector<T> values((size_ - used_) / sizeof(T));
    if (!values.empty()) std::memcpy(values.data(), data_ + used_, values.size() * sizeof(T));
    used_ = size_;
    return values;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t used_ = 0;
};

}  // namespace rfm::fuzz
