// SDB meshes and lights placed in world space by their nodes, lowered the same way for both RDBs (TraceRdb and
// RasterRdb must agree vertex for vertex and triangle for triangle, and light for light: the light maps of one
// are shown by the other).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "base/math.h"
#include "sdb/mesh.h"
#include "sdb/scene.h"

namespace fly::rdb {

struct PlacedMesh {
  std::vector<vec3> positionsM;  // the mesh's vertices in SDB order, world space
  // Unit normals per vertex: the mesh's own, transformed by the inverse transpose of worldFromLocal; where
  // there is none or it is degenerate (or the transform is singular), the normalised sum of the adjacent
  // kept faces' area-weighted normals; for a vertex of no kept triangle, +Y (up).
  std::vector<vec3> normals;
  // The triangles of non-zero area, in SDB order: local vertex indices, 3 each, and the SDB triangle each
  // came from. Zero area is decided up to the rounding of float positions: |e1 × e2| ≤ 1e-7 |e1| |e2|.
  std::vector<uint32_t> indices;
  std::vector<uint32_t> sdbTriangle;
  size_t skippedTriangles = 0;
};

PlacedMesh placeMesh(const sdb::Mesh& mesh, const mat4& worldFromLocal);
// The same, with the positions and normals appended to positionsM and normals (which keep what they held)
// rather than stored in the result, whose positionsM and normals stay empty; indices stay local to the mesh.
// For a caller that gathers many meshes into one array, without copying each.
PlacedMesh placeMesh(const sdb::Mesh& mesh, const mat4& worldFromLocal, std::vector<vec3>& positionsM,
                     std::vector<vec3>& normals);

// A light's placement: its node's origin, its photometric axis (the node's −Z) and the C = 0° half-plane
// direction (the node's +X made perpendicular to the axis), world space, unit. InputError naming the scene
// file, the node and the light when the node's transform is singular.
struct LightFrame {
  vec3 positionM{0.0f};
  vec3 directionWorld{0.0f, -1.0f, 0.0f};
  vec3 cAxisWorld{1.0f, 0.0f, 0.0f};
};
LightFrame placeLight(const sdb::Scene& scene, const sdb::Node& node, const mat4& worldFromLocal);

// v / |v| in float, or nullopt for a zero, tiny or non-finite v.
std::optional<vec3> unitOrNone(const dvec3& v);

}  // namespace fly::rdb
