#include "rdb/placed_mesh.h"

#include <cmath>

#include "base/error.h"

namespace fly::rdb {

std::optional<vec3> unitOrNone(const dvec3& v) {
  const double len = glm::length(v);
  if (!(len > 1e-30) || !std::isfinite(len)) return std::nullopt;
  return vec3(v / len);
}

PlacedMesh placeMesh(const sdb::Mesh& mesh, const mat4& worldFromLocal) {
  PlacedMesh placed;
  placed.positionsM.reserve(mesh.vertexCount());
  for (const vec3& p : mesh.positions) placed.positionsM.emplace_back(worldFromLocal * vec4(p, 1.0f));
  const std::vector<vec3>& world = placed.positionsM;

  // Per-vertex sum of the adjacent faces' area-weighted normals, for vertices without a usable normal.
  std::vector<dvec3> faceNormalSum(mesh.vertexCount(), dvec3(0.0));
  placed.indices.reserve(mesh.indices.size());
  placed.sdbTriangle.reserve(mesh.triangleCount());
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t* v = &mesh.indices[3 * t];
    const dvec3 e1 = dvec3(world[v[1]]) - dvec3(world[v[0]]);
    const dvec3 e2 = dvec3(world[v[2]]) - dvec3(world[v[0]]);
    const dvec3 n = glm::cross(e1, e2);  // length = twice the area
    // Zero area, up to the rounding of float positions: the edges are parallel within ~float epsilon.
    if (!(glm::length(n) > 1e-7 * glm::length(e1) * glm::length(e2))) {
      ++placed.skippedTriangles;
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      placed.indices.push_back(v[k]);
      faceNormalSum[v[k]] += n;
    }
    placed.sdbTriangle.push_back(uint32_t(t));
  }

  // Normals transform by the inverse transpose (a singular transform leaves only the face normals).
  const glm::dmat3 linear(worldFromLocal);
  const double det = glm::determinant(linear);
  const glm::dmat3 normalFromLocal = det != 0.0 ? glm::transpose(glm::inverse(linear)) : glm::dmat3(0.0);
  placed.normals.reserve(mesh.vertexCount());
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    std::optional<vec3> n;
    if (!mesh.normals.empty()) n = unitOrNone(normalFromLocal * dvec3(mesh.normals[i]));
    if (!n) n = unitOrNone(faceNormalSum[i]);
    placed.normals.push_back(n.value_or(vec3(0.0f, 1.0f, 0.0f)));
  }
  return placed;
}

LightFrame placeLight(const sdb::Scene& scene, const sdb::Node& node, const mat4& worldFromLocal) {
  LightFrame f;
  f.positionM = vec3(worldFromLocal[3]);
  const std::optional<vec3> dir = unitOrNone(dvec3(worldFromLocal * vec4(0.0f, 0.0f, -1.0f, 0.0f)));
  const dvec3 x(worldFromLocal * vec4(1.0f, 0.0f, 0.0f, 0.0f));
  const std::optional<vec3> cAxis = dir ? unitOrNone(x - glm::dot(x, dvec3(*dir)) * dvec3(*dir)) : std::nullopt;
  if (!cAxis) {
    throw InputError({scene.sourcePath.string()},
                     "node \"" + node.name + "\" places light \"" + scene.light(node.light).name +
                         "\" with a singular transform",
                     "give the node and its parents a non-zero scale");
  }
  f.directionWorld = *dir;
  f.cAxisWorld = *cAxis;
  return f;
}

}  // namespace fly::rdb
