// Lowering an SDB scene into the TraceRdb (rdb/trace_rdb.h): geometry flattened into world space, materials with
// the energy rule applied (measured BRDFs as shared tables or car-paint parameters), punctual and goniometric
// lights in world space, the sun and tabulated sky of the scene's site and time (rdb/site_lowering.h), and the
// declared sky portals as triangles.
// Only what the scene needs is built: no sky table without a sky, no goniometric tables without goniometric
// lights, no measured tables without measured materials.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "rdb/trace_rdb.h"
#include "sdb/ies.h"
#include "sdb/scene.h"
#include "sunsky/site_frame.h"
#include "sunsky/sky.h"

namespace fly::rdb {

struct TraceBuildOptions {
  // Cells per side of the equal-area sky table (TraceSky): resolution² cells of 2π/resolution² sr each.
  // [1, 1024]; default 64 (4096 cells of 1.5·10⁻³ sr, about 2.2° across).
  uint32_t skyResolution = 64;
  // Each sky cell holds the mean radiance of n × n stratified directions (cell-centred in φ and μ = cos θ, so
  // equally spaced in solid angle). [1, 64]; default 4.
  uint32_t skyCellSamples = 4;
  // Goniometric tables: γ steps over [0°, 180°] (≥ 2) and C steps over [0°, 360°) (≥ 1). Defaults 181 × 72:
  // 1° in γ, 5° in C (LM-63 files commonly measure in 5° to 22.5° C-planes and 1° to 5° in γ).
  uint32_t goniometricGammaSteps = 181;
  uint32_t goniometricCSteps = 72;

  // Light textures asked for: atlas at most lightTextureMaxSize² texels (generated UVs: density reduced to
  // fit, rdb/lightmap_uv.h; TEXCOORD_1: the square atlas side clamped), with lightTexturePaddingTexels free
  // texels around each generated chart. [8, 16384] and [0, 16].
  int lightTextureMaxSize = 4096;
  int lightTexturePaddingTexels = 2;
};

// Builds the TraceRdb of `scene`. Materials: index 0 is the default material (SDB id 0), then every material
// the placed meshes use, in the order first met. Every placed (node, mesh) pair adds all of its vertices (so
// the vertex light maps index SDB vertices as firstVertex + i) and its triangles of non-zero area; the others
// are left out and counted in TraceRdb::skippedTriangles. Meshes with triangles that ask for a light texture
// (sdb::Mesh::lightTexture, at its density or else the scene's bake texelsPerMetre) get a TraceLightTexture: UVs from TEXCOORD_1 when the mesh has them (finite, in [0, 1]², covering a
// non-zero area; otherwise a warning and generated ones), else from generateLightmapUv on the world positions.
// Errors: InputError from sunsky and the weather file (see lowerDaylight), InputError for a light placed by a
// singular transform; std::invalid_argument for options out of range.
TraceRdb buildTraceRdb(const sdb::Scene& scene, const TraceBuildOptions& options = {});

// Gives mesh `mesh` of rdb an automatic light texture (TraceLightTexture::automatic) with generated UVs at
// texelsPerMetre (reduced to fit maxSize² texels), keeping rdb.lightTextures in mesh order (the meshes'
// lightTexture indices are renumbered). Coincident vertices with equal normals are welded for charting
// (rdb/vertex_weld.h). Charts whose triangles are denser than their texels would be (fewer than
// kMinTexelsPerTriangle texels per triangle) stay on the vertex light maps: their corners get
// noLightTextureUv(). Returns the new entry, or null when every chart stays on the vertex maps.
// std::invalid_argument when the mesh does not exist, has no triangles or already has a light texture, or a
// setting is out of range.
TraceLightTexture* addAutomaticLightTexture(TraceRdb& rdb, uint32_t mesh, float texelsPerMetre, int maxSize,
                                            int paddingTexels);

// The TraceMaterial of an SDB material (its energy rule evaluated at normal incidence), without its texture
// slots (buildTraceRdb fills them).
TraceMaterial lowerMaterial(const sdb::Material& m, uint32_t sdbMaterialId);

// The baker's record of a measured table read from `file`: the table shared, and its largest directional
// albedo (BrdfTable::maxAlbedo); above 1 a warning names the file, the channel and the angle, and `scale`
// brings the peak down to 1.
TraceBrdfTable lowerBrdfTable(const std::string& file, std::shared_ptr<const BrdfTable> table);

// A texture slot for texture index textureIndex: the UV set, wrap modes and KHR_texture_transform of ref.
TraceTextureSlot lowerTextureRef(const sdb::TextureRef& ref, uint32_t textureIndex);

// An SDB texture as 8-bit texels (16-bit values rounded). std::invalid_argument when its sizes disagree.
TraceTexture lowerTexture(const sdb::Texture& t);

// Unit tangents per vertex for normal mapping and the axes of anisotropic reflection when the file gives none: at each vertex the area-weighted sum
// of its triangles' ∂p/∂u (from the UV derivatives), made perpendicular to the vertex normal, and w = ±1 the
// sign that makes w · N × T point along the summed ∂p/∂(−v), towards the image's top (glTF's bitangent, the
// +Y of a normal map, as the GL engine's tangents in rdb/raster_rdb.h). This per-vertex method agrees with
// MikkTSpace (which glTF names for files without tangents) on smooth, consistently mapped meshes; where the UVs give no
// direction (no UVs, degenerate mapping) the tangent is any unit vector perpendicular to the normal.
std::vector<vec4> generateTangents(std::span<const vec3> positions, std::span<const vec3> normals,
                                   std::span<const vec2> uv, std::span<const uint32_t> indices);

// The profile's luminous intensity on TraceGoniometricTable's grid. The light's frame (sdb/light.h) maps to the
// profile's (sdb/ies.h, candelaTowards): its −Z is the photometric axis z (γ = 0), its +X the C = 0° plane x,
// its +Y the C = 90° plane y, so C runs from +X towards +Y (counter-clockwise seen from above a downlight, as
// LM-63 measures type C).
TraceGoniometricTable tabulateGoniometric(const sdb::IesProfile& profile, uint32_t gammaSteps, uint32_t cSteps);

// The sky's radiance tabulated on TraceSky's equal-area map of world directions: each cell's mean over
// cellSamples² stratified directions, converted to the sky's ENU frame with frame.enuFromWorld.
TraceSky tabulateSky(const sunsky::Sky& sky, const sunsky::SiteFrame& frame, uint32_t resolution,
                     uint32_t cellSamples);

}  // namespace fly::rdb
