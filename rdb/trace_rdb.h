// The TraceRdb: the scene lowered once into flat arrays for the Monte-Carlo baker (docs/architecture.md).
// World space is glTF's (+Y up, metres); light in linear Rec.709 RGB with photometric luminance. Records
// refer to SDB entities by id value, never by pointer; the raytracer never includes sdb/ or sunsky/ — all it
// needs is here, as plain data a test can also build by hand.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "base/brdf_table.h"
#include "base/car_paint.h"
#include "base/color.h"
#include "base/math.h"
#include "rdb/lightmap_uv.h"

namespace fly::rdb {

// A material texture decoded once for the baker: 8 bits per channel, texels row-major from the top row of the
// image (v = 0 at the top, as glTF), channels interleaved. 16-bit sources are rounded to 8 bits (an error of
// at most 1/510 of full scale, far below a bake's Monte-Carlo noise). Colour slots (base colour, emission)
// are sRGB-encoded and decoded per texel at lookup by a 256-entry table, before bilinear filtering.
//
// No mip-maps: a baker's lookup is a point sample of the material at a ray hit, averaged over thousands of
// paths per light-map point, so a texture's detail is integrated by the Monte-Carlo estimate itself; a
// filtered (mip-mapped) lookup would average over a ray footprint that the baker has no use for and would
// bias the per-point values that the alpha cut-out test and the energy rule need.
struct TraceTexture {
  uint32_t width = 0;           // texels, ≥ 1
  uint32_t height = 0;          // texels, ≥ 1
  uint32_t channels = 0;        // 1 grey, 2 grey + alpha, 3 RGB, 4 RGBA
  std::vector<uint8_t> texels;  // width · height · channels bytes
};

// How texture coordinates outside [0, 1] map into the image (glTF sampler wrapS / wrapT).
enum class TraceWrap : uint8_t { kRepeat, kClampToEdge, kMirroredRepeat };

// A material's use of a texture: which one, which UV set, the KHR_texture_transform, the wrap modes and
// whether it is read bilinearly or by nearest texel (the glTF sampler's magFilter: points are sampled, so
// magnification is the filter that applies).
// The transform uv' = offset + R(rotation) (scale ⊙ uv), R(θ) = [cos θ, sin θ; −sin θ, cos θ] (the
// extension's T · R · S), stored as its columns: uv' = uvFromU · u + uvFromV · v + uvOffset.
struct TraceTextureSlot {
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  uint32_t texture = kNone;  // index into TraceRdb::textures, or none
  uint32_t texCoord = 0;     // 0 = TraceRdb::uv0, 1 = TraceRdb::uv1
  TraceWrap wrapS = TraceWrap::kRepeat;
  TraceWrap wrapT = TraceWrap::kRepeat;
  bool nearest = false;  // the texel the point falls in, instead of bilinear
  vec2 uvFromU{1.0f, 0.0f};
  vec2 uvFromV{0.0f, 1.0f};
  vec2 uvOffset{0.0f};

  explicit operator bool() const { return texture != kNone; }
};

// glTF alpha coverage (sdb::AlphaMode): opaque, cut out below alphaCutoff, or partly covered.
enum class TraceAlpha : uint8_t { kOpaque, kMask, kBlend };

// A material as the integrator uses it: the realistic material's energy rule already applied to its
// constants; textured materials apply it per point to the textured colours (raytracer/surface_point.h).
struct TraceMaterial {
  Rgb diffuse{0.8f};        // Lambertian albedo after the energy rule (at normal incidence), [0,1]
  Rgb diffuseColor{0.8f};   // the diffuse colour before the energy rule, [0,1] (sdb::Material::diffuseColor)
  Rgb reflection{0.0f};     // reflectionColor; with `fresnel` multiplied by Schlick(F0(ior)) at the hit angle
  Rgb transmission{0.0f};   // transmissionColor (before the energy rule's (1 − reflect) factor)
  bool fresnel = true;      // Fresnel (Schlick) or uniform reflection
  float ior = 1.5f;         // [1, 4]
  float reflectionGlossiness = 0.5f;    // [0,1], GGX α = glossiness²
  // Anisotropy of the glossy reflection (sdb::Material), each in [0,1]: the lobe's GGX widths along the U and
  // V axes are ggxAnisotropicAlphas(α, anisotropyU, anisotropyV) (base/ggx.h); U is the surface's tangent
  // turned about the normal by anisotropyRotationRad towards the bitangent (TraceRdb::tangents), V is U
  // turned by a further quarter turn. Equal values: isotropic.
  float anisotropyU = 0.0f;
  float anisotropyV = 0.0f;
  float anisotropyRotationRad = 0.0f;
  float transmissionGlossiness = 0.0f;  // [0,1]
  // Metalness m, [0,1] (sdb::Material::metalnessTexture): the point mixes the material above (weight 1 − m)
  // and a uniform reflector of colour diffuseColor (the base colour, weight m) — reflectance R0 = (1 − m) R0'
  // + m c and R90 = (1 − m) R90' + m c, diffuse and transmission × (1 − m), then the energy rule
  // (raytracer/bsdf.h). `diffuse` is then the mix's D(0).
  float metalness = 0.0f;
  Rgb emissionCdM2{0.0f};   // emitted luminance, cd/m²
  bool doubleSided = false; // emits from both faces (glTF doubleSided)
  uint32_t sdbMaterialId = 0;
  // Reflection fog (sdb::Material): what the reflection lobes show at reflected distance d fades linearly to
  // the radiance of a Lambertian surface of albedo reflectionFogColor at the reflecting point, reached at d =
  // reflectionFogDistanceM (m, (0, ∞]; ∞ = no fog); raytracer/integrator.h.
  float reflectionFogDistanceM = std::numeric_limits<float>::infinity();
  Rgb reflectionFogColor{0.0f};  // [0,1]
  bool hasReflectionFog() const { return std::isfinite(reflectionFogDistanceM); }

  // Textures; each multiplies the constant above it (sdb::Material).
  TraceTextureSlot diffuseTexture;     // sRGB colour × diffuseColor; its alpha (2 or 4 channels) × coverage
  TraceTextureSlot reflectionTexture;  // colour × reflection: linear, or sRGB where reflectionTextureSrgb
  bool reflectionTextureSrgb = false;
  TraceTextureSlot glossinessTexture;  // linear, first channel × reflectionGlossiness
  TraceTextureSlot transmissionTexture;  // linear colour (grey: first channel) × transmission
  TraceTextureSlot emissionTexture;      // sRGB colour × emissionCdM2
  TraceTextureSlot normalTexture;        // tangent-space normal map (glTF normalTexture), linear
  float normalScale = 1.0f;              // scales the map's x and y (glTF normalTexture.scale), ≥ 0
  TraceTextureSlot anisotropyTexture;    // linear; red = anisotropyU, green = anisotropyV (replaces them)
  TraceTextureSlot anisotropyRotationTexture;  // linear; red × 2π = anisotropyRotationRad (replaces it)
  TraceTextureSlot metalnessTexture;           // linear, first channel × metalness

  // Coverage = opacity × the diffuse texture's alpha × COLOR_0's alpha, used as `alpha` says.
  TraceAlpha alpha = TraceAlpha::kOpaque;
  float opacity = 1.0f;      // [0,1]
  float alphaCutoff = 0.5f;  // kMask: covered where coverage ≥ alphaCutoff, [0,1]

  // A measured BRDF that replaces the analytic lobes (diffuse, reflection, transmission) above, which the
  // baker then ignores: an index into TraceRdb::brdfTables, or the compact car-paint model; at most one.
  static constexpr uint32_t kNoBrdfTable = std::numeric_limits<uint32_t>::max();
  uint32_t brdfTable = kNoBrdfTable;
  std::optional<CarPaintBrdf> carPaint;

  bool isMeasured() const { return brdfTable != kNoBrdfTable || carPaint.has_value(); }
  // The glossy reflection is anisotropic somewhere (sdb::Material::isAnisotropic): then the integrator shades
  // it in the frame of TraceRdb::tangents.
  bool isAnisotropic() const { return anisotropyU != anisotropyV || bool(anisotropyTexture); }
  bool hasTextures() const {
    return bool(diffuseTexture) || bool(reflectionTexture) || bool(glossinessTexture) ||
           bool(transmissionTexture) || bool(emissionTexture) || bool(normalTexture) ||
           bool(anisotropyTexture) || bool(anisotropyRotationTexture) || bool(metalnessTexture);
  }
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
  // The scene neither asks for a light texture nor forbids one ("lightTexture": false): the bake may give it
  // one where vertices cannot carry the light (raytracer/light_resolution.h).
  bool automaticLightTextureAllowed = true;
  static constexpr uint32_t kNoLightTexture = std::numeric_limits<uint32_t>::max();
  uint32_t lightTexture = kNoLightTexture;  // index into TraceRdb::lightTextures, or none
};

// A mesh's light texture: per-texel irradiance over a light-map atlas, baked next to the vertex
// light maps. The UV convention is rdb/lightmap_uv.h's: texel (i, j) covers u ∈ [i/width, (i+1)/width),
// v ∈ [j/height, (j+1)/height), row j = 0 at v = 0 is the first (top) row of the image file.
struct TraceLightTexture {
  uint32_t mesh = 0;            // index into TraceRdb::meshes
  uint32_t width = 0;           // atlas size, texels, ≥ 1
  uint32_t height = 0;
  float texelsPerMetre = 0.0f;  // achieved density, texels/m (for TEXCOORD_1: the mean over the mesh)
  bool automatic = false;       // unasked: added where vertices cannot carry the light (addAutomaticLightTexture)
  std::string automaticReason;  // why, in words, for the bake's summary and manifest (automatic only)
  bool fromTexcoord1 = false;   // the UVs are the SDB mesh's TEXCOORD_1, else generated (rdb/lightmap_uv.h)
  bool densityReduced = false;  // generated UVs at less than the requested density, to fit the atlas
  // Light-map UV per triangle corner: 3 per triangle of the mesh, in TraceMesh triangle order. Corners of one
  // vertex differ where charts meet (seams). A triangle whose corners are noLightTextureUv() is not in the
  // atlas: it shows its vertex light map (automatic textures leave out charts finer in vertices than texels).
  std::vector<vec2> cornerUv;
};


// A measured BRDF table that materials share, one per distinct file.
struct TraceBrdfTable {
  std::string file;                        // where the SDB read it, for messages
  std::shared_ptr<const BrdfTable> table;  // never null
  // 1, or 1 / the table's largest directional albedo where that exceeds 1 (BrdfTable::maxAlbedo, the SDB's
  // report: a measurement that reflects more light than it receives, which would let light grow from bounce
  // to bounce): the baker evaluates the table times this factor.
  float scale = 1.0f;
  float maxAlbedo = 0.0f;  // BrdfTable::maxAlbedo's peak, before scaling
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
  // Per-vertex attributes that materials read, each empty when no material needs it (otherwise one per
  // vertex, with the default where a mesh has none): texture coordinates of the sets that texture slots use
  // (default 0, 0); COLOR_0, linear RGBA, when some mesh has it (default 1); unit world tangents (w = ±1, the
  // bitangent's sign: B = w · N × T) when some material has a normal map or anisotropic reflection, from the
  // file or else generated per vertex from the UV derivatives of its triangles (rdb/trace_rdb_build.h).
  std::vector<vec2> uv0;
  std::vector<vec2> uv1;
  std::vector<vec4> colors;
  std::vector<vec4> tangents;
  std::vector<TraceTexture> textures;  // the textures that materials use, each once
  std::vector<uint32_t> indices;
  std::vector<uint32_t> triangleMaterial;  // index into materials, one per triangle
  std::vector<TraceMaterial> materials;
  std::vector<TraceBrdfTable> brdfTables;  // the measured tables that materials use, each once
  std::vector<TraceMesh> meshes;
  std::vector<TraceLightTexture> lightTextures;  // meshes with a light texture, in mesh order

  // Lights.
  std::vector<TracePunctualLight> punctualLights;
  std::vector<TraceGoniometricTable> goniometricTables;
  std::vector<uint32_t> emissiveTriangles;  // triangles whose material emits
  bool hasSun = false;
  TraceSun sun;
  TraceSky sky;
  // Declared sky portals (sdb/portal.h) as triangles, 3 world corners each (m); a quad is two. No geometry:
  // not in the Embree scene, never hit; the integrator aims sky samples through them as through clear glass.
  std::vector<vec3> portalCornersM;

  Bounds3 boundsM;
  size_t skippedTriangles = 0;  // zero-area triangles of the SDB meshes, left out of `indices`

  size_t triangleCount() const { return indices.size() / 3; }
};

}  // namespace fly::rdb
