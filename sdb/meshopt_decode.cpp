#include "sdb/meshopt_decode.h"

#include <meshoptimizer.h>

#include <stdexcept>

namespace fly::sdb {

std::vector<uint8_t> decodeMeshoptView(std::span<const uint8_t> encoded, size_t count, size_t byteStride,
                                       MeshoptMode mode, MeshoptFilter filter) {
  // Strides the extension allows: attributes a multiple of 4 up to 256, indices 2 or 4.
  if (mode == MeshoptMode::kAttributes ? byteStride % 4 != 0 || byteStride == 0 || byteStride > 256
                                       : byteStride != 2 && byteStride != 4) {
    throw std::runtime_error("byteStride " + std::to_string(byteStride) + " is not allowed for its mode");
  }
  if (mode == MeshoptMode::kTriangles && count % 3 != 0) {
    throw std::runtime_error("TRIANGLES mode needs a count that is a multiple of 3, not " +
                             std::to_string(count));
  }
  if (mode != MeshoptMode::kAttributes && filter != MeshoptFilter::kNone) {
    throw std::runtime_error("filters apply to ATTRIBUTES mode only");
  }
  std::vector<uint8_t> out(count * byteStride);
  int rc = 0;
  switch (mode) {
    case MeshoptMode::kAttributes:
      rc = meshopt_decodeVertexBuffer(out.data(), count, byteStride, encoded.data(), encoded.size());
      break;
    case MeshoptMode::kTriangles:
      rc = meshopt_decodeIndexBuffer(out.data(), count, byteStride, encoded.data(), encoded.size());
      break;
    case MeshoptMode::kIndices:
      rc = meshopt_decodeIndexSequence(out.data(), count, byteStride, encoded.data(), encoded.size());
      break;
  }
  if (rc != 0)
    throw std::runtime_error("the compressed data is corrupt (meshoptimizer error " + std::to_string(rc) +
                             ")");
  switch (filter) {
    case MeshoptFilter::kNone:
      break;
    case MeshoptFilter::kOctahedral:
      if (byteStride != 4 && byteStride != 8)
        throw std::runtime_error("the OCTAHEDRAL filter needs byteStride 4 or 8");
      meshopt_decodeFilterOct(out.data(), count, byteStride);
      break;
    case MeshoptFilter::kQuaternion:
      if (byteStride != 8) throw std::runtime_error("the QUATERNION filter needs byteStride 8");
      meshopt_decodeFilterQuat(out.data(), count, byteStride);
      break;
    case MeshoptFilter::kExponential:
      meshopt_decodeFilterExp(out.data(), count, byteStride);
      break;
  }
  return out;
}

}  // namespace fly::sdb
