// The scene's features: what it contains that later stages must build. RDBs and engines build, compile and run
// only the parts a scene's features call for (docs/architecture.md, "Features decide what is built").
#pragma once

#include <map>
#include <string>
#include <vector>

#include "sdb/scene.h"

namespace fly::sdb {

struct SceneFeatures {
  bool sun = false;                  // the sun lights the scene (sky settings with sun on)
  bool sky = false;                  // a sky model lights the scene
  bool punctualLights = false;       // point, spot or directional lights
  bool goniometricLights = false;    // IES lights
  bool emissiveSurfaces = false;     // meshes with emissive materials
  bool twoSidedSurfaces = false;     // meshes baked and shaded on both faces
  bool lightTexturedMeshes = false;  // meshes that ask for light textures
  bool measuredBrdfs = false;        // materials with a measured BRDF table or a fitted car-paint BRDF
  bool transmissiveMaterials = false;  // glass and other materials that transmit light
  // transmitting materials whose transmission is glossy (transmissionGlossiness² ≥ kSmoothAlpha): the OpenGL
  // engine shows what lies behind them blurred
  bool frostedGlass = false;
  bool anisotropicMaterials = false;
  bool texturedMaterials = false;    // any material reads a texture
  bool bumpMaps = false;
  bool vertexColors = false;
  bool planarReflectors = false;     // mirror-like materials on flat meshes
  bool curvedReflectors = false;     // cube-map reflectors: mirror-like materials on curved meshes, "cubemap" ones
  // reflecting materials (neither glass nor measured) with reflection fog (Material::reflectionFogDistanceM)
  bool reflectionFog = false;
  bool skyPortals = false;           // declared sky portals (sdb/portal.h), openings the baker aims at
  // How the OpenGL engine shows each reflecting material's reflection (FLY §5's automatic choice by shape and
  // material, or the scene file's "engineReflection"), by material name: "planar" (its flat meshes), "cubemap"
  // (its curved meshes, or all with "cubemap"), or "planar, cubemap"; materials that get neither are absent.
  std::map<std::string, std::string> engineReflections;

  // The names of the features present, in the order above: "sun", "sky", "punctual-lights",
  // "goniometric-lights", "emissive-surfaces", "two-sided-surfaces", "light-textured-meshes", "measured-brdf",
  // "transmissive-materials", "frosted-glass", "anisotropic-materials", "textured-materials", "bump-maps", "vertex-colors",
  // "planar-reflectors", "curved-reflectors", "reflection-fog", "sky-portals".
  std::vector<std::string> names() const;
};

// Only meshes reachable from the node hierarchy count.
SceneFeatures computeFeatures(const Scene& scene);

}  // namespace fly::sdb
