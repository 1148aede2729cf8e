// Decoding of buffer views compressed with EXT_meshopt_compression through Debian's meshoptimizer. Kept apart
// from the glTF importer, which hands the decoded bytes to its accessors as if the view held them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace fly::sdb {

// The extension's "mode" and "filter" values (EXT_meshopt_compression, "Compressing buffer views").
enum class MeshoptMode { kAttributes, kTriangles, kIndices };
enum class MeshoptFilter { kNone, kOctahedral, kQuaternion, kExponential };

// `count` elements of `byteStride` bytes each, decoded from `encoded`; the filter is undone in place. Fails
// with std::runtime_error giving the reason (a stride the mode does not allow, corrupt data).
std::vector<uint8_t> decodeMeshoptView(std::span<const uint8_t> encoded, size_t count, size_t byteStride,
                                       MeshoptMode mode, MeshoptFilter filter);

}  // namespace fly::sdb
