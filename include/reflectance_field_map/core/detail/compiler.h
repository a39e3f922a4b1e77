// Compiler specifics of the core's hot loops, in one place.
#pragma once

#include <cstdint>

// Forces a function or lambda to be inlined where the compiler's heuristics measurably lose
// (per-cell code called through templates, which it would otherwise call out of line).
#if defined(__GNUC__) || defined(__clang__)
#define RFM_ALWAYS_INLINE __attribute__((always_inline))
#else
#define RFM_ALWAYS_INLINE
#endif

namespace rfm::detail {

// Relaxed atomic access to a plain byte (C++17 has no std::atomic_ref): threads writing the
// same flag concurrently stay well defined, and the flag costs a byte of plain storage.
RFM_ALWAYS_INLINE inline uint8_t relaxedLoad(const uint8_t* byte) {
  return __atomic_load_n(byte, __ATOMIC_RELAXED);
}
RFM_ALWAYS_INLINE inline void relaxedStore(uint8_t* byte, uint8_t value) {
  __atomic_store_n(byte, value, __ATOMIC_RELAXED);
}

}  // namespace rfm::detail
