// The TraceRdb: the scene lowered once into flat arrays for the Monte-Carlo baker (DESIGN.md, STYLE.md 2 and
// 4). World space is glTF's (+Y up, metres); light in linear Rec.709 RGB with photometric luminance. Records
// refer to SDB entities by id value, never by pointer; the raytracer never includes sdb/ or sunsky/ — all it
// needs is here, as plain data a test can also build by hand.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::rdb {

// A material as the integrator uses it: the realistic material's energy rule already applied.
struct TraceMaterial {
  Rgb diffuse{0.8f};        // Lambertian albedo after the energy rule (at normal incidence), [0,1]
  Rgb reflection{0.0f};     // reflectionColor; with `fresnel` multiplied by Schlick(F0(ior)) at the hit angle
  Rgb transmission{0.0f};   // transmissionColor (before the energy rule's (1 − reflect) factor)
  bool fresnel = true;      // Fresnel (Schlick) or uniform reflection
  float ior = 1.5f;         // [1, 4]
  float reflectionGlossiness = 0.5f;    // [0,1], GGX α = glossiness²
  float transmissionGlossiness = 0.0f;  // [0,1]
  Rgb emissionCdM2{0.0f};   // emitted luminance, cd/m²
  bool doubleSided = false; // emits from both faces (glTF doubleSided)
  uint32_t sdbMaterialId = 0;
};

// A placed mesh: a contiguous range of triangles and vertices in the flat arrays.
struct TraceMesh {
  uint32_t sdbMeshId = 0;
  uint32_t sdbNodeId = 0;
  uint32_t firstVertex = 0;
  uint32_t vertexCount = 0;
  uint32_t firstTriangle = 0;
  uint32_t triangleCount = 0;
  bool twoSided = false;  // bake both faces
  static constexpr uint32_t kNoLightTexture = std::numeric_limits<uint32_t>::max();
  uint32_t lightTexture = kNoLightTexture;  // index into TraceRdb::lightTextures, or none
};

// A mesh's light texture (issue 4): per-texel irradiance over a light-map atlas, baked next to the vertex
// light maps. The UV convention is rdb/lightmap_uv.h's: texel (i, j) covers u ∈ [i/width, (i+1)/width),
// v ∈ [j/height, (j+1)/height), row j = 0 at v = 0 is the first (top) row of the image file.
struct TraceLightTexture {
  uint32_t mesh = 0;            // index into TraceRdb::meshes
  uint32_t width = 0;           // atlas size, texels, ≥ 1
  uint32_t height = 0;
  float texelsPerMetre = 0.0f;  // achieved density, texels/m (for TEXCOORD_1: the mean over the mesh)
  bool automatic = false;       // chosen by the large-flat-surface rule (rdb/trace_rdb_build.h), unasked
  bool fromTexcoord1 = false;   // the UVs are the SDB mesh's TEXCOORD_1, else generated (rdb/lightmap_uv.h)
  // Light-map UV per triangle corner: 3 per triangle of the mesh, in TraceMesh triangle order. Corners of one
  // vertex differ where charts meet (seams).
  std::vector<vec2> cornerUv;
};

enum class PunctualType : uint8_t { kPoint, kSpot, kDirectional, kGoniometric };

// A measured intensity distribution tabulated on a regular grid in the light's frame: γ from the light's −Z axis
// (its photometric axis) in [0, 180°], C around it from +X towards +Y in [0, 360°). candelaCd[c·gammaSteps + g]
// at γ = g·180°/(gammaSteps−1), C = c·360°/cSteps, interpolated bilinearly (wrapping in C).
struct TraceGoniometricTable {
  uint32_t gammaSteps = 0;
  uint32_t cSteps = 0;
  std::vector<float> candelaCd;
};

struct TracePunctualLight {
  PunctualType type = PunctualType::kPoint;
  vec3 positionM{0.0f};        // world (unused for directional)
  vec3 directionWorld{0, -1, 0};  // unit; where the light points (−Z of its node)
  vec3 cAxisWorld{1, 0, 0};    // goniometric: unit, perpendicular to directionWorld, the C = 0° half-plane (+X)
  // Point, spot, goniometric: intensity in cd per channel (colour × intensity; goniometric: × the table's
  // value). Directional: illuminance in lux per channel on a surface facing it.
  Rgb intensity{0.0f};
  float rangeM = std::numeric_limits<float>::infinity();  // KHR_lights_punctual smooth window; ∞ = none
  float cosInner = 1.0f;  // spot: cos of the inner and outer cone angles
  float cosOuter = 0.0f;
  uint32_t goniometricTable = 0;  // index into TraceRdb::goniometricTables (goniometric lights)
  uint32_t sdbLightId = 0;
};

// The sun as a disc: everything within halfAngleRad of directionWorld, uniform radiance.
struct TraceSun {
  vec3 directionWorld{0, 1, 0};    // unit, towards the sun
  Rgb normalIlluminanceLux{0.0f};  // on a surface facing the sun
  float halfAngleRad = 0.004651f;  // 0.533° / 2
};

// The sky tabulated in world directions: an equal-area map of the upper hemisphere (+Y up) with
// `resolution`² cells. For a world direction d (unit, d.y ≥ 0): φ = atan2(d.z, d.x) wrapped to [0, 2π) and
// μ = d.y; cell (i, j) covers φ ∈ [2π·i/res, 2π·(i+1)/res) and μ ∈ [1 − (j+1)/res, 1 − j/res], so every cell
// has the same solid angle 2π/res². radianceCdM2[j·res + i] is the cell's mean radiance. Below the horizon
// (d.y < 0) the sky is black (the ground is geometry).
struct TraceSky {
  uint32_t resolution = 0;          // 0 = no sky
  std::vector<Rgb> radianceCdM2;    // resolution² cells, row j major
};

struct TraceRdb {
  // Geometry: world positions and unit shading normals per vertex, 3 vertex indices per triangle.
  std::vector<vec3> positionsM;
  std::vector<vec3> normals;
  std::vector<uint32_t> indices;
  std::vector<uint32_t> triangleMaterial;  // index into materials, one per triangle
  std::vector<TraceMaterial> materials;
  std::vector<TraceMesh> meshes;
  std::vector<TraceLightTexture> lightTextures;  // meshes with a light texture, in mesh order

  // Lights.
  std::vector<TracePunctualLight> punctualLights;
  std::vector<TraceGoniometricTable> goniometricTables;
  std::vector<uint32_t> emissiveTriangles;  // triangles whose material emits
  bool hasSun = false;
  TraceSun sun;
  TraceSky sky;

  Bounds3 boundsM;
  size_t skippedTriangles = 0;  // zero-area triangles of the SDB meshes, left out of `indices`

  size_t triangleCount() const { return indices.size() / 3; }
};

}  // namespace fly::rdb
