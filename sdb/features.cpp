#include "sdb/features.h"

#include <cmath>
#include <set>

namespace fly::sdb {

namespace {

// True when every vertex lies within 1e-4 of the mesh's extent from the plane of its first non-degenerate
// triangle (a flat mirror can be rendered with one planar reflection; a curved one cannot).
bool isPlanar(const Mesh& mesh) {
  vec3 normal(0.0f);
  vec3 origin(0.0f);
  for (size_t t = 0; t < mesh.triangleCount() && normal == vec3(0.0f); ++t) {
    const vec3& a = mesh.positions[mesh.indices[3 * t]];
    const vec3 n = glm::cross(mesh.positions[mesh.indices[3 * t + 1]] - a, mesh.positions[mesh.indices[3 * t + 2]] - a);
    if (glm::length(n) > 0.0f) {
      normal = glm::normalize(n);
      origin = a;
    }
  }
  if (normal == vec3(0.0f)) return true;
  Bounds3 b;
  for (const vec3& p : mesh.positions) b.extend(p);
  const float tolerance = 1e-4f * glm::length(b.size());
  for (const vec3& p : mesh.positions) {
    if (std::abs(glm::dot(p - origin, normal)) > tolerance) return false;
  }
  return true;
}

}  // namespace

std::vector<std::string> SceneFeatures::names() const {
  std::vector<std::string> out;
  const std::pair<bool, const char*> all[] = {
      {sun, "sun"},
      {sky, "sky"},
      {punctualLights, "punctual-lights"},
      {goniometricLights, "goniometric-lights"},
      {emissiveSurfaces, "emissive-surfaces"},
      {twoSidedSurfaces, "two-sided-surfaces"},
      {lightTexturedMeshes, "light-textured-meshes"},
      {measuredBrdfs, "measured-brdf"},
      {transmissiveMaterials, "transmissive-materials"},
      {frostedGlass, "frosted-glass"},
      {anisotropicMaterials, "anisotropic-materials"},
      {texturedMaterials, "textured-materials"},
      {bumpMaps, "bump-maps"},
      {vertexColors, "vertex-colors"},
      {planarReflectors, "planar-reflectors"},
      {curvedReflectors, "curved-reflectors"},
      {reflectionFog, "reflection-fog"},
      {skyPortals, "sky-portals"},
  };
  for (const auto& [present, name] : all) {
    if (present) out.emplace_back(name);
  }
  return out;
}

SceneFeatures computeFeatures(const Scene& scene) {
  SceneFeatures f;
  f.sun = scene.sky().sun;
  f.sky = scene.sky().model != SkyModel::kNone;
  f.skyPortals = !scene.portals().empty();
  std::set<MeshId> instanced;
  std::set<LightId> placedLights;
  scene.forEachNode([&](NodeId id, const mat4&) {
    const Node& n = scene.node(id);
    instanced.insert(n.meshes.begin(), n.meshes.end());
    if (n.light) placedLights.insert(n.light);
  });
  for (LightId id : placedLights) {
    if (scene.light(id).type == LightType::kGoniometric) {
      f.goniometricLights = true;
    } else {
      f.punctualLights = true;
    }
  }
  for (MeshId id : instanced) {
    const Mesh& mesh = scene.mesh(id);
    if (mesh.triangleCount() == 0) continue;
    const Material& m = scene.material(mesh.material);
    f.emissiveSurfaces |= m.isEmissive();
    f.twoSidedSurfaces |= mesh.twoSided;
    f.lightTexturedMeshes |= mesh.lightTexture.enabled;
    f.measuredBrdfs |= m.isMeasured();
    f.transmissiveMaterials |= m.isTransmissive();
    const bool glass = maxComponent(m.effective().transmission) > 0.0f;
    f.frostedGlass |= glass && !m.hasClearTransmission();
    f.anisotropicMaterials |= m.isAnisotropic();
    f.texturedMaterials |= bool(m.diffuseTexture) || bool(m.reflectionTexture) || bool(m.transmissionTexture) ||
                           bool(m.reflectionGlossinessTexture) || bool(m.anisotropyTexture) ||
                           bool(m.anisotropyRotationTexture) || bool(m.emissionTexture) || bool(m.bumpTexture) ||
                           bool(m.metalnessTexture);
    f.bumpMaps |= bool(m.bumpTexture);
    f.vertexColors |= !mesh.colors.empty();
    f.reflectionFog |= std::isfinite(m.reflectionFogDistanceM) && maxComponent(m.reflectionColor) > 0.0f &&
                       !m.isMeasured() && !glass;
    const bool flat = isPlanar(mesh);
    const char* choice = nullptr;
    if (m.isMeasured() || glass) {
      // shown by their ball textures, or as glass
    } else if (m.showsPlanarReflection() && flat) {
      f.planarReflectors = true;
      choice = "planar";
    } else if (m.showsCubeMapReflection(flat)) {
      f.curvedReflectors = true;
      choice = "cubemap";
    }
    if (choice) {
      std::string& c = f.engineReflections[m.name];
      if (c.empty()) {
        c = choice;
      } else if (c != choice) {
        c = "planar, cubemap";
      }
    }
  }
  return f;
}

}  // namespace fly::sdb
