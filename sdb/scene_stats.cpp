#include "sdb/scene_stats.h"

namespace fly::sdb {

SceneStats computeStats(const Scene& scene) {
  SceneStats s;
  s.nodes = scene.nodes().size();
  s.meshes = scene.meshes().size();
  s.materials = scene.materials().size();
  s.textures = scene.textures().size();
  s.cameras = scene.cameras().size();
  s.lights = scene.lights().size();
  for (const auto& [id, m] : scene.materials()) ++s.materialsByClass[materialClass(m)];
  for (const auto& [id, l] : scene.lights()) ++s.lightsByType[lightTypeName(l.type)];
  scene.forEachNode([&](NodeId id, const mat4& worldFromLocal) {
    for (MeshId meshId : scene.node(id).meshes) {
      const Mesh& mesh = scene.mesh(meshId);
      ++s.meshInstances;
      if (scene.material(mesh.material).isEmissive()) ++s.emissiveMeshes;
      s.triangles += mesh.triangleCount();
      s.vertices += mesh.vertexCount();
      for (const vec3& p : mesh.positions) s.boundsWorldM.extend(vec3(worldFromLocal * vec4(p, 1.0f)));
    }
  });
  return s;
}

}  // namespace fly::sdb
