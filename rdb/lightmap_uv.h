// Light-map UVs for meshes that ask for a light texture and have no TEXCOORD_1 (docs/scene-format.md, "Light textures"):
// the triangles are cut into near-planar charts, each chart is projected onto its plane (so a planar chart
// keeps the requested texel density exactly), turned to its minimum-area rectangle and packed with padding
// into one atlas.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/math.h"

namespace fly::rdb {

struct LightmapUvSettings {
  // Requested texel density, texels per metre of world space; finite and > 0. When the charts would not fit
  // into maxAtlasSize² at this density, it is reduced by the same factor for every chart
  // (LightmapUv::densityReduced).
  float texelsPerMetre = 0.0f;
  // Free texels between any two charts and between a chart and the atlas border; ≥ 0. The default 2 is one
  // texel for bilinear filtering plus one for dilating the baked values into the gap.
  int paddingTexels = 2;
  // Largest atlas width and height, texels; ≥ 2·paddingTexels + 1.
  int maxAtlasSize = 4096;
};

// The atlas of one mesh.
//
// UV convention: texel (i, j) of the width × height atlas covers u ∈ [i/width, (i+1)/width) and
// v ∈ [j/height, (j+1)/height); its centre is ((i + ½)/width, (j + ½)/height). u = 0 is the left edge of
// texel column 0 and v = 0 the upper edge of row 0, the first row stored in an image file (glTF puts the UV
// origin at an image's upper-left corner). Every chart lies strictly inside its own texels, which are at
// least paddingTexels texels away from every other chart's and from the atlas border.
struct LightmapUv {
  std::vector<uint32_t> sourceVertex;     // per output vertex: the input vertex whose attributes it copies
  std::vector<vec2> uv;                   // per output vertex: light-map coordinates, in (0, 1)²
  std::vector<uint32_t> indices;          // 3 per triangle into the output vertices, triangles in input order
  std::vector<uint32_t> chartOfTriangle;  // per triangle: its chart, 0 … chartCount − 1
  uint32_t chartCount = 0;
  // Atlas size, texels: any size, not rounded to a power of two; 0 × 0 for a mesh without triangles.
  uint32_t width = 0;
  uint32_t height = 0;
  float texelsPerMetre = 0.0f;  // achieved density, texels/m: the requested one unless densityReduced
  bool densityReduced = false;  // the requested density did not fit into maxAtlasSize²
  // Only when even one-texel charts cannot fit into maxAtlasSize² (more charts than texels): the atlas is
  // then maxAtlasSize wide and as high as it needs to be.
  bool exceedsMaxAtlasSize = false;
  float utilisation = 0.0f;  // fraction of the atlas's area covered by triangles, [0, 1]
};

// The light-map UV of a triangle corner outside its mesh's atlas (the triangle shows its vertex light map),
// and the test for it: atlas UVs lie in (0, 1)².
inline vec2 noLightTextureUv() { return vec2(-1.0f); }
inline bool inLightTexture(const vec2& uv) { return uv.x >= 0.0f; }
// Automatic light textures leave out charts with fewer texels than this per triangle: their vertices are at
// least as dense as texels would be.
inline constexpr double kMinTexelsPerTriangle = 2.0;

// Generates light-map UVs for a triangle mesh given in world space (metres): 3 indices per triangle,
// counter-clockwise seen from the front. Output vertices are the input vertices split where charts meet;
// input vertices that no triangle uses are left out. Degenerate triangles (zero area, up to float rounding)
// get a zero-area UV footprint inside a chart's texels. Deterministic: the same input gives the same output,
// bit for bit.
// Preconditions (std::invalid_argument, the caller's bug): indices.size() is a multiple of 3 and below 2^32,
// every index < positions.size(), every used position is finite, settings as documented above.
LightmapUv generateLightmapUv(std::span<const vec3> positionsWorld, std::span<const uint32_t> indices,
                              const LightmapUvSettings& settings);

}  // namespace fly::rdb
