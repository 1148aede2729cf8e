// Triangle meshes in the SDB: one material per mesh (a glTF primitive becomes one Mesh).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "base/math.h"
#include "sdb/ids.h"

namespace fly::sdb {

// Per-mesh request for a light texture (a per-texel irradiance map) instead of vertex light maps only.
struct LightTextureRequest {
  bool enabled = false;
  float texelsPerMetre = 0.0f;  // texel density, texels/m, (0, 1000]; 0 = the scene's bake setting
  // Whether the TraceRdb may give the mesh a light texture unasked (a large flat surface,
  // rdb/trace_rdb_build.h); false when the scene file says "lightTexture": false.
  bool allowAutomatic = true;
};

// Positions and vectors are in the mesh's local frame (metres); the node's worldFromLocal places them.
// Every attribute array is empty or has positions.size() entries.
struct Mesh {
  std::string name;
  std::vector<vec3> positions;  // metres, local frame
  std::vector<vec3> normals;    // unit length, local frame (generated flat normals when the source had none)
  std::vector<vec4> tangents;   // xyz unit tangent (local frame), w = ±1 bitangent sign (glTF); may be empty
  std::vector<vec2> uv0;        // TEXCOORD_0, texture coordinates; may be empty
  std::vector<vec2> uv1;        // TEXCOORD_1, light-map coordinates in [0,1]²; may be empty (then generated)
  std::vector<vec4> colors;     // COLOR_0, linear RGBA; may be empty
  std::vector<uint32_t> indices;  // 3 per triangle; counter-clockwise = front face (in world space, see importer)
  MaterialId material;          // 0 = the default material
  bool twoSided = false;        // bake and shade both faces (the material's doubleSided unless overridden)
  LightTextureRequest lightTexture;

  size_t triangleCount() const { return indices.size() / 3; }
  size_t vertexCount() const { return positions.size(); }
};

// Checks attribute sizes and index range; returns "" when consistent, otherwise what is wrong.
std::string validate(const Mesh& m);

}  // namespace fly::sdb
