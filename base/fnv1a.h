// FNV-1a, 64 bit (Fowler, Noll & Vo; IETF draft-eastlake-fnv): the checksum of checkpoints and the hash of a
// bake's inputs. Not cryptographic: it detects damaged or mismatched files, not tampering.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace fly {

inline constexpr uint64_t kFnv1aOffsetBasis = 0xcbf29ce484222325ull;

// The hash of `size` bytes at `data`, continuing from `hash` (kFnv1aOffsetBasis for a new one).
inline uint64_t fnv1a(const void* data, size_t size, uint64_t hash = kFnv1aOffsetBasis) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < size; ++i) {
    hash ^= p[i];
    hash *= 0x100000001b3ull;
  }
  return hash;
}

inline uint64_t fnv1a(std::string_view bytes) { return fnv1a(bytes.data(), bytes.size()); }

}  // namespace fly
