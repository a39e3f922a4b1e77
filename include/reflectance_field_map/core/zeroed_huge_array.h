#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <new>
#include <type_traits>
#include <utility>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace rfm {

// The pages a ZeroedHugeArray asks the kernel for.
enum class PageKind { kHuge, kOrdinary };

// A fixed-size array of zeros to start with, for the field's theta slices and masks.
// - calloc hands a large block straight from the kernel, zero without being written: its pages
//   are faulted in when first touched. So creating the field costs nothing, the threads that
//   insert fault in the pages they reach side by side, and pages no ray reaches stay unmapped.
//   (Faulting in 100 MB at once took 6-213 ms on the shared VM, all on one thread.)
// - With PageKind::kHuge, blocks of at least one huge page are offered to the kernel's transparent
//   huge pages (Linux; elsewhere, and when the kernel declines, they are ordinary pages). A
//   scan's rays then cross a few dozen 2 MB pages instead of thousands of 4 kB ones: far fewer
//   page translations. But a ray's first touch then brings in 2 MB: PageKind::kOrdinary keeps an
//   array that rays reach only here and there resident only where they reach.
template <typename T>
class ZeroedHugeArray {
  static_assert(std::is_trivially_copyable_v<T>, "zero bytes must be a valid T");

 public:
  static constexpr size_t kHugePageBytes = size_t{2} << 20;

  ZeroedHugeArray() = default;
  explicit ZeroedHugeArray(size_t count, PageKind pages = PageKind::kHuge)
      : size_(count), pages_(pages) {
    if (count == 0) return;
    data_ = static_cast<T*>(std::calloc(count, sizeof(T)));
    if (!data_) throw std::bad_alloc();
    advisePages();
  }
  ZeroedHugeArray(const ZeroedHugeArray& other) : ZeroedHugeArray(other.size_, other.pages_) {
    if (size_ > 0) std::memcpy(data_, other.data_, size_ * sizeof(T));
  }
  ZeroedHugeArray(ZeroedHugeArray&& other) noexcept
      : data_(std::exchange(other.data_, nullptr)),
        size_(std::exchange(other.size_, 0)),
        pages_(other.pages_) {}
  ZeroedHugeArray& operator=(ZeroedHugeArray other) noexcept {
    std::swap(data_, other.data_);
    std::swap(size_, other.size_);
    std::swap(pages_, other.pages_);
    return *this;
  }
  ~ZeroedHugeArray() { std::free(data_); }

  // Faults every page in now, one write a page, for a caller whose first touches must not wait
  // for them (a live mapper's first scans).
  void prefault() {
    constexpr size_t kPageBytes = 4096;  // the smallest page: a write to each reaches every page
    auto* bytes = reinterpret_cast<volatile unsigned char*>(data_);
    for (size_t offset = 0; offset < size_ * sizeof(T); offset += kPageBytes)
      bytes[offset] = 0;
  }

  // Zeroes again, page by page, only the pages holding a value other than zero: pages never
  // written stay unmapped (reading them maps the kernel's shared zero page), and written ones stay
  // resident for the next use instead of being faulted in afresh.
  void zeroWhereSet() {
    constexpr uintptr_t kPageBytes = 4096;  // the smallest page
    auto* const bytes = reinterpret_cast<unsigned char*>(data_);
    const size_t total = size_ * sizeof(T);
    size_t first = 0;
    while (first < total) {
      const uintptr_t address = reinterpret_cast<uintptr_t>(bytes + first);
      const size_t last = std::min(total, first + (kPageBytes - address % kPageBytes));
      if (std::any_of(bytes + first, bytes + last, [](unsigned char b) { return b != 0; }))
        std::memset(bytes + first, 0, last - first);
      first = last;
    }
  }

  size_t size() const { return size_; }
  PageKind pages() const { return pages_; }
  T* data() { return data_; }
  const T* data() const { return data_; }
  T& operator[](size_t i) { return data_[i]; }
  const T& operator[](size_t i) const { return data_[i]; }
  T* begin() { return data_; }
  T* end() { return data_ + size_; }
  const T* begin() const { return data_; }
  const T* end() const { return data_ + size_; }

 private:
  void advisePages() {
#if defined(__linux__) && defined(MADV_HUGEPAGE) && defined(MADV_NOHUGEPAGE)
    // The whole huge pages inside the block; advice only: failure leaves the kernel's default.
    // Ordinary pages are asked for too: a kernel set to huge pages always would use them.
    const auto first = reinterpret_cast<uintptr_t>(data_);
    const uintptr_t begin = (first + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes;
    const uintptr_t end = (first + size_ * sizeof(T)) / kHugePageBytes * kHugePageBytes;
    if (end > begin) {
      madvise(reinterpret_cast<void*>(begin), end - begin,
              pages_ == PageKind::kHuge ? MADV_HUGEPAGE : MADV_NOHUGEPAGE);
    }
#endif
  }

  T* data_ = nullptr;
  size_t size_ = 0;
  PageKind pages_ = PageKind::kHuge;
};

}  // namespace rfm
