// Baked light, handed from the raytracer's results to the GL engine (docs/architecture.md: the engines share baked
// results only through the LightMapStore). Plain data: the CLI fills it from a bake in memory or from a baked
// scene directory (cli/baked_light_maps.h); the raster engine reads it.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "base/color.h"
#include "base/math.h"

namespace fly::rdb {

// A mesh's light texture: irradiance per texel of its light-map atlas. UV convention as in
// rdb/lightmap_uv.h: texel (i, j) covers u ∈ [i/width, (i+1)/width), v ∈ [j/height, (j+1)/height); row j = 0
// (v = 0) is the top row of the baked EXR file and the first row here.
struct MeshLightTexture {
  uint32_t width = 0, height = 0;  // texels, ≥ 1
  // Irradiance, lux per channel, per texel, row-major from row 0: width·height values. backLux (the side of
  // −normal) only for a two-sided mesh, else empty.
  std::vector<Rgb> frontLux, backLux;
  // The light-map UV of every triangle corner: 3 per triangle of the SDB mesh that has area, in the SDB
  // mesh's triangle order. Triangles of zero area (TraceRdb's and RasterRdb's rule: |e1 × e2| ≤
  // 10⁻⁷·|e1|·|e2| in world space) have no corners here, as in TraceMesh and RasterRdb. The corners of one
  // vertex differ where the atlas's charts meet (seams).
  std::vector<vec2> cornerUv;
  // The part of frontLux / backLux that came straight from the sun's disc (LightMapStore::sun), the same
  // size; empty when the bake kept none apart.
  std::vector<Rgb> frontSunDirectLux, backSunDirectLux;
  // The standard error of frontLux / backLux per texel (lux per channel), the same sizes (the viewer's lux
  // probe reports it; the GL engine draws without it).
  std::vector<Rgb> frontStdErrorLux, backStdErrorLux;
};

// The baked irradiance of one placed mesh: SDB node `sdbNodeId` holding SDB mesh `sdbMeshId`.
struct MeshLightMap {
  uint32_t sdbNodeId = 0, sdbMeshId = 0;
  // Irradiance, lux per channel, on the front (the side the shading normal points to) and the back of the
  // surface, per vertex of the SDB mesh, in the SDB mesh's vertex order. backLux is empty for a one-sided
  // mesh.
  std::vector<Rgb> frontLux, backLux;
  // The light texture, for a mesh baked with one; the engine draws it instead of the vertex values.
  std::optional<MeshLightTexture> lightTexture;
  // The part of frontLux / backLux that came straight from the sun's disc (LightMapStore::sun), per vertex as
  // they are; empty when the bake kept none apart.
  std::vector<Rgb> frontSunDirectLux, backSunDirectLux;
  // The standard error of frontLux / backLux (lux per channel, the Monte-Carlo estimate's), per vertex as
  // they are; empty when the caller did not keep it (the GL engine draws without it; the viewer's lux probe
  // reports it).
  std::vector<Rgb> frontStdErrorLux, backStdErrorLux;
};

// The sun of a bake that kept its direct light apart (FLY §3's sunlight mode: baked light without the sun's
// direct term, which the engine draws in real time for any sun).
struct BakedSun {
  vec3 directionWorld{0.0f, 1.0f, 0.0f};  // unit, towards the sun
  Rgb normalIlluminanceLux{0.0f};         // on a surface facing it
};

struct LightMapStore {
  std::vector<MeshLightMap> meshes;
  // With it, every mesh's frontSunDirectLux (and backSunDirectLux where it has backLux) and its light
  // texture's are filled; without it (a bake without a sun, or by a fly that did not keep it apart) all are
  // empty.
  std::optional<BakedSun> sun;

  // The light map of SDB mesh `sdbMeshId` as placed by node `sdbNodeId`, or nullptr when none was baked.
  const MeshLightMap* find(uint32_t sdbNodeId, uint32_t sdbMeshId) const;
};

}  // namespace fly::rdb
