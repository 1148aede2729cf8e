// The RasterRdb: the scene lowered for the OpenGL engine (docs/architecture.md) as plain, GPU-ready
// arrays: world-space vertices (one copy per placed (node, mesh) pair, in the SDB mesh's vertex order so the
// vertex light maps index them directly), material blocks, lights for the simple mode's Phong, cameras, the
// sky dome, and which shader variants the scene's features call for. World space is glTF's (+Y up, metres);
// light in linear Rec.709 RGB with photometric luminance. The engine's own layouts (std430 blocks, buffers)
// stay in raster/.
#pragma once

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_measured_brdf.h"
#include "rdb/raster_sky.h"

namespace fly::sdb {
class Scene;
struct ChangeSet;
}  // namespace fly::sdb

namespace fly::rdb {

// A material's image texture as the GPU takes it: RGBA8, row-major from the top row (glTF's v = 0 is the
// top row and GL's t = 0 its first row, so uv samples it as given). 1- and 2-channel sources are grey (and
// alpha), 3-channel ones opaque; 16-bit channels are rounded to 8 bits (v₈ = round(v₁₆ · 255 / 65535)).
struct RasterTexture {
  uint32_t sdbTextureId = 0;
  // sRGB-encoded colour (base colour, emission): the GPU decodes it to linear when it samples; otherwise
  // linear data (normal maps). One SDB texture used both ways appears twice.
  bool srgb = false;
  uint32_t width = 0, height = 0;  // texels, ≥ 1
  std::vector<uint8_t> rgba8;      // 4 bytes a texel

  bool operator==(const RasterTexture&) const = default;
};

// How a texture coordinate outside [0, 1] maps into the image (sdb::WrapMode: glTF 2.0 §5.26 wrapS / wrapT,
// the GL wrap modes of the same names).
enum class RasterWrap : uint32_t { kRepeat, kClampToEdge, kMirroredRepeat };
// How a texture is filtered when magnified and minified (sdb::MagFilter, sdb::MinFilter: glTF 2.0 §5.26
// magFilter / minFilter, the GL filters of the same names).
enum class RasterMagFilter : uint32_t { kLinear, kNearest };
enum class RasterMinFilter : uint32_t {
  kNearest,
  kLinear,
  kNearestMipmapNearest,
  kLinearMipmapNearest,
  kNearestMipmapLinear,
  kLinearMipmapLinear,
};

// A material's use of a RasterTexture.
struct RasterTextureRef {
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();
  uint32_t texture = kNone;  // index into RasterRdb::textures, or kNone
  uint32_t texCoord = 0;     // which UV set: 0 = RasterRdb::uv0, 1 = RasterRdb::uv1
  // KHR_texture_transform (sdb::UvTransform) as the rows of the affine map uv' = (dot(uvRow0.xy, uv) +
  // uvRow0.z, dot(uvRow1.xy, uv) + uvRow1.z) = T(offset) · R(rotation) · S(scale) · uv, with the
  // extension's R = [cos r, sin r; −sin r, cos r] (counter-clockwise in UV space, whose v points down).
  vec3 uvRow0{1.0f, 0.0f, 0.0f};
  vec3 uvRow1{0.0f, 1.0f, 0.0f};
  // The glTF sampler: wrapping along u (the image's columns) and v (its rows), and the filters (the
  // mipmapped minification filters also get the engine's anisotropic filtering).
  RasterWrap wrapS = RasterWrap::kRepeat;
  RasterWrap wrapT = RasterWrap::kRepeat;
  RasterMagFilter magFilter = RasterMagFilter::kLinear;
  RasterMinFilter minFilter = RasterMinFilter::kLinearMipmapLinear;

  explicit operator bool() const { return texture != kNone; }
  bool operator==(const RasterTextureRef&) const = default;
};

// How a material's coverage is used (sdb::AlphaMode, glTF 2.0 §3.9.4).
enum class RasterAlphaMode : uint32_t { kOpaque = 0, kMask = 1, kBlend = 2 };

// A material block: what the three modes shade with.
struct RasterMaterial {
  Rgb diffuse{0.8f};   // Lambertian albedo after the energy rule (sdb::Material::effective()), [0,1]
  Rgb specular{0.0f};  // reflect input of the energy rule at normal incidence (reflectionAt(1)), [0,1]
  Rgb emissionCdM2{0.0f};  // emitted luminance, cd/m²; with emissionDisplay a display colour in [0, 1]
  // sdb::Material::emissionDisplay: shown as emissionCdM2 times the exposure's white (Renderer::setDisplayWhite)
  bool emissionDisplay = false;
  // Glass (a material whose energy rule transmits at normal incidence): a thin-walled pane that shows what
  // lies behind it. Clear glass (transmissionAlpha 0, sdb::Material::hasClearTransmission) times its T(θ) at
  // the angle it is seen, as the baker's shadow rays cross it (raytracer/bsdf.h): base/clear_pane.h's pane of
  // two Fresnel faces of the index that fresnelF0 gives, with T(0) = transmission · (1 − reflection · F0), or
  // transmission · (1 − reflection) at every angle for uniform reflection (fresnelF0 < 0). Frosted glass
  // (transmissionAlpha > 0) scatters into the baker's thin-surface GGX lobe of that α mirrored through the
  // pane, whose albedo towards θo is transmission · ((A + B) − (F0 A + F90 B)) by the split sum's table at α
  // (F0 = specular, F90 = environmentF90), and shows what lies behind it blurred by the lobe's width
  // (raster/renderer.h). transmission is 0 for other materials.
  Rgb transmission{0.0f};  // transmissionColor, [0,1]
  // Glass's transmission texture (sdb::Material::transmissionTexture; linear, red): multiplies `transmission`
  // per pixel. With it, `diffuse` is the diffuse input after the reflection's share only, (1 − r′) d, and the
  // engine takes the texel's transmission share: diffuse · (1 − transmission · red). Glass with a texture is
  // shaded per fragment.
  RasterTextureRef transmissionTexture;
  float transmissionAlpha = 0.0f;  // GGX α = transmission glossiness², [0, 1]; 0 (below kSmoothAlpha): clear
  // reflectionColor, [0,1], of clear glass and of uniform reflection (glTF metals, sdb/gltf_import.cpp); 0 for
  // other (Fresnel) reflection. The light-map modes show an opaque uniform reflector as a rough one:
  // (diffuse + reflection) · E / π (raster/renderer.h).
  Rgb reflection{0.0f};
  // The base colour's texel (sRGB-decoded) multiplies specular, reflection and environmentF90 too: a glTF
  // metal reflects its base colour texture (sdb::Material::reflectionTextureSrgb, sdb/gltf_import.cpp).
  bool reflectionTinted = false;
  float fresnelF0 = -1.0f;
  // What the image-based light's split sum (raster/environment_light.h) reflects: F0 = `specular` at normal
  // incidence and F90 = environmentF90 at grazing incidence (the reflection colour: Schlick's Fresnel rises
  // to it; uniform reflection has F90 = F0), with the GGX width ggxAlpha = glossiness² (as the baker's
  // glossy lobe). environmentF90 is 0 for a material that reflects nothing and for measured BRDFs.
  Rgb environmentF90{0.0f};
  float ggxAlpha = 1.0f;
  // The glossiness texture (sdb::Material::reflectionGlossinessTexture; linear) of an opaque analytic material
  // that reflects: its red channel multiplies the glossiness per pixel, so the lobe's width there is
  // α = ggxAlpha · red² (= (glossiness · red)², as the baker) in the lamps', the sun's and the environment's
  // specular terms and the anisotropic widths. Meshes of such a material are shaded per fragment.
  RasterTextureRef glossinessTexture;
  // Metalness per pixel (sdb::Material::metalnessTexture; linear, red × metalness = k): the material mixed
  // with a uniform reflector of the base colour c (diffuse × texel × COLOR_0): specular, environmentF90 and
  // reflection → mix(·, c, k), transmission × (1 − k). With it, `diffuse` is the diffuse colour d before the
  // energy rule, which the engine applies per pixel: (1 − R0)(1 − t)(1 − k) d, R0 the mixed specular, t the
  // mixed transmission. Meshes of such a material are shaded per fragment.
  RasterTextureRef metalnessTexture;
  float metalness = 0.0f;  // [0, 1], the factor of metalnessTexture
  // Textures (each optional). The base colour's texel (sRGB-decoded) times COLOR_0 multiplies `diffuse` —
  // the energy rule is linear in the diffuse input, so this is the rule applied per texel
  // (sdb::applyEnergyRule) — and its alpha the coverage; the emission texel multiplies emissionCdM2; the
  // normal map (glTF normalTexture: tangent space, +Y towards the image's top) bends the normal of the Phong
  // and sun terms, its x and y scaled by normalScale.
  RasterTextureRef baseColorTexture;
  RasterTextureRef emissionTexture;
  RasterTextureRef normalTexture;
  float normalScale = 1.0f;  // [0, ∞)
  // Anisotropic reflection (sdb::Material::isAnisotropic, of an opaque material that reflects): the GGX lobe
  // of ggxAlpha stretched to the widths base/ggx.h's ggxAnisotropicAlphas gives for anisotropyU / V, α_t along
  // the tangent turned by anisotropyRotationRad about the normal towards the front face's bitangent (t' = cos
  // ρ t + sin ρ w (n × t), as the baker), α_b across t'. The tangent is RasterRdb::tangents' (+u of the UV set
  // the normal map, or else the anisotropy's textures, read; UV set 0 without either). The textures
  // replace the values per pixel: anisotropyTexture's red = U, green = V; anisotropyRotationTexture's red ×
  // 2π = ρ. Meshes of such a material are shaded per fragment (RasterRdb::shadedPerFragment).
  bool anisotropic = false;
  float anisotropyU = 0.0f;  // [0, 1]
  float anisotropyV = 0.0f;  // [0, 1]
  float anisotropyRotationRad = 0.0f;
  RasterTextureRef anisotropyTexture;
  RasterTextureRef anisotropyRotationTexture;
  // Coverage = opacity × base colour texel alpha × COLOR_0 alpha, used as alphaMode says: kMask covers where
  // coverage ≥ alphaCutoff, kBlend covers the fraction `coverage` (what lies behind shows through the rest).
  RasterAlphaMode alphaMode = RasterAlphaMode::kOpaque;
  float alphaCutoff = 0.5f;  // [0, 1]
  float opacity = 1.0f;      // [0, 1]
  // A measured or fitted BRDF (sdb::Material::isMeasured): index into RasterRdb::measuredBrdfs, shown per
  // fragment from its ball texture (raster/ball_texture.h) in place of the analytic terms; kNone for others.
  // `diffuse` then holds its albedo at normal incidence (what the directional ambient's mean albedo and the
  // light-map modes' fallback use).
  uint32_t measured = RasterTextureRef::kNone;
  // An opaque reflector shown by planar reflections (sdb::Material::showsPlanarReflection: a mirror, or what
  // the scene file marks "planar"; neither glass nor measured): on a flat mesh the engine shows what it
  // reflects (RasterRdb::planarReflectors). Its reflection R(θ) = mirrorReflection times
  // Schlick's Fresnel of mirrorF0, or times 1 for uniform reflection (mirrorF0 < 0).
  bool mirrorLike = false;
  Rgb mirrorReflection{0.0f};
  float mirrorF0 = -1.0f;
  // Shown by a cube map rendered from each mesh's centre (RasterRdb::cubeReflectors;
  // sdb::Material::showsCubeMapReflection): on its curved meshes (a mirror-like material), or on all of them
  // (the scene file's "cubemap"). Neither glass nor measured.
  bool cubeMapOnCurved = false;
  bool cubeMapAlways = false;
  // Reflection fog (sdb::Material) of an opaque analytic material that reflects (specular > 0; neither glass
  // nor measured): what its planar image, cube map or image-based light shows at reflected distance d fades
  // to fogColor · E / π (E the irradiance the mode has at the pixel) by t = min(d / reflectionFogDistanceM, 1)
  // (docs/materials-engine.md); ∞: none. Such a material is shaded per fragment (shadedPerFragment).
  float reflectionFogDistanceM = std::numeric_limits<float>::infinity();
  Rgb reflectionFogColor{0.0f};  // [0, 1]
  uint32_t sdbMaterialId = 0;

  bool hasTexture() const {
    return bool(baseColorTexture) || bool(emissionTexture) || bool(normalTexture) || bool(anisotropyTexture) ||
           bool(anisotropyRotationTexture) || bool(glossinessTexture) || bool(transmissionTexture) ||
           bool(metalnessTexture);
  }
  bool hasReflectionFog() const { return reflectionFogDistanceM < std::numeric_limits<float>::infinity(); }

  bool operator==(const RasterMaterial&) const = default;
};

// A plane of mirror meshes of one material (RasterMaterial::mirrorLike), which the engine shows by rendering
// the scene mirrored in it (FLY §5's planar reflections): world points p with dot(normal, p) = offsetM, the
// normal on the side the mirrors face (their triangles' front). Meshes whose vertices all lie within 10⁻⁴ of
// their extent (and 1 mm) of one plane are flat; meshes of a material on one plane (normals within 0.06°,
// offsets within 1 mm) share it.
struct RasterPlanarReflector {
  vec3 normal{0, 1, 0};
  float offsetM = 0.0f;
  uint32_t material = 0;           // index into RasterRdb::materials
  std::vector<uint32_t> meshes;    // indices into RasterRdb::meshes
  float areaM2 = 0.0f;
  vec3 loM{0.0f}, hiM{0.0f};       // the meshes' bounding box (world)

  bool operator==(const RasterPlanarReflector&) const = default;
};
// The most planar reflectors a scene renders (one mirrored pass each); further mirrors show no reflection.
inline constexpr uint32_t kMaxPlanarReflectors = 4;

// A mesh that shows what it reflects by a cube environment map (FLY §5's curved reflectors): the scene without
// the mesh rendered into six 90° views from the centre of its bounding box, prefiltered for its glossiness.
// A mesh of a material with RasterMaterial::cubeMapAlways, or with cubeMapOnCurved that is not flat (the
// planar reflectors' flatness test).
struct RasterCubeReflector {
  uint32_t material = 0;  // index into RasterRdb::materials
  uint32_t mesh = 0;      // index into RasterRdb::meshes
  vec3 centreM{0.0f};     // world: the centre of the mesh's bounding box
  float radiusM = 0.0f;   // half the box's diagonal

  bool operator==(const RasterCubeReflector&) const = default;
};
// The most cube-map reflectors a scene renders (six views each, when the scene or its light changes); the
// largest by radius are kept, the others show no reflection.
inline constexpr uint32_t kMaxCubeReflectors = 4;

// A placed mesh: contiguous vertex and index ranges in the flat arrays. Its vertices are the SDB mesh's in
// order; a light-textured mesh's are followed by seam copies (see RasterRdb::lightMapUv).
struct RasterMesh {
  uint32_t sdbNodeId = 0;
  uint32_t sdbMeshId = 0;
  uint32_t firstVertex = 0;
  uint32_t vertexCount = 0;
  uint32_t firstIndex = 0;  // into RasterRdb::indices
  uint32_t indexCount = 0;
  uint32_t material = 0;     // index into RasterRdb::materials
  bool twoSided = false;     // both faces shaded (a light map has front and back values)
  bool hasLightMap = false;  // RasterRdb::frontLux (and backLux when two-sided) hold this mesh's values
  static constexpr uint32_t kNoLightTexture = std::numeric_limits<uint32_t>::max();
  uint32_t lightTexture = kNoLightTexture;  // index into RasterRdb::lightTextures, or none
  bool hasColors = false;  // RasterRdb::colors holds this mesh's COLOR_0 (else it reads (1, 1, 1, 1) there)
  uint32_t planarReflector = RasterTextureRef::kNone;  // index into RasterRdb::planarReflectors, or none
  uint32_t cubeReflector = RasterTextureRef::kNone;    // index into RasterRdb::cubeReflectors, or none

  bool operator==(const RasterMesh&) const = default;
};

// A mesh's baked light texture (rdb/light_map_store.h, MeshLightTexture, without its corner UVs, which became
// RasterRdb::lightMapUv): irradiance in lux per texel, row-major from row 0 (v ∈ [0, 1/height)).
struct RasterLightTexture {
  uint32_t width = 0, height = 0;  // texels, ≥ 1
  std::vector<Rgb> frontLux;       // width·height
  std::vector<Rgb> backLux;        // two-sided meshes baked on both sides, else empty (front on both faces)
  // The part of frontLux / backLux that came straight from the sun's disc (RasterRdb::frontSunDirectLux),
  // the same sizes; empty when the bake kept none apart.
  std::vector<Rgb> frontSunDirectLux;
  std::vector<Rgb> backSunDirectLux;

  bool operator==(const RasterLightTexture&) const = default;
};

enum class RasterLightType : uint32_t { kPoint = 0, kSpot = 1, kDirectional = 2, kGoniometric = 3 };

struct RasterLight {
  RasterLightType type = RasterLightType::kPoint;
  vec3 positionM{0.0f};           // world (unused for directional)
  vec3 directionWorld{0, -1, 0};  // unit, where the light points (−Z of its node)
  vec3 cAxisWorld{1, 0, 0};       // goniometric: unit, the C = 0° half-plane
  // Point, spot: intensity in cd (colour × intensity); goniometric: colour × multiplier, times the table's
  // cd; directional: illuminance in lux on a surface facing it.
  Rgb intensity{0.0f};
  float rangeM = std::numeric_limits<float>::infinity();  // KHR_lights_punctual window; ∞ = none
  float cosInner = 1.0f;                                  // spot cone
  float cosOuter = 0.0f;
  uint32_t goniometricOffset = 0;  // goniometric: first value in RasterRdb::goniometricCd
  uint32_t sdbLightId = 0;

  bool operator==(const RasterLight&) const = default;
};

// Goniometric tables of RasterRdb::goniometricCd: γ from the photometric axis in kGonioGammaSteps steps over
// [0°, 180°], C in kGonioCSteps steps over [0°, 360°) (rdb::tabulateGoniometric's grid and order).
inline constexpr uint32_t kRasterGonioGammaSteps = 37;  // 5°
inline constexpr uint32_t kRasterGonioCSteps = 24;      // 15°

enum class RasterProjection : uint32_t { kPerspective, kOrthographic };

struct RasterCamera {
  std::string name;
  uint32_t sdbCameraId = 0;
  uint32_t sdbNodeId = 0;
  mat4 worldFromCamera{1.0f};  // the camera looks down its −Z with +Y up; rigid (scale removed)
  RasterProjection projection = RasterProjection::kPerspective;
  float yfovRad = 0.8726646f;  // vertical field of view
  float aspectRatio = 0.0f;    // width / height; 0 = the image's
  float znearM = 0.05f;
  float zfarM = std::numeric_limits<float>::infinity();
  float xmagM = 1.0f, ymagM = 1.0f;  // orthographic half extents

  bool operator==(const RasterCamera&) const = default;
};

// Which shader variants and passes the scene's features call for (docs/architecture.md,
// "Features decide what is built"): the engine compiles only these.
struct RasterVariants {
  bool lightMap = false;     // some mesh has a light map: light-map mode is possible
  bool lightTexture = false; // some mesh has a light texture: light-map modes sample it per fragment
  // The light maps keep the sun's direct part apart (RasterRdb::frontSunDirectLux): sunlight mode shows the
  // rest and draws the sun's direct term in real time.
  bool sunDirect = false;
  bool twoSided = false;     // two-sided meshes: the vertex shader's front/back choice
  bool sky = false;          // a sky dome (sunlight mode's background)
  bool sun = false;          // a sun disc (sunlight mode) and the sun as a directional light (both modes)
  bool goniometric = false;  // goniometric lights in the simple mode's Phong
  bool glass = false;        // a mesh of glass: a second pass shows what lies behind it
  bool frostedGlass = false;  // a mesh of frosted glass: what lies behind it is shown blurred (a mip chain)
  // Surfaces shaded per fragment (textures, COLOR_0, alpha coverage; RasterRdb::shadedPerFragment):
  bool textures = false;      // some material samples a texture (RasterRdb::textures is not empty)
  bool normalMaps = false;    // some material has a normal map: RasterRdb::tangents
  bool anisotropy = false;    // some mesh's material is anisotropic (RasterMaterial::anisotropic): tangents
  bool glossinessTextures = false;  // some material reads a glossiness texture (RasterMaterial)
  bool metalnessTextures = false;   // some material reads a metalness texture (RasterMaterial)
  bool uv1 = false;           // some texture is read with the second UV set: RasterRdb::uv1
  bool vertexColors = false;  // some mesh has COLOR_0: RasterRdb::colors
  bool alphaMask = false;     // some material is a cut-out (kMask)
  bool alphaBlend = false;    // some material is blended (kBlend): drawn after the rest, back to front
  bool measuredBrdf = false;  // some mesh has a measured BRDF: ball textures (raster/ball_texture.h)
  bool planarReflectors = false;  // RasterRdb::planarReflectors is not empty: mirrored passes
  bool cubeReflectors = false;    // RasterRdb::cubeReflectors is not empty: cube-map captures
  bool reflectionFog = false;     // some mesh's material has reflection fog (RasterMaterial)
  // Some material's diffuse share depends on the angle to the eye: a Fresnel reflection (F90 = environmentF90
  // differs from F0 = specular < 1; raster/shaders/scene_glsl.h, flyDiffuseTowards). Without one the light-map
  // modes' per-fragment surfaces interpolate no position and normal.
  bool diffuseByAngle = false;

  bool operator==(const RasterVariants&) const = default;
};

// The empirical "directional ambient" term of the FLY paper (§3: it "simulates secondary diffuse illumination
// by raising the luminance of corner vertices"), which the paper does not define. fly's form, per vertex with
// world normal n and corner factor c ∈ [0, 1]:
//   E_ambient = (upLux · (1 + n_y)/2 + downLux · (1 − n_y)/2) · (1 + kCornerGain · c)
// (1 ± n_y)/2 is the view factor of a tilted plane to the upper / lower hemisphere. c is 1 − |Σ wᵢ nᵢ| / Σ wᵢ
// over the faces meeting at a concave corner (angle-weighted unit face normals of every mesh touching the
// point; 0 on a flat surface, 0.29 where two perpendicular faces meet, 0.42 at a room's three-face corner; 0
// at convex corners). Levels: with daylight (sunlight mode), upLux = the sky's horizontal illuminance and
// downLux = that of the ground (reflectance RasterSky::groundAlbedo, rdb/raster_sky.h) lit by sky and sun; in
// simple mode, those of the daylight (when the scene has a sky or sun, whose sun the simple mode's Phong
// also shades with) plus, on both, the ambient term of progressive radiosity (Cohen et al. 1988, §4.2):
// for the scene's lights ρ̄c/(1 − ρ̄c) · Ē, with Ē the area-weighted mean of the lights' unshadowed direct
// illuminance at the vertices, and for its emissive surfaces, which the Phong does not shade with,
// Ē_e · c/(1 − ρ̄c), with Ē_e their flux (π·L per emitting face and m²) spread over every surface — the mean
// illuminance of an enclosure (the integrating-sphere formula) where c = 1; ρ̄ is the area-weighted mean
// albedo (luminance), capped at 0.9, and c the scene's closure (RasterRdb::ambientClosure): the share of the
// light leaving its surfaces that lands on another of them. In a closed room c = 1; a lone ground plane
// under a glTF light has c = 0 and no ambient term, so its Phong shows ρE/π alone.
inline constexpr float kCornerGain = 1.0f;
struct DirectionalAmbient {
  Rgb upLux{0.0f};
  Rgb downLux{0.0f};

  bool operator==(const DirectionalAmbient&) const = default;
};

struct RasterRdb {
  // Geometry: world positions, unit normals, the corner factor of the directional ambient term, per vertex;
  // 3 indices per triangle (zero-area triangles left out).
  std::vector<vec3> positionsM;
  std::vector<vec3> normals;
  std::vector<float> cornerFactor;
  std::vector<uint32_t> indices;
  std::vector<RasterMesh> meshes;
  std::vector<RasterMaterial> materials;  // index 0: the default material (SDB id 0), then first use order
  Bounds3 boundsM;

  // Vertex light maps, irradiance in lux per vertex (aligned with positionsM; 0 for meshes without one).
  // Empty when no mesh has a light map; backLux empty when no mesh with a light map is two-sided.
  std::vector<Rgb> frontLux;
  std::vector<Rgb> backLux;
  // The part of frontLux / backLux that arrived straight from the sun's disc at the bake's sun
  // (LightMapStore::sun), aligned alike; both empty when the light maps keep none apart (a bake without a
  // sun, or by a fly that did not keep it), backSunDirectLux also when backLux is. Sunlight mode shows
  // albedo · (E − E_sunDirect) / π plus the sun's direct term for the current sun (FLY §3).
  std::vector<Rgb> frontSunDirectLux;
  std::vector<Rgb> backSunDirectLux;

  // Light textures. A light-textured mesh's vertices are split where its atlas's charts meet, as in the baked
  // scene.gltf (cli/baked_scene.h): each SDB vertex keeps the UV of its first triangle corner ((0, 0) for a
  // vertex of no triangle) and a copy (same position, normal, light-map values) follows the mesh's SDB
  // vertices for every further UV; its indices use the copies. lightMapUv: per vertex (aligned with
  // positionsM), the light-map UV (rdb/lightmap_uv.h's convention), (0, 0) for meshes without a light
  // texture; empty when no mesh has one.
  std::vector<vec2> lightMapUv;
  std::vector<RasterLightTexture> lightTextures;  // in mesh order

  // Per-vertex attributes of textured and COLOR_0 surfaces, aligned with positionsM, each empty unless some
  // mesh needs it (a mesh that does not reads zeros, or white for colors): UV sets 0 and 1 (the source's, in
  // texture space; a mesh without the set its material reads gets zeros); COLOR_0, linear RGBA; and for
  // normal-mapped and anisotropic meshes the world tangent frame: xyz the unit tangent (towards +u), w = ±1
  // with bitangent = w · cross(normal, tangent) (towards −v, the image's top), as glTF. Tangents come from the
  // file when it has them (placed with worldFromLocal, w times the sign of its determinant), else they are
  // generated per vertex from the UV set of the normal map, else of the anisotropy's textures, else UV set 0
  // (Lengyel 2001, "Computing Tangent Space Basis Vectors": each
  // triangle's ∂p/∂u and ∂p/∂v summed over the triangles at a vertex, made orthogonal to the normal; w from
  // the side ∂p/∂(−v) lies on). A vertex where that gives no direction (a mesh without the UV set, or a UV
  // area of zero) takes n × x̂ (n × ŷ where |n_x| ≥ 0.9), normalised, with w = 1. Seam copies of
  // light-textured meshes carry their source vertex's values.
  std::vector<vec2> uv0;
  std::vector<vec2> uv1;
  std::vector<vec4> colors;
  std::vector<vec4> tangents;
  // The materials' textures, in the materials' first-use order (base colour, emission, normal map,
  // anisotropy, anisotropy rotation, glossiness).
  std::vector<RasterTexture> textures;
  // The measured BRDFs of the materials that have one (RasterMaterial::measured), in the materials' order.
  std::vector<RasterMeasuredBrdf> measuredBrdfs;
  // Flat mirrors (RasterPlanarReflector), the kMaxPlanarReflectors largest by area.
  std::vector<RasterPlanarReflector> planarReflectors;
  // Curved mirrors (RasterCubeReflector), the kMaxCubeReflectors largest.
  std::vector<RasterCubeReflector> cubeReflectors;

  std::vector<RasterLight> lights;
  std::vector<float> goniometricCd;
  DirectionalAmbient ambient;          // simple mode (the daylight and the scene's lights)
  // The share of the light that leaves the scene's surfaces — what they emit and reflect of the lights,
  // cosine-distributed — that lands on another surface rather than escaping: DirectionalAmbient's c,
  // estimated by up to 4 096 rays from points distributed by that flux (fewer in scenes of many triangles);
  // nullopt for a scene without lights or emitters.
  std::optional<float> ambientClosure;
  DirectionalAmbient daylightAmbient;  // sunlight mode (sky and sun)

  std::vector<RasterCamera> cameras;  // in id order

  std::optional<RasterSky> sky;  // nullopt when the scene has neither sky nor sun

  RasterVariants variants;

  size_t triangleCount() const { return indices.size() / 3; }
  // Whether the engine shades `mesh` per fragment: its material has a texture, alpha coverage, anisotropy or a
  // measured BRDF, or the mesh has COLOR_0; clear glass stays in its own pass, shaded per vertex without textures.
  bool shadedPerFragment(const RasterMesh& mesh) const;
  bool operator==(const RasterRdb&) const;
};

// What RasterRdb::update re-made, so the engine re-uploads only that.
struct RasterRdbChanges {
  bool geometry = false;   // vertices, indices, meshes, light maps, corner factors: everything below too
  // The whole material table (an assignment changed the table). Changes that alter which textures or
  // per-vertex attributes the scene needs, or a material's alpha mode, rebuild everything (geometry).
  bool materials = false;
  std::vector<uint32_t> materialBlocks;  // else: these blocks only
  bool lights = false;                   // lights, goniometric tables
  bool ambient = false;                  // the directional ambient levels
  bool cameras = false;
  bool sky = false;  // sky dome and sun (a new time of day, site or sky)

  bool any() const {
    return geometry || materials || !materialBlocks.empty() || lights || ambient || cameras || sky;
  }
};

struct RasterBuildOptions {
  uint32_t skyWidth = 256;  // sky dome image, pixels (rdb::buildRasterSky)
  uint32_t skyHeight = 128;
};

// The illuminance (lux) that light `l` of `rdb` gives a surface at p facing it, unshadowed, and the unit
// direction towards it (toLightWorld): a directional light's as given, the others I(direction) · window / d²
// with KHR_lights_punctual's range window and spot falloff, or the goniometric table (bilinear, as the
// shader's flyGonioCd); 0 at the light's own position. The GL engine's shaders compute the same.
Rgb punctualIlluminanceLux(const RasterRdb& rdb, const RasterLight& l, const vec3& p, vec3& toLightWorld);

// Builds the RasterRdb of `scene`, with the vertex light maps and light textures of `lightMaps` where it has
// them (matched by (SDB node id, SDB mesh id); a light map whose vertex count differs from the mesh's, or a
// light texture whose corner UVs do not match the mesh's triangles with area, is an InputError).
// Errors: as buildTraceRdb (InputError from the site and weather file).
RasterRdb buildRasterRdb(const sdb::Scene& scene, const LightMapStore* lightMaps = nullptr,
                         const RasterBuildOptions& options = {});

// Brings `rdb` (built from the scene before `changes`) up to date with `scene`, re-making only what changed:
// a material edit re-makes that block (and the ambient level) unless it changes which textures, UV sets or
// alpha mode the material uses (then, as for an edited texture, everything is rebuilt), a time, site or sky change re-makes the sky
// and daylight ambient, a light edit the lights and ambient, a camera edit the cameras; any change of
// geometry, hierarchy or attachments rebuilds. The result equals buildRasterRdb(scene, lightMaps, options).
RasterRdbChanges updateRasterRdb(RasterRdb& rdb, const sdb::Scene& scene, const sdb::ChangeSet& changes,
                                 const LightMapStore* lightMaps = nullptr,
                                 const RasterBuildOptions& options = {});

}  // namespace fly::rdb
