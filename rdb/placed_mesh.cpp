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
  std::vector<vec3> positionsM, normals;
  PlacedMesh placed = placeMesh(mesh, worldFromLocal, positionsM, normals);
  placed.positionsM = std::move(positionsM);
  placed.normals = std::move(normals);
  return placed;
}

PlacedMesh placeMesh(const sdb::Mesh& mesh, const mat4& worldFromLocal, std::vector<vec3>& positionsM,
                     std::vector<vec3>& normals) {
  PlacedMesh placed;
  const size_t first = positionsM.size();
  positionsM.reserve(first + mesh.vertexCount());
  for (const vec3& p : mesh.positions) positionsM.emplace_back(worldFromLocal * vec4(p, 1.0f));
  const vec3* world = positionsM.data() + first;
  auto faceNormal = [&](const uint32_t* v) {  // length = twice the area
    return glm::cross(dvec3(world[v[1]]) - dvec3(world[v[0]]), dvec3(world[v[2]]) - dvec3(world[v[0]]));
  };

  placed.indices.reserve(mesh.indices.size());
  placed.sdbTriangle.reserve(mesh.triangleCount());
  for (size_t t = 0; t < mesh.triangleCount(); ++t) {
    const uint32_t* v = &mesh.indices[3 * t];
    const dvec3 e1 = dvec3(world[v[1]]) - dvec3(world[v[0]]);
    const dvec3 e2 = dvec3(world[v[2]]) - dvec3(world[v[0]]);
    const dvec3 n = glm::cross(e1, e2);
    // Zero area, up to the rounding of float positions: the edges are parallel within ~float epsilon.
    if (!(glm::length(n) > 1e-7 * glm::length(e1) * glm::length(e2))) {
      ++placed.skippedTriangles;
      continue;
    }
    placed.indices.insert(placed.indices.end(), v, v + 3);
    placed.sdbTriangle.push_back(uint32_t(t));
  }

  // Normals transform by the inverse transpose (a singular transform leaves only the face normals).
  const glm::dmat3 linear(worldFromLocal);
  const double det = glm::determinant(linear);
  const glm::dmat3 normalFromLocal = det != 0.0 ? glm::transpose(glm::inverse(linear)) : glm::dmat3(0.0);
  const size_t firstNormal = normals.size();
  normals.reserve(firstNormal + mesh.vertexCount());
  std::vector<size_t> withoutNormal;  // vertices whose own normal is missing or unusable
  for (size_t i = 0; i < mesh.vertexCount(); ++i) {
    std::optional<vec3> n;
    if (!mesh.normals.empty()) n = unitOrNone(normalFromLocal * dvec3(mesh.normals[i]));
    if (!n) withoutNormal.push_back(i);
    normals.push_back(n.value_or(vec3(0.0f, 1.0f, 0.0f)));
  }
  if (!withoutNormal.empty()) {
    // The normalised sum of the adjacent kept faces' area-weighted normals, summed in triangle order.
    std::vector<dvec3> faceNormalSum(mesh.vertexCount(), dvec3(0.0));
    for (size_t k = 0; k < placed.indices.size(); k += 3) {
      const dvec3 n = faceNormal(&placed.indices[k]);
      for (size_t c = 0; c < 3; ++c) faceNormalSum[placed.indices[k + c]] += n;
    }
    for (size_t i : withoutNormal) {
      normals[firstNormal + i] = unitOrNone(faceNormalSum[i]).value_or(vec3(0.0f, 1.0f, 0.0f));
    }
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
