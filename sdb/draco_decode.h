// Decoding of Draco-compressed meshes (KHR_draco_mesh_compression) through Debian's libdraco. Kept apart from
// the glTF importer, which turns the result into accessor data with glTF's own conversion rules.
#pragma once

#include <cstddef>
#include <cstdint>
#include <map>
#include <span>
#include <vector>

namespace fly::sdb {

// What the glTF accessor says an attribute holds, which the decoded values must match.
struct DracoAttributeRequest {
  int components = 0;      // 1..4 (SCALAR … VEC4)
  bool isFloat = true;     // glTF componentType FLOAT; otherwise an integer type of `componentBytes`
  int componentBytes = 4;  // 1, 2 or 4
  bool isSigned = false;   // for integer types: BYTE and SHORT
};

struct DracoMesh {
  size_t pointCount = 0;
  std::vector<uint32_t> indices;  // 3 per triangle, into the points
  // Per requested Draco attribute id: pointCount values, each `components` × `componentBytes` little-endian
  // bytes in the request's type (floats as IEEE 754 single precision).
  std::map<int, std::vector<uint8_t>> attributes;
};

// Decodes `encoded` (a Draco mesh bit stream) and extracts the attributes `requests` names by Draco unique
// id. Fails with std::runtime_error giving the reason (not a Draco mesh, corrupt, an attribute id missing or
// of a type other than the request's).
DracoMesh decodeDracoMesh(std::span<const uint8_t> encoded,
                          const std::map<int, DracoAttributeRequest>& requests);

}  // namespace fly::sdb
