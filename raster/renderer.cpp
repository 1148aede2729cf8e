#include "raster/renderer.h"

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "base/ggx.h"
#include "raster/cube_reflections.h"
#include "raster/room_probe.h"
#include "raster/draw_chunks.h"
#include "raster/gl_program.h"
#include "raster/mirror_blur.h"
#include "raster/shaders/ambient_occlusion_glsl.h"
#include "raster/shaders/ball_texture_glsl.h"
#include "raster/shaders/mirror_blur_glsl.h"
#include "raster/shaders/scene_glsl.h"
#include "raster/shaders/sun_glass_glsl.h"
#include "raster/sun_glass.h"
#include "rdb/lightmap_uv.h"

namespace fly::raster {

const char* renderModeName(RenderMode m) {
  switch (m) {
    case RenderMode::kSimple:
      return "simple";
    case RenderMode::kLightMap:
      return "lightmap";
    case RenderMode::kSunlight:
      return "sunlight";
  }
  return "?";
}

std::vector<RenderMode> supportedModes(const rdb::RasterRdb& rdb) {
  std::vector<RenderMode> modes;
  if (rdb.variants.lightMap) modes.push_back(RenderMode::kLightMap);
  if (rdb.variants.sky) modes.push_back(RenderMode::kSunlight);
  modes.push_back(RenderMode::kSimple);
  return modes;
}

View viewOfCamera(const rdb::RasterCamera& camera) {
  View v;
  v.worldFromCamera = camera.worldFromCamera;
  v.orthographic = camera.projection == rdb::RasterProjection::kOrthographic;
  v.yfovRad = camera.yfovRad;
  v.znearM = camera.znearM;
  v.zfarM = std::isfinite(camera.zfarM) ? camera.zfarM : 1e30f;
  v.xmagM = camera.xmagM;
  v.ymagM = camera.ymagM;
  return v;
}

View framingView(const Bounds3& boundsM, float aspect) {
  View v;
  const vec3 center = boundsM.empty() ? vec3(0.0f) : 0.5f * (boundsM.min + boundsM.max);
  const float radius = std::max(1e-3f, 0.5f * glm::length(boundsM.size()));
  const float halfFov = 0.5f * v.yfovRad;
  const float halfFovX = std::atan(std::tan(halfFov) * std::max(aspect, 1e-3f));
  const float distance = radius / std::sin(std::min(halfFov, halfFovX));
  const float elevation = float(degToRad(30.0));
  const vec3 back = glm::normalize(vec3(std::cos(elevation) * 0.70710678f, std::sin(elevation),
                                        std::cos(elevation) * 0.70710678f));  // from the target to the eye
  const vec3 eye = center + distance * back;
  const vec3 x = glm::normalize(glm::cross(vec3(0, 1, 0), back));
  const vec3 y = glm::cross(back, x);
  v.worldFromCamera = frameTransform(x, y, back, eye);
  v.znearM = std::max(1e-3f * distance, distance - 1.01f * radius);
  v.zfarM = distance + 1.01f * radius;
  return v;
}

namespace {

// The shader's std430 blocks (raster/shaders/scene_glsl.h).
struct GpuMaterial {
  vec4 diffuse, specular, emission, transmission, reflection, coverage, environment, anisotropy;
};
struct GpuLight {
  vec4 positionType, directionRange, cAxisOffset, intensity, cone;
};

GpuMaterial gpuMaterial(const rdb::RasterMaterial& m) {
  return {vec4(m.diffuse, m.reflectionTinted ? 1.0f : 0.0f),
          vec4(m.specular, 0.0f),
          // A display colour c as −(c + 1) (every channel ≤ −1), which flyEmission scales by the display white.
          vec4(m.emissionDisplay ? -(m.emissionCdM2 + Rgb(1.0f)) : m.emissionCdM2, m.transmissionAlpha),
          vec4(m.transmission, m.fresnelF0),
          vec4(m.reflection, m.metalness),
          vec4(m.opacity, m.alphaCutoff, m.normalScale, float(uint32_t(m.alphaMode))),
          vec4(m.environmentF90, m.ggxAlpha),
          vec4(m.anisotropyU, m.anisotropyV, m.anisotropyRotationRad, m.anisotropic ? 1.0f : 0.0f)};
}

// A per-fragment draw's texture slots (kSurfaceFragment's uTextureSlots bits, in this order) and the texture
// units they are bound to: base colour, emission, normal map, anisotropy, anisotropy rotation, glossiness,
// transmission, metalness.
constexpr int kTextureSlots = 8;
constexpr GLuint kTextureSlotUnits[kTextureSlots] = {5, 6, 7, 16, 17, 18, 19, 20};
std::array<const rdb::RasterTextureRef*, kTextureSlots> textureSlots(const rdb::RasterMaterial& m) {
  return {&m.baseColorTexture,          &m.emissionTexture,   &m.normalTexture,       &m.anisotropyTexture,
          &m.anisotropyRotationTexture, &m.glossinessTexture, &m.transmissionTexture, &m.metalnessTexture};
}

mat4 projection(const View& v, float aspect) {
  if (v.orthographic) {
    const float ymag = v.ymagM, xmag = v.ymagM * aspect;
    return glm::ortho(-xmag, xmag, -ymag, ymag, v.znearM, v.zfarM);
  }
  if (v.zfarM >= 1e30f) return glm::infinitePerspective(v.yfovRad, aspect, v.znearM);
  return glm::perspective(v.yfovRad, aspect, v.znearM, v.zfarM);
}

// A rectangle of pixels (x, y from the bottom left).
struct ScreenRect {
  GLint x = 0, y = 0;
  GLsizei width = 0, height = 0;
  bool empty() const { return width <= 0 || height <= 0; }
};

// The pixels the box [lo, hi] covers on a widthPx × heightPx image (one pixel of margin); the whole image
// where a corner lies behind the eye, nothing where the box lies outside the view.
ScreenRect boxOnScreen(const mat4& clipFromWorld, const vec3& lo, const vec3& hi, uint32_t widthPx, uint32_t heightPx) {
  vec4 corners[8];
  uint32_t outsideAll = 0x1f;  // per frustum plane x ≥ −w, x ≤ w, y ≥ −w, y ≤ w, w > 0: every corner beyond it
  bool behindEye = false;
  for (int c = 0; c < 8; ++c) {
    const vec4 p = clipFromWorld * vec4(c & 1 ? hi.x : lo.x, c & 2 ? hi.y : lo.y, c & 4 ? hi.z : lo.z, 1.0f);
    corners[c] = p;
    const uint32_t outside = (p.x < -p.w ? 1u : 0u) | (p.x > p.w ? 2u : 0u) | (p.y < -p.w ? 4u : 0u) |
                             (p.y > p.w ? 8u : 0u) | (p.w <= 1e-6f ? 16u : 0u);
    outsideAll &= outside;
    behindEye |= p.w <= 1e-6f;
  }
  if (outsideAll != 0) return {};
  if (behindEye) return {0, 0, GLsizei(widthPx), GLsizei(heightPx)};
  vec2 ndcLo(1e30f), ndcHi(-1e30f);
  for (const vec4& p : corners) {
    ndcLo = glm::min(ndcLo, vec2(p) / p.w);
    ndcHi = glm::max(ndcHi, vec2(p) / p.w);
  }
  const float x0 = std::floor((ndcLo.x * 0.5f + 0.5f) * float(widthPx)) - 1.0f;
  const float y0 = std::floor((ndcLo.y * 0.5f + 0.5f) * float(heightPx)) - 1.0f;
  const float x1 = std::ceil((ndcHi.x * 0.5f + 0.5f) * float(widthPx)) + 1.0f;
  const float y1 = std::ceil((ndcHi.y * 0.5f + 0.5f) * float(heightPx)) + 1.0f;
  ScreenRect r;
  r.x = GLint(std::clamp(x0, 0.0f, float(widthPx)));
  r.y = GLint(std::clamp(y0, 0.0f, float(heightPx)));
  r.width = GLsizei(std::clamp(x1, 0.0f, float(widthPx))) - r.x;
  r.height = GLsizei(std::clamp(y1, 0.0f, float(heightPx))) - r.y;
  return r;
}

// `clipFromCamera` with its near plane replaced by `planeCamera` (camera space; points p with
// dot(planeCamera, (p, 1)) ≥ 0 are kept): Lengyel, "Oblique View Frustum Depth Projection and Clipping",
// Journal of Game Development 1(2), 2005. The far plane tilts with it; depth stays monotonic in front of it.
mat4 obliqueNearPlane(mat4 clipFromCamera, const vec4& planeCamera) {
  const auto sign = [](float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); };
  const vec4 q = glm::inverse(clipFromCamera) * vec4(sign(planeCamera.x), sign(planeCamera.y), 1.0f, 1.0f);
  const vec4 c = planeCamera * (2.0f / glm::dot(planeCamera, q));
  // The third row becomes c − the fourth row.
  for (int col = 0; col < 4; ++col) clipFromCamera[col][2] = c[col] - clipFromCamera[col][3];
  return clipFromCamera;
}

// GGX α from which a planar reflector's image is blurred (flyMirrorImage): the baker's bound between a delta
// lobe and a glossy one (raytracer/bsdf.h, kSmoothAlpha).
constexpr float kGlossyMirrorAlpha = 1e-3f;

// Pixels per unit of tan(angle from the view axis) at the image's centre (perspective), or −pixels per metre
// (orthographic): how far a lobe's angle reaches on a heightPx-high image (flyBlurLod, MirrorLobe::pxPerTan).
float blurScale(const View& view, uint32_t heightPx) {
  return view.orthographic ? -0.5f * float(heightPx) / view.ymagM : 0.5f * float(heightPx) / std::tan(0.5f * view.yfovRad);
}

// The scene program's shader variant, one bit per #define (Renderer::sceneProgram).
enum VariantBit : uint32_t {
  kVariantLightMap = 1u << 0,
  kVariantPhong = 1u << 1,
  kVariantSun = 1u << 2,
  kVariantTwoSided = 1u << 3,
  kVariantGonio = 1u << 4,
  kVariantLightTexture = 1u << 5,
  kVariantGlass = 1u << 6,
  // The per-fragment surfaces' program (kSurfaceVertex, kSurfaceFragment) and its own #defines.
  kVariantPerFragment = 1u << 7,
  kVariantTextures = 1u << 8,
  kVariantNormalMap = 1u << 9,
  kVariantUv1 = 1u << 10,
  kVariantVertexColor = 1u << 11,
  kVariantAlphaMask = 1u << 12,
  kVariantBlendPass = 1u << 13,
  // Sunlight mode over light maps that keep the sun's direct part apart (rdb::RasterVariants::sunDirect).
  kVariantSunDirect = 1u << 14,
  // The sun's direct term through clear glass times its T (raster/sun_glass.h): scenes with glass and a sun.
  kVariantSunGlass = 1u << 15,
  // Measured BRDFs shown by their ball textures (raster/ball_texture.h): scenes with such materials.
  kVariantMeasured = 1u << 16,
  // The opaque draws record their near lamps' pixels for kNearLampsCompute (scenes whose measured materials
  // have lamps within BallSettings::nearLightRadii).
  kVariantNearDeferred = 1u << 17,
  // Flat mirrors show the image of a mirrored pass (RasterRdb::planarReflectors).
  kVariantPlanarReflection = 1u << 18,
  // Curved reflectors show their cube maps (RasterRdb::cubeReflectors, raster/cube_reflections.h).
  kVariantCubeReflection = 1u << 20,
  // Sunlight mode's image-based light from the sky (raster/environment_light.h).
  kVariantIbl = 1u << 19,
  // Simple mode's ambient term times the screen-space ambient occlusion (raster/ambient_occlusion.h).
  kVariantAmbientOcclusion = 1u << 21,
  // Frosted glass (with kVariantGlass): its transmittance by the split sum's table, what lies behind it
  // blurred by the lobe's width (rdb::RasterMaterial::transmissionAlpha).
  kVariantFrosted = 1u << 22,
  // Materials with reflection fog (per fragment): what they reflect fades to the fog's luminance with the
  // reflected distance (rdb::RasterMaterial::reflectionFogDistanceM).
  kVariantReflectionFog = 1u << 23,
  // Anisotropic reflection lobes (rdb::RasterMaterial::anisotropic; per-fragment surfaces, with tangents).
  kVariantAnisotropy = 1u << 24,
  // The light-map modes' per-fragment surfaces scale the diffuse albedo by the angle to the eye
  // (rdb::RasterVariants::diffuseByAngle): they interpolate the position and normal for it.
  kVariantDiffuseByAngle = 1u << 25,
  // Glossiness textures (rdb::RasterMaterial::glossinessTexture; per-fragment surfaces): the lobe's width per
  // pixel in the lamps', the sun's and the environment's specular terms.
  kVariantGlossinessTexture = 1u << 26,
  // With kVariantIbl: the specular environment is the room probe's, looked up with its box (raster/room_probe.h).
  kVariantRoomProbe = 1u << 27,
  // Metalness textures (rdb::RasterMaterial::metalnessTexture; per-fragment surfaces): the mix with a metal of
  // the base colour per pixel.
  kVariantMetalnessTexture = 1u << 28,
};

// Some mesh shows the environment's specular light (its material's environmentF90 > 0, and it is no planar or
// cube reflector, which show their own images): the room probe has a use.
bool reflectsEnvironment(const rdb::RasterRdb& r) {
  return std::any_of(r.meshes.begin(), r.meshes.end(), [&](const rdb::RasterMesh& mesh) {
    const rdb::RasterMaterial& x = r.materials[mesh.material];
    return mesh.planarReflector == rdb::RasterTextureRef::kNone &&
           mesh.cubeReflector == rdb::RasterTextureRef::kNone &&
           std::max({x.environmentF90.r, x.environmentF90.g, x.environmentF90.b}) > 0.0f;
  });
}

// A glTF sampler (rdb::RasterTextureRef's wrap modes and filters) as one number: the key of its GL sampler
// object (Renderer::samplerFor).
uint32_t samplerKey(const rdb::RasterTextureRef& ref) {
  return uint32_t(ref.wrapS) | uint32_t(ref.wrapT) << 4 | uint32_t(ref.magFilter) << 8 |
         uint32_t(ref.minFilter) << 12;
}

rdb::RasterMinFilter minFilterOfKey(uint32_t key) {
  return rdb::RasterMinFilter((key >> 12) & 0xfu);
}

// Whether the sampler of `key` reads mip levels (then it also gets anisotropic filtering).
bool samplerMipmapped(uint32_t key) {
  const rdb::RasterMinFilter f = minFilterOfKey(key);
  return f != rdb::RasterMinFilter::kNearest && f != rdb::RasterMinFilter::kLinear;
}

GLint glMinFilter(rdb::RasterMinFilter f) {
  switch (f) {
    case rdb::RasterMinFilter::kNearest:
      return GL_NEAREST;
    case rdb::RasterMinFilter::kLinear:
      return GL_LINEAR;
    case rdb::RasterMinFilter::kNearestMipmapNearest:
      return GL_NEAREST_MIPMAP_NEAREST;
    case rdb::RasterMinFilter::kLinearMipmapNearest:
      return GL_LINEAR_MIPMAP_NEAREST;
    case rdb::RasterMinFilter::kNearestMipmapLinear:
      return GL_NEAREST_MIPMAP_LINEAR;
    case rdb::RasterMinFilter::kLinearMipmapLinear:
      break;
  }
  return GL_LINEAR_MIPMAP_LINEAR;
}

GLint glWrap(rdb::RasterWrap w) {
  switch (w) {
    case rdb::RasterWrap::kClampToEdge:
      return GL_CLAMP_TO_EDGE;
    case rdb::RasterWrap::kMirroredRepeat:
      return GL_MIRRORED_REPEAT;
    case rdb::RasterWrap::kRepeat:
      break;
  }
  return GL_REPEAT;
}

// Compiled programs and their uniforms' locations (−1 where a variant has none: glUniform ignores it).
struct BackgroundProgram {
  GLuint program = 0;
  GLint worldFromCamera = -1, tanHalfFov = -1, sunDir = -1, sunRadiance = -1, sunCosHalfAngle = -1, region = -1,
        passPx = -1;
};
struct ToneMapProgram {
  GLuint program = 0;
  GLint op = -1, exposureScale = -1, whitePoint = -1;
};

// One draw of per-fragment surfaces (rdb::RasterRdb::shadedPerFragment): a material's opaque or cut-out
// meshes, or one blended mesh, as a range of the draw-ordered index buffer (Renderer::uploadDraws).
struct SurfaceDraw {
  size_t firstIndex = 0;
  GLsizei indexCount = 0;
  uint32_t material = 0;
  bool mask = false;
  bool blend = false;
  bool twoSided = false;  // both faces drawn (two-sided or glass); else the back faces are culled
  bool glass = false;     // glass: drawn in the glass pass, over the image of the rest
  uint32_t reflector = rdb::RasterTextureRef::kNone;  // RasterRdb::planarReflectors' index of its meshes
  uint32_t cubeReflector = rdb::RasterTextureRef::kNone;  // RasterRdb::cubeReflectors' index of its mesh
  vec3 centreM{0.0f};              // blended: the mesh's bounding-box centre, sorted by its view depth
  GLuint samplers[kTextureSlots] = {};  // the material's texture slots' sampler objects (Renderer::samplerFor)
};

// A per-fragment draw's sampler objects, one per texture slot of its material (textureSlots), from
// `samplerOf` (Renderer::samplerFor).
template <class SamplerOf>
void assignSamplers(SurfaceDraw& d, const rdb::RasterRdb& r, SamplerOf samplerOf) {
  const auto slots = textureSlots(r.materials[d.material]);
  for (int k = 0; k < kTextureSlots; ++k) d.samplers[k] = *slots[k] ? samplerOf(*slots[k]) : 0;
}

// A light texture's place in the array texture (kSceneFragment's LightRect): rect = x, y, width, height in
// texels of the layer; layer = the layer's index, 1 / layer width, 1 / layer height.
struct GpuLightRect {
  vec4 rect, layer;
};
// aLightSlot of kSceneVertex: the slot of the mesh's front light texture, kLightSlotHasBack when the back's
// follows it; kNoLightSlot for a mesh without one.
constexpr uint32_t kNoLightSlot = 0xffffffffu;
constexpr uint32_t kLightSlotHasBack = 0x80000000u;

// aSurface of kSceneVertex: bits 0–29 the material's index, bit 30 two-sided, bit 31 has a light map.
uint32_t surfaceBits(const rdb::RasterMesh& m) {
  return (m.material & 0x3fffffffu) | (m.twoSided ? 0x40000000u : 0u) | (m.hasLightMap ? 0x80000000u : 0u);
}

// Replaces `buffer` with a new immutable store holding `data`. A zero-sized store cannot be bound as an SSBO
// range, so an empty `data` still gets one element's (undefined, never read) room.
template <class T>
void storeBuffer(GLuint& buffer, const std::vector<T>& data, GLbitfield flags = 0) {
  glDeleteBuffers(1, &buffer);
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(1, data.size()) * sizeof(T)),
                       data.empty() ? nullptr : data.data(), flags);
}

// Runs the bound compute program (8 × 8 work groups, kBackgroundCompute, kToneMapCompute) over every pixel,
// then makes its image stores visible to what reads them next: texture fetches (the tone-map pass),
// framebuffer access (the scene drawn over the background, present) and read-backs (luminanceRgb, srgb8).
void dispatchPerPixel(uint32_t widthPx, uint32_t heightPx) {
  glDispatchCompute((widthPx + 7) / 8, (heightPx + 7) / 8, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_FRAMEBUFFER_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

// shaders::kLuminanceEncoding's flyDecodeLuminance on the CPU: a pixel's two words → linear RGB in cd/m².
void decodeLuminance(uint32_t x, uint32_t y, float* rgb) {
  const uint32_t q[3] = {x & 0x7ffffu, (x >> 19) | ((y & 0x3fu) << 13), (y >> 6) & 0x7ffffu};
  const int exponent = int(y >> 25) - 64;
  for (int c = 0; c < 3; ++c) rgb[c] = std::ldexp(float(q[c]), exponent - 19);
}

}  // namespace

struct Renderer::SceneProgram {
  GLuint program = 0;
  GLint clipFromWorld = -1, eye = -1, viewDir = -1, orthographic = -1, lightCount = -1, ambientUp = -1,
        ambientDown = -1, displayWhite = -1, sunDir = -1, sunNormalLux = -1, glassPass = -1, textureSlots = -1, uvRows = -1,
        material = -1, sunGlassFromWorld = -1, sunGlassBias = -1, ballLayer = -1, ballFromWorld = -1,
        nearLights = -1, nearLightCount = -1, reflector = -1, sunInReflection = -1, mirrorReflection = -1,
        mirrorF0 = -1, radianceTopLevel = -1, cubeReflector = -1, worldFromClip = -1, blurView = -1,
        mirrorGlossy = -1, mirrorCoarse = -1, mirrorWorldFromClip = -1, fogDistance = -1, fogColor = -1,
        mirrorScale = -1, mirrorFine = -1, mirrorTapCount = -1, mirrorTaps = -1, probeCentre = -1,
        probeBoxMin = -1, probeBoxMax = -1, irradianceAmbient = -1;
};

struct NearProgram {
  GLuint program = 0;
  GLint worldFromClip = -1, eye = -1, viewDir = -1, orthographic = -1;
};

struct Renderer::Gpu {
  GLuint vao = 0;
  GLuint positions = 0, normals = 0, corners = 0, surfaces = 0, frontLux = 0, backLux = 0, indices = 0;
  GLuint frontSunLux = 0, backSunLux = 0;  // rdb::RasterRdb::frontSunDirectLux, backSunDirectLux
  GLuint materials = 0, lights = 0, gonio = 0;
  GLuint skyTexture = 0;
  // Light textures (uploadLightTextures): per vertex the light-map UV and the slot; the slots' rectangles;
  // every slot's texels in one RGBA32F array texture.
  GLuint lightMapUv = 0, lightSlots = 0, lightRects = 0, lightTextures = 0;
  GLuint floatFbo = 0, floatColor = 0, depth = 0;
  // Scenes with clear glass: a copy of the float image before the glass is drawn, which the glass shows
  // through itself (render). Made at the first such render of a size.
  GLuint behindColor = 0;
  // Scenes with frosted glass: that copy decoded to RGBA32F with a box-filtered mip chain, which frosted panes
  // read at the level of their lobe's width, and a copy of the depth buffer, which says how far behind a pane
  // what it shows lies; the split sum's table for their transmittance (made once); the decoding pass.
  GLuint behindBlurred = 0, behindDepth = 0, frostTable = 0, behindDecode = 0;
  GLuint srgbFbo = 0, srgbColor = 0;
  // Per-fragment surfaces: their attributes (rdb::RasterRdb::uv0 …), the materials' textures (one GL texture
  // each, mipmapped), the index buffer in draw order (per-vertex meshes first, then SurfaceDraws' ranges),
  // and for blended ones the blend target (RGBA32F, kBlendComposite) with its framebuffer (sharing `depth`).
  GLuint uv0 = 0, uv1 = 0, colors = 0, tangents = 0, drawIndices = 0;
  std::vector<GLuint> textures;
  // One sampler object per distinct glTF sampler the materials use (samplerFor), by samplerKey.
  std::map<uint32_t, GLuint> samplers;
  GLuint blendFbo = 0, blendColor = 0;
  GLuint composite = 0;
  std::vector<SurfaceDraw> surfaceDraws;  // opaque and cut-out first (by material), then blended
  std::vector<size_t> blendOrder;         // per frame: the blended draws back to front
  GLsizei perVertexIndexCount = 0;        // the first range of the element buffer: per-vertex meshes
  GLsizei perVertexOneSidedCount = 0;     // of which the one-sided meshes' come first (back faces culled)
  // That range in chunks with their boxes (raster/draw_chunks.h), and per pass the chunks it draws.
  std::vector<DrawChunk> perVertexChunks;
  std::vector<IndexRange> visibleChunks;
  std::vector<GLsizei> drawCounts;
  std::vector<const void*> drawOffsets;
  float maxAnisotropy = 1.0f;             // the textures' (setMaxAnisotropy); 1 without anisotropic filtering
  float driverMaxAnisotropy = 1.0f;       // min(kMaxAnisotropy, the driver's), 1 without
  std::map<uint32_t, SceneProgram> scene;  // by variant (VariantBit)
  BackgroundProgram background, sky;
  ToneMapProgram toneMap;
  // The measured materials' near lamps (kNearLampsCompute): the opaque draws' records (two RGBA32UI images,
  // framebuffer attachments 1 and 2, made at the first such render of a size, all 0 between frames), the
  // lamps per BRDF, and the pass's program without and with goniometric lights.
  GLuint nearData = 0, nearLight = 0, nearLists = 0;
  // The sharp planar reflectors' images (RG32UI, kLuminanceEncoding, the target's size; a glossy one's is its
  // MirrorBlur pyramid), which this frame made, and how much coarser per axis each one's pass was drawn.
  std::vector<GLuint> reflectionColor;
  std::vector<char> reflectionShown;
  std::vector<uint32_t> reflectionScale;
  // Reflection fog: a fogged planar reflector's pass depth and worldFromClip (drawReflections;
  // shaders::kSurfaceFragment, flyMirrorDistance), 0 for others; a cube face's depth for a cube reflector
  // with fog (captureCubeReflectors), 0 until one.
  std::vector<GLuint> reflectionDepth;
  std::vector<mat4> reflectionWorldFromClip;
  GLuint cubeFaceDepth = 0;
  std::map<bool, NearProgram> nearPrograms;
  GLint maxImageSizePx = 0;  // GL_MAX_RENDERBUFFER_SIZE and GL_MAX_TEXTURE_SIZE, whichever is smaller
  GLsizei indexCount = 0;    // of the whole scene
  bool everyMeshLightMapped = false;
  bool environmentReflected = false;  // reflectsEnvironment: some mesh shows the environment

  ~Gpu() {
    const GLuint buffers[] = {positions, normals,   corners,     surfaces,    frontLux,  backLux,
                              indices,   materials, lights,      gonio,       uv0,       uv1,
                              colors,    tangents,  drawIndices, frontSunLux, backSunLux};
    glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
    glDeleteTextures(GLsizei(textures.size()), textures.data());
    for (const auto& [key, sampler] : samplers) glDeleteSamplers(1, &sampler);
    glDeleteTextures(1, &blendColor);
    glDeleteFramebuffers(1, &blendFbo);
    glDeleteProgram(composite);
    glDeleteVertexArrays(1, &vao);
    glDeleteTextures(1, &skyTexture);
    const GLuint lightBuffers[] = {lightMapUv, lightSlots, lightRects};
    glDeleteBuffers(GLsizei(std::size(lightBuffers)), lightBuffers);
    glDeleteTextures(1, &lightTextures);
    glDeleteTextures(1, &floatColor);
    glDeleteTextures(1, &behindColor);
    glDeleteTextures(1, &behindBlurred);
    glDeleteTextures(1, &behindDepth);
    glDeleteTextures(1, &frostTable);
    glDeleteProgram(behindDecode);
    glDeleteTextures(1, &srgbColor);
    glDeleteRenderbuffers(1, &depth);
    glDeleteFramebuffers(1, &floatFbo);
    glDeleteFramebuffers(1, &srgbFbo);
    for (const auto& [variant, p] : scene) glDeleteProgram(p.program);
    glDeleteProgram(background.program);
    glDeleteProgram(sky.program);
    glDeleteProgram(toneMap.program);
    const GLuint nearTextures[] = {nearData, nearLight};
    glDeleteTextures(2, nearTextures);
    glDeleteBuffers(1, &nearLists);
    for (const auto& [withGonio, p] : nearPrograms) glDeleteProgram(p.program);
    glDeleteTextures(GLsizei(reflectionColor.size()), reflectionColor.data());
    glDeleteTextures(GLsizei(reflectionDepth.size()), reflectionDepth.data());
    glDeleteTextures(1, &cubeFaceDepth);
  }
};

Renderer::Renderer() : gpu_(std::make_unique<Gpu>()) {
  glCreateVertexArrays(1, &gpu_->vao);
  GLint renderbufferPx = 0, texturePx = 0;
  glGetIntegerv(GL_MAX_RENDERBUFFER_SIZE, &renderbufferPx);
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &texturePx);
  gpu_->maxImageSizePx = std::min(renderbufferPx, texturePx);
  // Anisotropic filtering: core in GL 4.6, else ARB_/EXT_texture_filter_anisotropic (the same enums).
  if (epoxy_gl_version() >= 46 || epoxy_has_gl_extension("GL_ARB_texture_filter_anisotropic") ||
      epoxy_has_gl_extension("GL_EXT_texture_filter_anisotropic")) {
    GLfloat maxAniso = 1.0f;
    glGetFloatv(GL_MAX_TEXTURE_MAX_ANISOTROPY, &maxAniso);
    gpu_->maxAnisotropy = std::clamp(maxAniso, 1.0f, kMaxAnisotropy);
  }
  gpu_->driverMaxAnisotropy = gpu_->maxAnisotropy;
  stats_.maxAnisotropy = gpu_->maxAnisotropy;
  // The environment's cube maps are filtered across their faces' edges (raster/environment_light.h).
  glEnable(GL_TEXTURE_CUBE_MAP_SEAMLESS);
}

void Renderer::setImageBasedLight(bool on) {
  cubesDirty_ |= on != imageBasedLight_;  // the cube reflectors' captures are lit by it
  probeDirty_ |= on != imageBasedLight_;
  imageBasedLight_ = on;
}

void Renderer::setRoomProbe(bool on) {
  probeDirty_ |= on != roomProbe_;
  roomProbe_ = on;
}

void Renderer::setEnvironmentSettings(const EnvironmentSettings& settings) {
  if (environment_ && environment_->settings() == settings) return;
  environment_ = std::make_unique<EnvironmentLight>(compiler(), settings);  // checks the settings
  environmentSettings_ = settings;
  environmentDirty_ = true;
}

void Renderer::setMaxAnisotropy(float samples) {
  if (!(samples >= 1.0f)) throw std::invalid_argument("anisotropic filtering takes at least 1 sample");
  gpu_->maxAnisotropy = std::min(samples, gpu_->driverMaxAnisotropy);
  stats_.maxAnisotropy = gpu_->maxAnisotropy;
  if (gpu_->driverMaxAnisotropy <= 1.0f) return;
  for (const auto& [key, sampler] : gpu_->samplers) {
    if (samplerMipmapped(key)) glSamplerParameterf(sampler, GL_TEXTURE_MAX_ANISOTROPY, gpu_->maxAnisotropy);
  }
}

// The GL sampler object of `ref`'s glTF sampler, made on first use: its wrap modes and filters, and where
// the minification filter is mipmapped the anisotropic filtering setMaxAnisotropy gives.
unsigned Renderer::samplerFor(const rdb::RasterTextureRef& ref) {
  const uint32_t key = samplerKey(ref);
  GLuint& sampler = gpu_->samplers[key];
  if (sampler) return sampler;
  glCreateSamplers(1, &sampler);
  stats_.samplerObjects = int(gpu_->samplers.size());
  glSamplerParameteri(sampler, GL_TEXTURE_WRAP_S, glWrap(ref.wrapS));
  glSamplerParameteri(sampler, GL_TEXTURE_WRAP_T, glWrap(ref.wrapT));
  glSamplerParameteri(sampler, GL_TEXTURE_MIN_FILTER, glMinFilter(ref.minFilter));
  glSamplerParameteri(sampler, GL_TEXTURE_MAG_FILTER,
                      ref.magFilter == rdb::RasterMagFilter::kNearest ? GL_NEAREST : GL_LINEAR);
  if (gpu_->driverMaxAnisotropy > 1.0f && samplerMipmapped(key)) {
    glSamplerParameterf(sampler, GL_TEXTURE_MAX_ANISOTROPY, gpu_->maxAnisotropy);
  }
  return sampler;
}

Renderer::~Renderer() = default;

SunShadows::Compile Renderer::compiler() {
  return [this](const std::string& name, const std::string& defines,
                std::initializer_list<std::pair<unsigned, const char*>> stages) {
    return compileProgram(name, defines, stages);
  };
}

unsigned Renderer::compileProgram(const std::string& name, const std::string& defines,
                                  std::initializer_list<std::pair<unsigned, const char*>> stages) {
  const unsigned p = linkGlProgram(name, defines, stages);
  stats_.programs.push_back(name);
  return p;
}

// The scene program of a variant (VariantBit), compiled on first use, named by its tags in bit order.
const Renderer::SceneProgram& Renderer::sceneProgram(uint32_t variant) {
  SceneProgram& sp = gpu_->scene[variant];
  if (sp.program) return sp;
  std::string name = "scene";
  std::string defines = "#define FLY_CORNER_GAIN " + std::to_string(rdb::kCornerGain) + "\n" +
                        "#define FLY_GONIO_GAMMA_STEPS " + std::to_string(rdb::kRasterGonioGammaSteps) +
                        "\n" + "#define FLY_GONIO_C_STEPS " + std::to_string(rdb::kRasterGonioCSteps) + "\n" +
                        "#define FLY_MAX_NEAR_LIGHTS " + std::to_string(kMaxNearLights) + "\n" +
                        "#define FLY_ALBEDO_STEPS " + std::to_string(rdb::kRasterAlbedoSteps) + "\n" +
                        "#define FLY_BRDF_BINDING 4\n#define FLY_BRDF_TABLE_UNIT 10\n";
  const struct {
    uint32_t bit;
    const char* tag;
    const char* define;
  } kVariants[] = {{kVariantLightMap, "lightmap", "FLY_LIGHT_MAP"},
                   {kVariantPhong, "phong", "FLY_PHONG"},
                   {kVariantSun, "sun", "FLY_SUN"},
                   {kVariantTwoSided, "twosided", "FLY_TWO_SIDED"},
                   {kVariantGonio, "gonio", "FLY_GONIO"},
                   {kVariantLightTexture, "lighttexture", "FLY_LIGHT_TEXTURE"},
                   {kVariantGlass, "glass", "FLY_GLASS"},
                   {kVariantPerFragment, "perfragment", "FLY_PER_FRAGMENT"},
                   {kVariantTextures, "textures", "FLY_TEXTURES"},
                   {kVariantNormalMap, "normalmap", "FLY_NORMAL_MAP"},
                   {kVariantUv1, "uv1", "FLY_UV1"},
                   {kVariantVertexColor, "vertexcolor", "FLY_VERTEX_COLOR"},
                   {kVariantAlphaMask, "mask", "FLY_ALPHA_MASK"},
                   {kVariantBlendPass, "blend", "FLY_BLEND_PASS"},
                   {kVariantSunDirect, "sundirect", "FLY_SUN_DIRECT"},
                   {kVariantSunGlass, "sunglass", "FLY_SUN_GLASS"},
                   {kVariantMeasured, "measured", "FLY_MEASURED"},
                   {kVariantNearDeferred, "neardeferred", "FLY_NEAR_DEFERRED"},
                   {kVariantPlanarReflection, "planarreflection", "FLY_PLANAR_REFLECTION"},
                   {kVariantIbl, "ibl", "FLY_IBL"},
                   {kVariantCubeReflection, "cubereflection", "FLY_CUBE_REFLECTION"},
                   {kVariantAmbientOcclusion, "ssao", "FLY_SSAO"},
                   {kVariantFrosted, "frosted", "FLY_FROSTED"},
                   {kVariantReflectionFog, "fog", "FLY_REFLECTION_FOG"},
                   {kVariantAnisotropy, "anisotropy", "FLY_ANISOTROPY"},
                   {kVariantDiffuseByAngle, "diffusebyangle", "FLY_DIFFUSE_BY_ANGLE"},
                   {kVariantGlossinessTexture, "glossinesstexture", "FLY_GLOSSINESS_TEXTURE"},
                   {kVariantRoomProbe, "roomprobe", "FLY_ROOM_PROBE"},
                   {kVariantMetalnessTexture, "metalnesstexture", "FLY_METALNESS_TEXTURE"}};
  for (const auto& v : kVariants) {
    if (!(variant & v.bit)) continue;
    name += std::string("+") + v.tag;
    defines += std::string("#define ") + v.define + "\n";
  }
  const bool perFragment = variant & kVariantPerFragment;
  // The anisotropy, glossiness, transmission and metalness slots' units lie above the 16 that OpenGL 4.5
  // guarantees.
  if (perFragment && (variant & kVariantTextures)) {
    const char* what = (variant & kVariantMetalnessTexture)    ? "metalness"
                       : (variant & kVariantGlass)             ? "transmission"
                       : (variant & kVariantGlossinessTexture) ? "glossiness"
                       : (variant & kVariantAnisotropy)        ? "anisotropy"
                                                               : nullptr;
    const GLuint highest = (variant & kVariantMetalnessTexture)    ? kTextureSlotUnits[7]
                           : (variant & kVariantGlass)             ? kTextureSlotUnits[6]
                           : (variant & kVariantGlossinessTexture) ? kTextureSlotUnits[5]
                                                                   : kTextureSlotUnits[4];
    GLint units = 0;
    if (what) glGetIntegerv(GL_MAX_TEXTURE_IMAGE_UNITS, &units);
    if (what && units <= GLint(highest)) {
      throw std::runtime_error("the OpenGL driver has " + std::to_string(units) + " fragment texture units; " +
                               what + " textures need " + std::to_string(highest + 1));
    }
  }
  const std::string vertex = std::string(shaders::kSunGlassLookup) + shaders::kAoAmbientCommon +
                             shaders::kGlassPane + shaders::kSceneCommon +
                             (perFragment ? shaders::kSurfaceVertex : shaders::kSceneVertex);
  const std::string fragment =
      std::string(shaders::kLuminanceEncoding) + shaders::kSunGlassLookup + shaders::kAoAmbientCommon +
      shaders::kAoAmbientLookup +
      (perFragment
           ? std::string(shaders::kGlassPane) + shaders::kSceneCommon +
                 ((variant & kVariantMeasured) ? std::string(shaders::kMeasuredBrdf) + shaders::kNearLamp : "") +
                 shaders::kLightTextureLookup + ((variant & kVariantPlanarReflection) ? shaders::kMirrorBlurUpsample : "") +
                 ((variant & kVariantGlass) ? shaders::kGlassBehind : "") + shaders::kSurfaceFragment
           : ((variant & (kVariantIbl | kVariantDiffuseByAngle))
                  ? std::string(shaders::kGlassPane) + shaders::kSceneCommon
                  : std::string()) +
                 shaders::kLightTextureLookup + ((variant & kVariantGlass) ? shaders::kGlassBehind : "") +
                 shaders::kSceneFragment);
  const GLuint p = compileProgram(
      name, defines, {{GL_VERTEX_SHADER, vertex.c_str()}, {GL_FRAGMENT_SHADER, fragment.c_str()}});
  auto loc = [&](const char* n) { return glGetUniformLocation(p, n); };
  sp.clipFromWorld = loc("uClipFromWorld");
  sp.eye = loc("uEyeM");
  sp.viewDir = loc("uViewDirWorld");
  sp.orthographic = loc("uOrthographic");
  sp.lightCount = loc("uLightCount");
  sp.ambientUp = loc("uAmbientUpLux");
  sp.ambientDown = loc("uAmbientDownLux");
  sp.displayWhite = loc("uDisplayWhiteCdM2");
  sp.sunDir = loc("uSunDirWorld");
  sp.sunNormalLux = loc("uSunNormalLux");
  sp.glassPass = loc("uGlassPass");
  sp.textureSlots = loc("uTextureSlots");
  sp.uvRows = loc("uUvRows");
  sp.material = loc("uMaterial");
  sp.sunGlassFromWorld = loc("uSunGlassFromWorld");
  sp.sunGlassBias = loc("uSunGlassBiasM");
  sp.ballLayer = loc("uBallLayer");
  sp.ballFromWorld = loc("uBallFromWorld");
  sp.nearLights = loc("uNearLights");
  sp.nearLightCount = loc("uNearLightCount");
  sp.reflector = loc("uReflector");
  sp.sunInReflection = loc("uSunInReflection");
  sp.mirrorReflection = loc("uMirrorReflection");
  sp.mirrorF0 = loc("uMirrorF0");
  sp.radianceTopLevel = loc("uRadianceTopLevel");
  sp.worldFromClip = loc("uWorldFromClip");
  sp.blurView = loc("uBlurView");
  sp.mirrorGlossy = loc("uMirrorGlossy");
  sp.mirrorCoarse = loc("uMirrorCoarse");
  sp.mirrorScale = loc("uMirrorScale");
  sp.mirrorFine = loc("uMirrorFine");
  sp.mirrorTapCount = loc("uMirrorTapCount");
  sp.mirrorTaps = loc("uMirrorTaps");
  sp.mirrorWorldFromClip = loc("uMirrorWorldFromClip");
  sp.cubeReflector = loc("uCubeReflector");
  sp.fogDistance = loc("uFogDistanceM");
  sp.fogColor = loc("uFogColor");
  sp.probeCentre = loc("uProbeCentreM");
  sp.irradianceAmbient = loc("uIrradianceAmbient");
  sp.probeBoxMin = loc("uProbeBoxMinM");
  sp.probeBoxMax = loc("uProbeBoxMaxM");
  sp.program = p;
  return sp;
}

void Renderer::upload(const rdb::RasterRdb& rdb) {
  rdb_ = &rdb;
  cubesDirty_ = true;
  probeDirty_ = true;
  reflectorTangents_.clear();
  uploadGeometry();
  uploadTextures();
  uploadMaterials();
  uploadLights();
  uploadSky();
}

void Renderer::setBallSettings(const BallSettings& settings) {
  if (!balls_) balls_ = std::make_unique<BallTextures>(compiler());
  balls_->setSettings(settings);
}

std::vector<float> Renderer::ballLayer(uint32_t layer) const {
  if (!balls_ || stats_.ballsMade == 0) throw std::logic_error("Renderer::ballLayer before a ball was made");
  return balls_->readLayer(layer);
}

void Renderer::update(const rdb::RasterRdb& rdb, const rdb::RasterRdbChanges& changes) {
  rdb_ = &rdb;
  cubesDirty_ |= changes.any();
  probeDirty_ |= changes.any();
  if (changes.any()) reflectorTangents_.clear();
  if (changes.geometry) {
    upload(rdb);
    return;
  }
  if (changes.materials) {
    uploadMaterials();
  } else {
    for (uint32_t i : changes.materialBlocks) {
      const GpuMaterial m = gpuMaterial(rdb.materials.at(i));
      glNamedBufferSubData(gpu_->materials, GLintptr(i * sizeof(GpuMaterial)), sizeof m, &m);
      const char casts = castsSunShadows(rdb.materials[i]) ? 1 : 0;
      shadowGeometryDirty_ |= casts != materialCasts_.at(i);
      materialCasts_[i] = casts;
      sunGlassDirty_ = true;  // its T, or whether it is glass, may have changed
      for (SurfaceDraw& d : gpu_->surfaceDraws) {
        // Its samplers may have changed.
        if (d.material == i)
          assignSamplers(d, rdb, [this](const rdb::RasterTextureRef& ref) { return samplerFor(ref); });
      }
      ++stats_.materialBlockUploads;
    }
    gpu_->environmentReflected = reflectsEnvironment(rdb);
  }
  if (changes.lights) uploadLights();
  if (changes.sky) uploadSky();
  // Ambient levels and cameras are uniforms, read at every render.
}

void Renderer::uploadGeometry() {
  const rdb::RasterRdb& r = *rdb_;
  storeBuffer(gpu_->positions, r.positionsM);
  storeBuffer(gpu_->normals, r.normals);
  storeBuffer(gpu_->corners, r.cornerFactor);
  const GLuint vao = gpu_->vao;
  auto attrib = [&](GLuint index, GLuint buffer, GLint components, GLsizei stride) {
    glVertexArrayVertexBuffer(vao, index, buffer, 0, stride);
    glVertexArrayAttribFormat(vao, index, components, GL_FLOAT, GL_FALSE, 0);
    glVertexArrayAttribBinding(vao, index, index);
    glEnableVertexArrayAttrib(vao, index);
  };
  attrib(0, gpu_->positions, 3, sizeof(vec3));
  attrib(1, gpu_->normals, 3, sizeof(vec3));
  attrib(2, gpu_->corners, 1, sizeof(float));
  if (!r.frontLux.empty()) {
    storeBuffer(gpu_->frontLux, r.frontLux);
    attrib(3, gpu_->frontLux, 3, sizeof(vec3));
  } else {
    glDisableVertexArrayAttrib(vao, 3);
  }
  if (!r.backLux.empty()) {
    storeBuffer(gpu_->backLux, r.backLux);
    attrib(4, gpu_->backLux, 3, sizeof(vec3));
  } else {
    glDisableVertexArrayAttrib(vao, 4);
  }
  // Per-fragment surfaces' attributes, where the scene has them.
  auto optional = [&](GLuint index, GLuint& buffer, const auto& values, GLint components) {
    if (values.empty()) {
      glDisableVertexArrayAttrib(vao, index);
      return;
    }
    storeBuffer(buffer, values);
    attrib(index, buffer, components, GLsizei(components * sizeof(float)));
  };
  optional(12, gpu_->frontSunLux, r.frontSunDirectLux, 3);
  optional(13, gpu_->backSunLux, r.backSunDirectLux, 3);
  optional(8, gpu_->uv0, r.uv0, 2);
  optional(9, gpu_->uv1, r.uv1, 2);
  optional(10, gpu_->colors, r.colors, 4);
  optional(11, gpu_->tangents, r.tangents, 4);
  // The element buffer is uploadDraws': the meshes' indices in draw order.
  gpu_->indexCount = GLsizei(r.indices.size());
  gpu_->everyMeshLightMapped =
      std::all_of(r.meshes.begin(), r.meshes.end(), [](const rdb::RasterMesh& m) { return m.hasLightMap; });
  uploadLightTextures();
  shadowGeometryDirty_ = true;
  sunGlassDirty_ = true;
  ++stats_.geometryUploads;
}

// The light textures of rdb::RasterRdb::lightTextures, front then (when baked) back of each, are "slots",
// shelf-packed in order into the layers of one GL_TEXTURE_2D_ARRAY as large as the largest texture (one draw
// samples them all). Per slot a GpuLightRect; per vertex aLightMapUv and aLightSlot (kSceneVertex).
void Renderer::uploadLightTextures() {
  const rdb::RasterRdb& r = *rdb_;
  glDeleteTextures(1, &gpu_->lightTextures);
  gpu_->lightTextures = 0;
  if (r.lightTextures.empty()) {
    glDisableVertexArrayAttrib(gpu_->vao, 6);
    glDisableVertexArrayAttrib(gpu_->vao, 7);
    return;
  }
  struct Slot {
    const std::vector<Rgb>* texels;
    uint32_t width, height;
  };
  std::vector<Slot> slots;
  std::vector<uint32_t> firstSlot;  // per light texture
  uint32_t layerW = 1, layerH = 1;
  for (const rdb::RasterLightTexture& t : r.lightTextures) {
    firstSlot.push_back(uint32_t(slots.size()));
    slots.push_back({&t.frontLux, t.width, t.height});
    if (!t.backLux.empty()) slots.push_back({&t.backLux, t.width, t.height});
    // The sun-direct texels follow in the same order (kSceneFragment, flyLightTexel).
    if (!t.frontSunDirectLux.empty()) slots.push_back({&t.frontSunDirectLux, t.width, t.height});
    if (!t.backSunDirectLux.empty()) slots.push_back({&t.backSunDirectLux, t.width, t.height});
    layerW = std::max(layerW, t.width);
    layerH = std::max(layerH, t.height);
  }
  GLint maxSizePx = 0, maxLayers = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSizePx);
  glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &maxLayers);
  if (layerW > uint32_t(maxSizePx) || layerH > uint32_t(maxSizePx)) {
    throw std::runtime_error("a light texture of " + std::to_string(layerW) + "×" + std::to_string(layerH) +
                             " texels exceeds the OpenGL driver's limit of " + std::to_string(maxSizePx) +
                             " per side: bake with a lower light-texture density");
  }
  // Shelves: left to right, a new shelf below the tallest so far when a row is full, a new layer when the
  // layer is full. Every slot fits into an empty layer.
  std::vector<GpuLightRect> rects;
  uint32_t x = 0, y = 0, shelfH = 0, layer = 0;
  for (const Slot& s : slots) {
    if (x + s.width > layerW) {
      x = 0;
      y += shelfH;
      shelfH = 0;
    }
    if (y + s.height > layerH) {
      x = y = shelfH = 0;
      ++layer;
    }
    rects.push_back({vec4(float(x), float(y), float(s.width), float(s.height)),
                     vec4(float(layer), 1.0f / float(layerW), 1.0f / float(layerH), 0.0f)});
    x += s.width;
    shelfH = std::max(shelfH, s.height);
  }
  if (layer + 1 > uint32_t(maxLayers)) {
    throw std::runtime_error("the light textures need " + std::to_string(layer + 1) +
                             " layers, more than the OpenGL driver's " + std::to_string(maxLayers));
  }
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &gpu_->lightTextures);
  glTextureStorage3D(gpu_->lightTextures, 1, GL_RGBA32F, GLsizei(layerW), GLsizei(layerH),
                     GLsizei(layer + 1));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  for (size_t k = 0; k < slots.size(); ++k) {
    // Row 0 (v ∈ [0, 1/height)) goes first, at t = 0: the shader samples at t = v.
    glTextureSubImage3D(gpu_->lightTextures, 0, GLint(rects[k].rect.x), GLint(rects[k].rect.y),
                        GLint(rects[k].layer.x), GLsizei(slots[k].width), GLsizei(slots[k].height), 1, GL_RGB,
                        GL_FLOAT, slots[k].texels->data());
  }
  glTextureParameteri(gpu_->lightTextures, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(gpu_->lightTextures, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(gpu_->lightTextures, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(gpu_->lightTextures, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  storeBuffer(gpu_->lightRects, rects);

  std::vector<uint32_t> vertexSlots(r.positionsM.size(), kNoLightSlot);
  for (const rdb::RasterMesh& m : r.meshes) {
    if (m.lightTexture == rdb::RasterMesh::kNoLightTexture) continue;
    const bool back = !r.lightTextures[m.lightTexture].backLux.empty();
    // Vertices of triangles outside the atlas (rdb::inLightTexture) keep their vertex light map.
    for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) {
      if (rdb::inLightTexture(r.lightMapUv[v])) vertexSlots[v] = firstSlot[m.lightTexture] | (back ? kLightSlotHasBack : 0u);
    }
  }
  storeBuffer(gpu_->lightMapUv, r.lightMapUv);
  storeBuffer(gpu_->lightSlots, vertexSlots);
  const GLuint vao = gpu_->vao;
  glVertexArrayVertexBuffer(vao, 6, gpu_->lightMapUv, 0, sizeof(vec2));
  glVertexArrayAttribFormat(vao, 6, 2, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(vao, 6, 6);
  glEnableVertexArrayAttrib(vao, 6);
  glVertexArrayVertexBuffer(vao, 7, gpu_->lightSlots, 0, sizeof(uint32_t));
  glVertexArrayAttribIFormat(vao, 7, 1, GL_UNSIGNED_INT, 0);
  glVertexArrayAttribBinding(vao, 7, 7);
  glEnableVertexArrayAttrib(vao, 7);
}

// The material table and each vertex's aSurface (its mesh's material index and flags), which an assignment
// changes along with the table.
void Renderer::uploadMaterials() {
  const rdb::RasterRdb& r = *rdb_;
  std::vector<GpuMaterial> m;
  m.reserve(r.materials.size());
  for (const rdb::RasterMaterial& x : r.materials) m.push_back(gpuMaterial(x));
  storeBuffer(gpu_->materials, m, GL_DYNAMIC_STORAGE_BIT);  // update() rewrites single blocks
  gpu_->environmentReflected = reflectsEnvironment(r);
  std::vector<uint32_t> surfaces(r.positionsM.size(), 0u);
  for (const rdb::RasterMesh& mesh : r.meshes) {
    std::fill_n(surfaces.begin() + std::ptrdiff_t(mesh.firstVertex), mesh.vertexCount, surfaceBits(mesh));
  }
  storeBuffer(gpu_->surfaces, surfaces);
  glVertexArrayVertexBuffer(gpu_->vao, 5, gpu_->surfaces, 0, sizeof(uint32_t));
  glVertexArrayAttribIFormat(gpu_->vao, 5, 1, GL_UNSIGNED_INT, 0);
  glVertexArrayAttribBinding(gpu_->vao, 5, 5);
  glEnableVertexArrayAttrib(gpu_->vao, 5);
  uploadDraws();
  // Which triangles cast the sun's shadows (glass and blended surfaces do not).
  std::vector<char> casts;
  for (const rdb::RasterMaterial& x : r.materials) casts.push_back(castsSunShadows(x) ? 1 : 0);
  shadowGeometryDirty_ |= casts != materialCasts_;
  materialCasts_ = std::move(casts);
  sunGlassDirty_ = true;
  ballBrdfsDirty_ = true;
  ++stats_.materialTableUploads;
}

// The element buffer in draw order: the per-vertex meshes' indices first (one draw of their visible chunks,
// each mesh's triangles in the chunks' spatial order: raster/draw_chunks.h), then for the surfaces drawn per
// fragment (rdb::RasterRdb::shadedPerFragment) per material its opaque or cut-out meshes (one draw each: a draw
// binds one material's textures), then each blended mesh.
void Renderer::uploadDraws() {
  const rdb::RasterRdb& r = *rdb_;
  gpu_->surfaceDraws.clear();
  gpu_->perVertexIndexCount = gpu_->indexCount;
  gpu_->perVertexChunks.clear();
  std::vector<uint32_t> ordered;
  ordered.reserve(r.indices.size());
  auto append = [&](const rdb::RasterMesh& m) {
    ordered.insert(ordered.end(), r.indices.begin() + std::ptrdiff_t(m.firstIndex),
                   r.indices.begin() + std::ptrdiff_t(m.firstIndex + m.indexCount));
  };
  // Whether a mesh's back faces are drawn: two-sided meshes' and glass's (either face of a pane passes light,
  // as in the baker); the others' are culled (glTF's doubleSided: false).
  auto bothSides = [&](const rdb::RasterMesh& m) {
    return m.twoSided || maxComponent(r.materials[m.material].transmission) > 0.0f;
  };
  // The one-sided meshes first, then the others (drawVisibleChunks culls the first range's backs).
  for (const bool twoSided : {false, true}) {
    for (const rdb::RasterMesh& m : r.meshes) {
      if (r.shadedPerFragment(m) || bothSides(m) != twoSided) continue;
      const uint32_t first = uint32_t(ordered.size());
      append(m);
      appendDrawChunks(ordered, first, m.indexCount, r.positionsM, gpu_->perVertexChunks);
    }
    if (!twoSided) gpu_->perVertexOneSidedCount = GLsizei(ordered.size());
  }
  gpu_->perVertexIndexCount = GLsizei(ordered.size());
  // Opaque, then cut-out materials (a program with discard after those without), each material's meshes in
  // one draw.
  for (const rdb::RasterAlphaMode mode : {rdb::RasterAlphaMode::kOpaque, rdb::RasterAlphaMode::kMask}) {
    for (uint32_t material = 0; material < r.materials.size(); ++material) {
      if (r.materials[material].alphaMode != mode) continue;
      // The material's meshes that are no reflector in one draw, then one draw per planar reflector and one
      // per cube reflector, in the order of their first mesh.
      // (planar reflector, cube reflector, two-sided)
      std::vector<std::tuple<uint32_t, uint32_t, bool>> groups;
      for (const rdb::RasterMesh& m : r.meshes) {
        const std::tuple<uint32_t, uint32_t, bool> g(m.planarReflector, m.cubeReflector, bothSides(m));
        if (m.material == material && r.shadedPerFragment(m) && std::find(groups.begin(), groups.end(), g) == groups.end())
          groups.push_back(g);
      }
      auto plain = [](const auto& g) {
        return std::get<0>(g) == rdb::RasterTextureRef::kNone && std::get<1>(g) == rdb::RasterTextureRef::kNone;
      };
      std::stable_sort(groups.begin(), groups.end(), [&](const auto& a, const auto& b) { return plain(a) && !plain(b); });
      for (const auto& [reflector, cube, twoSided] : groups) {
        SurfaceDraw d;
        d.firstIndex = ordered.size();
        d.material = material;
        d.mask = mode == rdb::RasterAlphaMode::kMask;
        d.twoSided = twoSided;
        d.glass = maxComponent(r.materials[material].transmission) > 0.0f;
        d.reflector = reflector;
        d.cubeReflector = cube;
        for (const rdb::RasterMesh& m : r.meshes) {
          if (m.material == material && m.planarReflector == reflector && m.cubeReflector == cube &&
              bothSides(m) == twoSided && r.shadedPerFragment(m))
            append(m);
        }
        d.indexCount = GLsizei(ordered.size() - d.firstIndex);
        if (d.indexCount > 0) gpu_->surfaceDraws.push_back(d);
      }
    }
  }
  for (const rdb::RasterMesh& m : r.meshes) {
    if (r.materials[m.material].alphaMode != rdb::RasterAlphaMode::kBlend || m.indexCount == 0) continue;
    SurfaceDraw d;
    d.firstIndex = ordered.size();
    d.material = m.material;
    d.blend = true;
    d.twoSided = bothSides(m);
    Bounds3 b;
    for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) b.extend(r.positionsM[v]);
    d.centreM = 0.5f * (b.min + b.max);
    append(m);
    d.indexCount = GLsizei(m.indexCount);
    gpu_->surfaceDraws.push_back(d);
  }
  storeBuffer(gpu_->drawIndices, ordered);
  glVertexArrayElementBuffer(gpu_->vao, gpu_->drawIndices);
  for (SurfaceDraw& d : gpu_->surfaceDraws) {
    assignSamplers(d, r, [this](const rdb::RasterTextureRef& ref) { return samplerFor(ref); });
  }
}

// Each rdb::RasterTexture as an immutable GL texture with a full mip chain (glGenerateTextureMipmap); how it
// is filtered and wrapped is the sampler object of the material's use of it (samplerFor).
void Renderer::uploadTextures() {
  const rdb::RasterRdb& r = *rdb_;
  glDeleteTextures(GLsizei(gpu_->textures.size()), gpu_->textures.data());
  gpu_->textures.assign(r.textures.size(), 0);
  GLint maxSizePx = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxSizePx);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  for (size_t i = 0; i < r.textures.size(); ++i) {
    const rdb::RasterTexture& t = r.textures[i];
    if (t.width > uint32_t(maxSizePx) || t.height > uint32_t(maxSizePx)) {
      throw std::runtime_error("a texture of " + std::to_string(t.width) + "×" + std::to_string(t.height) +
                               " texels exceeds the OpenGL driver's limit of " + std::to_string(maxSizePx) +
                               " per side: scale the image down");
    }
    GLuint& tex = gpu_->textures[i];
    glCreateTextures(GL_TEXTURE_2D, 1, &tex);
    const GLsizei levels = GLsizei(std::floor(std::log2(double(std::max(t.width, t.height))))) + 1;
    glTextureStorage2D(tex, levels, t.srgb ? GL_SRGB8_ALPHA8 : GL_RGBA8, GLsizei(t.width), GLsizei(t.height));
    glTextureSubImage2D(tex, 0, 0, 0, GLsizei(t.width), GLsizei(t.height), GL_RGBA, GL_UNSIGNED_BYTE,
                        t.rgba8.data());
    glGenerateTextureMipmap(tex);
  }
  stats_.textureUploads += int(r.textures.size());
}

void Renderer::uploadLights() {
  std::vector<GpuLight> lights;
  for (const rdb::RasterLight& l : rdb_->lights) {
    GpuLight g;
    g.positionType = vec4(l.positionM, float(uint32_t(l.type)));
    g.directionRange = vec4(l.directionWorld, std::isfinite(l.rangeM) ? l.rangeM : 0.0f);
    g.cAxisOffset = vec4(l.cAxisWorld, float(l.goniometricOffset));
    g.intensity = vec4(l.intensity, 0.0f);
    g.cone = vec4(l.cosInner, l.cosOuter, 0.0f, 0.0f);
    lights.push_back(g);
  }
  storeBuffer(gpu_->lights, lights);
  storeBuffer(gpu_->gonio, rdb_->goniometricCd);
  ++stats_.lightUploads;
}

void Renderer::uploadSky() {
  environmentDirty_ = true;
  if (gpu_->skyTexture) {
    glDeleteTextures(1, &gpu_->skyTexture);
    gpu_->skyTexture = 0;
  }
  if (!rdb_->sky || rdb_->sky->width == 0 || rdb_->sky->height == 0) return;
  const rdb::RasterSky& s = *rdb_->sky;
  glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->skyTexture);
  glTextureStorage2D(gpu_->skyTexture, 1, GL_RGB32F, GLsizei(s.width), GLsizei(s.height));
  glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
  glTextureSubImage2D(gpu_->skyTexture, 0, 0, 0, GLsizei(s.width), GLsizei(s.height), GL_RGB, GL_FLOAT,
                      s.radianceCdM2.data());
  glTextureParameteri(gpu_->skyTexture, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(gpu_->skyTexture, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(gpu_->skyTexture, GL_TEXTURE_WRAP_S, GL_REPEAT);         // φ wraps around
  glTextureParameteri(gpu_->skyTexture, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);  // θ ends at the poles
  ++stats_.skyUploads;
}

void Renderer::decodeBlurred(unsigned source, unsigned& target) {
  Gpu& g = *gpu_;
  if (!target) {
    const uint32_t levels = uint32_t(std::floor(std::log2(double(std::max(width_, height_))))) + 1;
    glCreateTextures(GL_TEXTURE_2D, 1, &target);
    glTextureStorage2D(target, GLsizei(levels), GL_RGBA32F, GLsizei(width_), GLsizei(height_));
    glTextureParameteri(target, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTextureParameteri(target, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(target, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(target, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  }
  if (!g.behindDecode) {
    g.behindDecode = compileProgram("behind-decode", shaders::kLuminanceEncoding,
                                    {{GL_COMPUTE_SHADER, shaders::kBehindDecode}});
  }
  glUseProgram(g.behindDecode);
  glBindImageTexture(0, source, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  glBindImageTexture(1, target, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatchPerPixel(width_, height_);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glGenerateTextureMipmap(target);
}

void Renderer::copyDepth(unsigned& target, int x, int y, int width, int height) {
  if (!target) {
    glCreateTextures(GL_TEXTURE_2D, 1, &target);
    glTextureStorage2D(target, 1, GL_DEPTH24_STENCIL8, GLsizei(width_), GLsizei(height_));
    glTextureParameteri(target, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
    glTextureParameteri(target, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(target, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glCopyImageSubData(gpu_->depth, GL_RENDERBUFFER, 0, x, y, 0, target, GL_TEXTURE_2D, 0, x, y, 0, width, height, 1);
}

void Renderer::prepareFrostedGlass() {
  Gpu& g = *gpu_;
  if (!g.frostTable) {
    g.frostTable = makeSplitSumTable(compiler(), kSkyEnvironmentSettings.tablePx, kSkyEnvironmentSettings.tableSamples);
  }
  decodeBlurred(g.behindColor, g.behindBlurred);
  copyDepth(g.behindDepth, 0, 0, int(width_), int(height_));
  glBindTextureUnit(3, g.behindBlurred);
  glBindTextureUnit(1, g.behindDepth);
  glBindTextureUnit(14, g.frostTable);
}

void Renderer::resize(uint32_t widthPx, uint32_t heightPx) {
  if (widthPx == width_ && heightPx == height_ && gpu_->floatFbo) return;
  glDeleteFramebuffers(1, &gpu_->floatFbo);
  glDeleteFramebuffers(1, &gpu_->srgbFbo);
  glDeleteTextures(1, &gpu_->floatColor);
  glDeleteTextures(1, &gpu_->srgbColor);
  glDeleteTextures(1, &gpu_->behindColor);
  gpu_->behindColor = 0;
  glDeleteTextures(1, &gpu_->behindBlurred);
  gpu_->behindBlurred = 0;
  glDeleteTextures(1, &gpu_->behindDepth);
  gpu_->behindDepth = 0;
  const GLuint nearTextures[] = {gpu_->nearData, gpu_->nearLight};
  glDeleteTextures(2, nearTextures);
  gpu_->nearData = gpu_->nearLight = 0;
  glDeleteTextures(GLsizei(gpu_->reflectionColor.size()), gpu_->reflectionColor.data());
  gpu_->reflectionColor.clear();
  glDeleteTextures(GLsizei(gpu_->reflectionDepth.size()), gpu_->reflectionDepth.data());
  gpu_->reflectionDepth.clear();
  glDeleteTextures(1, &gpu_->cubeFaceDepth);
  gpu_->cubeFaceDepth = 0;
  glDeleteTextures(1, &gpu_->blendColor);
  glDeleteFramebuffers(1, &gpu_->blendFbo);
  gpu_->blendColor = gpu_->blendFbo = 0;
  glDeleteRenderbuffers(1, &gpu_->depth);
  const GLsizei w = GLsizei(widthPx), h = GLsizei(heightPx);
  glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->floatColor);
  glTextureStorage2D(gpu_->floatColor, 1, GL_RG32UI, w, h);  // shaders::kLuminanceEncoding
  glCreateRenderbuffers(1, &gpu_->depth);
  glNamedRenderbufferStorage(gpu_->depth, GL_DEPTH24_STENCIL8, w, h);
  glCreateFramebuffers(1, &gpu_->floatFbo);
  glNamedFramebufferTexture(gpu_->floatFbo, GL_COLOR_ATTACHMENT0, gpu_->floatColor, 0);
  glNamedFramebufferRenderbuffer(gpu_->floatFbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER, gpu_->depth);
  glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->srgbColor);
  glTextureStorage2D(gpu_->srgbColor, 1, GL_RGBA8, w, h);
  glCreateFramebuffers(1, &gpu_->srgbFbo);
  glNamedFramebufferTexture(gpu_->srgbFbo, GL_COLOR_ATTACHMENT0, gpu_->srgbColor, 0);
  for (GLuint fbo : {gpu_->floatFbo, gpu_->srgbFbo}) {
    if (glCheckNamedFramebufferStatus(fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("the OpenGL driver cannot render into a " + std::to_string(widthPx) + "×" +
                               std::to_string(heightPx) + " RG32UI framebuffer");
    }
  }
  width_ = widthPx;
  height_ = heightPx;
}

void Renderer::render(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx) {
  if (!rdb_) throw std::logic_error("Renderer::render before upload");
  const GLint maxSize = std::min(16384, gpu_->maxImageSizePx);
  if (widthPx < 1 || heightPx < 1 || widthPx > uint32_t(maxSize) || heightPx > uint32_t(maxSize)) {
    throw std::invalid_argument("image size " + std::to_string(widthPx) + "×" + std::to_string(heightPx) +
                                " is out of range (1 to " + std::to_string(maxSize) + " pixels per side)");
  }
  const rdb::RasterRdb& r = *rdb_;
  const rdb::RasterVariants& v = r.variants;
  if ((mode == RenderMode::kLightMap && !v.lightMap) || (mode == RenderMode::kSunlight && !v.sky)) {
    throw std::invalid_argument(std::string("the scene does not support ") + renderModeName(mode) +
                                " mode (" +
                                (mode == RenderMode::kLightMap ? "it has no light maps: bake it first"
                                                               : "it has neither sky nor sun") +
                                ")");
  }
  // The room probe (raster/room_probe.h): light-map and sunlight modes of a scene with a sky whose materials
  // reflect an environment; the image-based light it needs is built in both modes.
  const bool probe = roomProbe_ && imageBasedLight_ && gpu_->skyTexture && mode != RenderMode::kSimple &&
                     gpu_->environmentReflected;
  if ((mode == RenderMode::kSunlight || probe) && imageBasedLight_ && gpu_->skyTexture) {
    if (!environment_) environment_ = std::make_unique<EnvironmentLight>(compiler(), environmentSettings_);
    if (environmentDirty_) {
      environment_->build(gpu_->skyTexture);
      environmentDirty_ = false;
      ++stats_.environmentBuilds;
    }
  }
  if (v.cubeReflectors) captureCubeReflectors(mode);
  probeActive_ = probe;
  if (probe) captureRoomProbe(vec3(view.worldFromCamera[3]), mode);
  resize(widthPx, heightPx);
  if (v.planarReflectors) drawReflections(view, mode, widthPx, heightPx);
  if (mode == RenderMode::kSimple && aoSettings_.enabled) drawAmbientOcclusion(view, widthPx, heightPx);
  renderPass(view, mode, widthPx, heightPx, nullptr, nullptr);
}

// The room probe at the eye, where none was captured, the scene, its light or the mode changed, or the eye
// moved kRecaptureDistanceM from its centre: each face the scene as the mode shows it, lit by the sky's
// image-based light as before the probe (the probe leaves out its own passes), no planar reflections, the
// sun's disc left out of the sky (the lobes' sun term shows it).
void Renderer::captureRoomProbe(const vec3& eyeM, RenderMode mode) {
  if (probe_ && probe_->captured() && !probeDirty_ && probeMode_ == mode &&
      glm::distance(eyeM, probe_->centreM()) <= kRecaptureDistanceM) {
    return;
  }
  if (!probe_) probe_ = std::make_unique<RoomProbe>(compiler());
  const uint32_t n = probe_->facePx();
  resize(n, n);
  gpu_->reflectionShown.assign(rdb_->planarReflectors.size(), 0);
  capturingProbe_ = true;
  probe_->capture(eyeM, [&](const View& face) {
    const CubePass pass{rdb::RasterTextureRef::kNone};
    renderPass(face, mode, n, n, nullptr, &pass);
    RoomProbe::Face drawn{gpu_->floatColor, std::vector<float>(size_t(n) * n)};
    glBindFramebuffer(GL_READ_FRAMEBUFFER, gpu_->floatFbo);
    glReadPixels(0, 0, GLsizei(n), GLsizei(n), GL_DEPTH_COMPONENT, GL_FLOAT, drawn.depth.data());
    return drawn;
  });
  capturingProbe_ = false;
  ++stats_.probeCaptures;
  probeDirty_ = false;
  probeMode_ = mode;
}

// The cube reflectors' maps, where the scene, its light or the mode changed since they were captured: each
// face the scene without the reflector's own draw, from its centre, no planar reflections, the sun's disc left
// out of the sky (a few texels would hold its whole radiance; the reflector's Phong lobe shows the sun).
void Renderer::captureCubeReflectors(RenderMode mode) {
  const rdb::RasterRdb& r = *rdb_;
  if (!cubesDirty_ && cubeMode_ == mode && cubes_ && cubes_->count() == r.cubeReflectors.size()) return;
  if (!cubes_) cubes_ = std::make_unique<CubeReflections>(compiler());
  const uint32_t n = cubes_->facePx();
  resize(n, n);
  gpu_->reflectionShown.assign(r.planarReflectors.size(), 0);
  for (uint32_t k = 0; k < r.cubeReflectors.size(); ++k) {
    const rdb::RasterCubeReflector& c = r.cubeReflectors[k];
    const rdb::RasterMaterial& m = r.materials[c.material];
    cubes_->capture(k, c.centreM, std::max(1e-3f, 1e-3f * c.radiusM), m.reflectionFogDistanceM, [&](const View& face) {
      const CubePass pass{k};
      renderPass(face, mode, n, n, nullptr, &pass);
      CubeReflections::Face drawn{gpu_->floatColor};
      if (m.hasReflectionFog()) {
        // Reflection fog's distances (raster/cube_reflections.h): the face's depth and how to unproject it.
        copyDepth(gpu_->cubeFaceDepth, 0, 0, int(n), int(n));
        drawn.depth = gpu_->cubeFaceDepth;
        drawn.worldFromClip = glm::inverse(projection(face, 1.0f) * glm::inverse(face.worldFromCamera));
      }
      return drawn;
    });
    ++stats_.cubeCaptures;
  }
  cubesDirty_ = false;
  cubeMode_ = mode;
}

namespace {

// Per planar reflector: its anisotropic material's lobe axis t' in its plane (Renderer::reflectorTangents_),
// zero for others: the mean over its vertices of the tangent made perpendicular to the normal and turned by
// the rotation towards the bitangent w · n × t (as kSurfaceFragment turns it per pixel); where that gives no
// direction, n × x̂ (n × ŷ where |n_x| ≥ 0.9), rdb::RasterRdb::tangents' own fallback.
std::vector<vec3> reflectorTangents(const rdb::RasterRdb& r) {
  std::vector<vec3> out(r.planarReflectors.size(), vec3(0.0f));
  for (size_t k = 0; k < r.planarReflectors.size(); ++k) {
    const rdb::RasterPlanarReflector& pr = r.planarReflectors[k];
    const rdb::RasterMaterial& m = r.materials[pr.material];
    if (!m.anisotropic) continue;
    const vec3 n = pr.normal;
    const float c = std::cos(m.anisotropyRotationRad), s = std::sin(m.anisotropyRotationRad);
    vec3 sum(0.0f);
    for (uint32_t mesh : pr.meshes) {
      const rdb::RasterMesh& rm = r.meshes[mesh];
      for (uint32_t v = rm.firstVertex; v < rm.firstVertex + rm.vertexCount && v < r.tangents.size(); ++v) {
        const vec3 t = vec3(r.tangents[v]) - n * glm::dot(n, vec3(r.tangents[v]));
        if (glm::dot(t, t) < 1e-12f) continue;
        const vec3 u = glm::normalize(t);
        sum += c * u + s * (r.tangents[v].w < 0.0f ? -1.0f : 1.0f) * glm::cross(n, u);
      }
    }
    if (glm::dot(sum, sum) < 1e-12f) {
      const vec3 u = glm::normalize(glm::cross(n, std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0)));
      sum = c * u + s * glm::cross(n, u);
    }
    out[k] = glm::normalize(sum);
  }
  return out;
}

// How much coarser than the image (per axis) a glossy reflector's mirrored pass is drawn
// (Renderer::setGlossyReflectionScale): `forced`, or from the sky's spread 2α · pxPerTan (full pixels) the
// largest of 4, 2, 1 no wider than an eighth of it; either way one that divides the image's size.
uint32_t glossyPassScale(uint32_t forced, float narrowAlpha, float pxPerTan, uint32_t widthPx, uint32_t heightPx) {
  uint32_t s = forced;
  if (s == 0) {
    const float eighth = pxPerTan > 0.0f ? 2.0f * narrowAlpha * pxPerTan / 8.0f : 0.0f;
    s = eighth >= 4.0f ? 4 : eighth >= 2.0f ? 2 : 1;
  }
  while (s > 1 && (widthPx % s != 0 || heightPx % s != 0)) s /= 2;
  return s;
}

}  // namespace

// Each planar reflector seen from its front: the scene mirrored in its plane, drawn from the mirrored camera
// (a view whose worldFromCamera has determinant −1, so front faces wind clockwise) with the near plane moved
// onto the mirror (Lengyel's oblique frustum), and kept as that reflector's image. Pixel (x, y) of the image is
// what the real camera sees in the mirror at (x, y): the mirrored camera sees the point p where the real one
// sees its mirror image. A glossy reflector's pass may be drawn s times coarser per axis (glossyPassScale) in
// the target's lower-left corner and split there (raster/mirror_blur.h) without a copy; the glossy
// reflectors are blurred together after the last pass.
void Renderer::drawReflections(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx) {
  const rdb::RasterRdb& r = *rdb_;
  const rdb::RasterVariants& v = r.variants;
  const vec3 eye(view.worldFromCamera[3]);
  const vec3 viewDir = -glm::normalize(vec3(view.worldFromCamera[2]));
  gpu_->reflectionShown.assign(r.planarReflectors.size(), 0);
  gpu_->reflectionColor.resize(r.planarReflectors.size(), 0);
  gpu_->reflectionDepth.resize(r.planarReflectors.size(), 0);
  gpu_->reflectionWorldFromClip.resize(r.planarReflectors.size(), mat4(1.0f));
  gpu_->reflectionScale.resize(r.planarReflectors.size(), 1);
  if (v.anisotropy && reflectorTangents_.size() != r.planarReflectors.size()) reflectorTangents_ = reflectorTangents(r);
  const float aspect = float(widthPx) / float(heightPx);
  const mat4 clipFromWorld = projection(view, aspect) * glm::inverse(view.worldFromCamera);
  for (uint32_t k = 0; k < r.planarReflectors.size(); ++k) {
    const rdb::RasterPlanarReflector& pr = r.planarReflectors[k];
    const bool front = view.orthographic ? glm::dot(viewDir, pr.normal) < 0.0f : glm::dot(pr.normal, eye) > pr.offsetM;
    if (!front) continue;
    // The mirror's pixels: the screen rectangle of its bounding box (the whole image where a corner lies
    // behind the eye); none when the box lies outside the view.
    if (boxOnScreen(clipFromWorld, pr.loM, pr.hiM, widthPx, heightPx).empty()) continue;
    const rdb::RasterMaterial& prMaterial = r.materials[pr.material];
    const bool glossy = prMaterial.ggxAlpha >= kGlossyMirrorAlpha;
    // The lobe's widths: α_wide / α_narrow along the tangent axis t' or across it (base/ggx.h).
    vec2 alphas(prMaterial.ggxAlpha);
    if (prMaterial.anisotropic && k < reflectorTangents_.size())
      alphas = ggxAnisotropicAlphas(prMaterial.ggxAlpha, prMaterial.anisotropyU, prMaterial.anisotropyV);
    const float narrowAlpha = std::min(alphas.x, alphas.y);
    // A fogged reflector's fog reads the pass's depth per pixel, sharp (a coarser pass would show its pixels
    // along the fog's edges).
    const bool fullOnly = view.orthographic || v.frostedGlass || v.measuredBrdf || prMaterial.hasReflectionFog();
    const uint32_t scale =
        glossy && !fullOnly ? glossyPassScale(glossyReflectionScale_, narrowAlpha, blurScale(view, heightPx), widthPx, heightPx) : 1;
    const uint32_t passW = widthPx / scale, passH = heightPx / scale;
    const ScreenRect rect = boxOnScreen(clipFromWorld, pr.loM, pr.hiM, passW, passH);
    if (rect.empty()) continue;
    mat4 mirror(1.0f);  // p' = p − 2 (n·p − d) n
    for (int c = 0; c < 3; ++c)
      for (int row = 0; row < 3; ++row) mirror[c][row] = (c == row ? 1.0f : 0.0f) - 2.0f * pr.normal[c] * pr.normal[row];
    mirror[3] = vec4(2.0f * pr.offsetM * pr.normal, 1.0f);
    View mirrored = view;
    mirrored.worldFromCamera = mirror * view.worldFromCamera;
    const NdcRect ndc{2.0f * float(rect.x) / float(passW) - 1.0f, 2.0f * float(rect.y) / float(passH) - 1.0f,
                      2.0f * float(rect.x + rect.width) / float(passW) - 1.0f,
                      2.0f * float(rect.y + rect.height) / float(passH) - 1.0f};
    const MirrorPass pass{vec4(pr.normal, -pr.offsetM), k, ndc, {rect.x, rect.y, rect.width, rect.height}};
    glScissor(rect.x, rect.y, rect.width, rect.height);
    glEnable(GL_SCISSOR_TEST);
    renderPass(mirrored, mode, passW, passH, &pass, nullptr);
    glDisable(GL_SCISSOR_TEST);
    if (!glossy) {
      GLuint& image = gpu_->reflectionColor[k];
      if (!image) {
        glCreateTextures(GL_TEXTURE_2D, 1, &image);
        glTextureStorage2D(image, 1, GL_RG32UI, GLsizei(widthPx), GLsizei(heightPx));
        glTextureParameteri(image, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // integer: read with texelFetch
        glTextureParameteri(image, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      }
      glCopyImageSubData(gpu_->floatColor, GL_TEXTURE_2D, 0, rect.x, rect.y, 0, image, GL_TEXTURE_2D, 0, rect.x,
                         rect.y, 0, rect.width, rect.height, 1);
    }
    const vec4 planeCamera = glm::transpose(mirrored.worldFromCamera) * pass.planeWorld;
    const mat4 mirroredWorldFromClip =
        glm::inverse(obliqueNearPlane(projection(mirrored, aspect), planeCamera) * glm::inverse(mirrored.worldFromCamera));
    if (prMaterial.hasReflectionFog()) {
      // Reflection fog reads how far behind the mirror what it shows lies: the pass's depth in the rectangle
      // (the mirror's fragments lie inside it) and how to unproject it.
      copyDepth(gpu_->reflectionDepth[k], rect.x, rect.y, rect.width, rect.height);
      gpu_->reflectionWorldFromClip[k] = mirroredWorldFromClip;
    }
    if (glossy) {
      if (!mirrorBlur_) mirrorBlur_ = std::make_unique<MirrorBlur>(compiler());
      MirrorLobe lobe{
          .worldFromClip = mirroredWorldFromClip,
          .planeWorld = pass.planeWorld,
          .eye = view.orthographic ? vec4(viewDir, 0.0f) : vec4(vec3(mirrored.worldFromCamera[3]), 1.0f),
          .alpha = narrowAlpha,
          .pxPerTan = blurScale(view, passH)};
      if (alphas.x != alphas.y) {
        // The wide axis on screen where the view ray through the rectangle's centre meets the mirror (else at
        // its box's centre): the image of a short step along it.
        const vec3 t = reflectorTangents_[k];
        const vec3 wide = alphas.x > alphas.y ? t : glm::cross(pr.normal, t);
        vec3 at = 0.5f * (pr.loM + pr.hiM);
        const vec4 centre = glm::inverse(clipFromWorld) *
                            vec4(2.0f * (float(rect.x) + 0.5f * float(rect.width)) / float(passW) - 1.0f,
                                 2.0f * (float(rect.y) + 0.5f * float(rect.height)) / float(passH) - 1.0f, 0.0f, 1.0f);
        const vec3 toCentre = vec3(centre) / centre.w - eye;
        const float along = glm::dot(pr.normal, toCentre);
        if (!view.orthographic && along < 0.0f) at = eye + (pr.offsetM - glm::dot(pr.normal, eye)) / along * toCentre;
        const float step = 1e-3f * std::max(glm::length(at - eye), 1e-3f);
        const vec4 a = clipFromWorld * vec4(at, 1.0f), b = clipFromWorld * vec4(at + step * wide, 1.0f);
        vec2 axis = a.w > 0.0f && b.w > 0.0f ? (vec2(b) / b.w - vec2(a) / a.w) * vec2(float(widthPx), float(heightPx))
                                             : vec2(glm::transpose(mat3(view.worldFromCamera)) * wide);
        if (glm::dot(axis, axis) > 0.0f) {
          lobe.wideAxis = glm::normalize(axis);
          lobe.aspect = std::max(alphas.x, alphas.y) / narrowAlpha;
        }
      }
      mirrorBlur_->split(k, gpu_->floatColor, gpu_->depth, {rect.x, rect.y, rect.width, rect.height}, passW, passH, lobe);
      stats_.lastGlossyReflectionScale = scale;
    }
    gpu_->reflectionScale[k] = scale;
    gpu_->reflectionShown[k] = 1;
    ++stats_.reflectionPasses;
    stats_.reflectionPassPixels += int64_t(rect.width) * rect.height;
  }
  if (mirrorBlur_) mirrorBlur_->finish();
}

bool Renderer::hasDisplayEmission() const {
  if (!rdb_) return false;
  return std::any_of(rdb_->materials.begin(), rdb_->materials.end(), [](const rdb::RasterMaterial& m) {
    return m.emissionDisplay && maxComponent(m.emissionCdM2) > 0.0f;
  });
}

// Back faces culled (one-sided surfaces) or drawn (two-sided ones); the winding of the front face is the
// pass's (glFrontFace: mirrored passes turn it).
static void setFaceCulling(bool cull) {
  if (cull)
    glEnable(GL_CULL_FACE);
  else
    glDisable(GL_CULL_FACE);
}

// The per-vertex meshes' chunks in gpu_->visibleChunks: the one-sided meshes' in one multi-draw with their back
// faces culled, then the two-sided ones' in another. Leaves face culling off.
void Renderer::drawVisibleChunks() {
  std::vector<GLsizei>& counts = gpu_->drawCounts;
  std::vector<const void*>& offsets = gpu_->drawOffsets;
  const uint32_t boundary = uint32_t(gpu_->perVertexOneSidedCount);
  for (const bool twoSided : {false, true}) {
    counts.clear();
    offsets.clear();
    for (const IndexRange& r : gpu_->visibleChunks) {
      // The part of the range on this side of the boundary (a merged range may cross it).
      const uint32_t lo = twoSided ? std::max(r.firstIndex, boundary) : r.firstIndex;
      const uint32_t hi = twoSided ? r.firstIndex + r.indexCount : std::min(r.firstIndex + r.indexCount, boundary);
      if (hi <= lo) continue;
      counts.push_back(GLsizei(hi - lo));
      offsets.push_back(reinterpret_cast<const void*>(size_t(lo) * sizeof(uint32_t)));
      stats_.perVertexTrianglesDrawn += (hi - lo) / 3;
    }
    if (counts.empty()) continue;
    setFaceCulling(!twoSided);
    glMultiDrawElements(GL_TRIANGLES, counts.data(), GL_UNSIGNED_INT, offsets.data(), GLsizei(counts.size()));
  }
  setFaceCulling(false);
}



void Renderer::renderPass(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx,
                          const MirrorPass* mirrorPass, const CubePass* cubePass) {
  const rdb::RasterRdb& r = *rdb_;
  const rdb::RasterVariants& v = r.variants;
  const float aspect = float(widthPx) / float(heightPx);
  mat4 clipFromCamera = projection(view, aspect);
  // A plane transforms as a row vector: C_camera = C_world · worldFromCamera.
  if (mirrorPass) clipFromCamera = obliqueNearPlane(clipFromCamera, glm::transpose(view.worldFromCamera) * mirrorPass->planeWorld);
  const mat4 clipFromWorld = clipFromCamera * glm::inverse(view.worldFromCamera);
  glFrontFace(mirrorPass ? GL_CW : GL_CCW);
  // The per-vertex meshes' chunks this pass can see (a mirrored pass: through its mirror, in front of it).
  visibleRanges(gpu_->perVertexChunks, clipFromWorld, mirrorPass ? mirrorPass->rect : NdcRect{}, gpu_->visibleChunks);

  // The background in every pixel, in place of a colour clear; the scene is drawn over it: the sky and the
  // sun where the scene has them, in sunlight mode and in light-map mode (what a window shows beyond the
  // baked surfaces: the sky of the bake's site and time), else black.
  const bool sunlight = mode == RenderMode::kSunlight;
  const bool sky = (sunlight || mode == RenderMode::kLightMap) && v.sky;
  BackgroundProgram& bg = sky ? gpu_->sky : gpu_->background;
  if (!bg.program) {
    bg.program = compileProgram(sky ? "sky" : "background",
                                std::string(sky ? "#define FLY_SKY\n" : "") + shaders::kLuminanceEncoding,
                                {{GL_COMPUTE_SHADER, shaders::kBackgroundCompute}});
    auto loc = [&](const char* n) { return glGetUniformLocation(bg.program, n); };
    bg.worldFromCamera = loc("uWorldFromCamera");
    bg.tanHalfFov = loc("uTanHalfFov");
    bg.sunDir = loc("uSunDirWorld");
    bg.sunRadiance = loc("uSunRadianceCdM2");
    bg.sunCosHalfAngle = loc("uSunCosHalfAngle");
    bg.region = loc("uRegion");
    bg.passPx = loc("uPassPx");
  }
  glUseProgram(bg.program);
  if (sky) {
    const mat3 rotation(view.worldFromCamera);
    glUniformMatrix3fv(bg.worldFromCamera, 1, GL_FALSE, &rotation[0][0]);
    const float tanY = view.orthographic ? 0.0f : std::tan(0.5f * view.yfovRad);
    glUniform2f(bg.tanHalfFov, tanY * aspect, tanY);
    const rdb::RasterSky& s = *r.sky;
    glUniform3fv(bg.sunDir, 1, &s.sunDirWorld[0]);
    glUniform3fv(bg.sunRadiance, 1, &s.sunRadianceCdM2[0]);
    glUniform1f(bg.sunCosHalfAngle, s.hasSun && !cubePass ? std::cos(s.sunHalfAngleRad) : 2.0f);
    glBindTextureUnit(0, gpu_->skyTexture);
  }
  // A mirrored pass fills only its scissor rectangle, the only pixels it draws and its reflector reads
  // (with frosted glass, whose blur reads the whole pass's mip chain, all of the pass).
  const bool rectOnly = mirrorPass && !v.frostedGlass;
  const GLint region[4] = {rectOnly ? mirrorPass->rectPx[0] : 0, rectOnly ? mirrorPass->rectPx[1] : 0,
                           rectOnly ? mirrorPass->rectPx[2] : GLint(widthPx), rectOnly ? mirrorPass->rectPx[3] : GLint(heightPx)};
  glUniform4iv(bg.region, 1, region);
  glUniform2f(bg.passPx, float(widthPx), float(heightPx));
  glBindImageTexture(0, gpu_->floatColor, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32UI);
  dispatchPerPixel(uint32_t(region[2]), uint32_t(region[3]));

  glBindFramebuffer(GL_FRAMEBUFFER, gpu_->floatFbo);
  glViewport(0, 0, GLsizei(widthPx), GLsizei(heightPx));
  glClearNamedFramebufferfi(gpu_->floatFbo, GL_DEPTH_STENCIL, 0, 1.0f, 0);
  glEnable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);

  // The scene with the program of this mode and the scene's features (modes that need the same variant share
  // it: simple and sunlight modes differ only in the ambient uniforms): the per-vertex meshes in one
  // draw, then the per-fragment surfaces (uploadDraws), the glass, the blended surfaces.
  if (gpu_->indexCount > 0) {
    const bool lightMaps = mode != RenderMode::kSimple && v.lightMap;
    const bool phong = !lightMaps || !gpu_->everyMeshLightMapped;
    // Sunlight mode over light maps without the sun's direct part: that part drawn for the current sun.
    const bool sunDirect = sunlight && lightMaps && v.sunDirect;
    const bool ibl = (sunlight || probeActive_) && imageBasedLight_ && environment_ && !environmentDirty_;
    // The room probe's maps for the specular environment, except in the probe's own capture.
    const bool roomProbe = ibl && probeActive_ && !capturingProbe_ && probe_ && probe_->captured();
    // The maps of the specular environment: the room probe's, else the sky's.
    const EnvironmentLight* specular = !ibl ? nullptr : roomProbe ? &probe_->maps() : environment_.get();
    const uint32_t shared = (ibl ? kVariantIbl : 0u) | (roomProbe ? kVariantRoomProbe : 0u) | (lightMaps ? kVariantLightMap : 0u) | (phong ? kVariantPhong : 0u) |
                            ((phong || sunDirect) && v.sun ? kVariantSun : 0u) |
                            (sunDirect ? kVariantSunDirect : 0u) | (v.twoSided ? kVariantTwoSided : 0u) |
                            (phong && v.goniometric ? kVariantGonio : 0u) |
                            (lightMaps && v.lightTexture ? kVariantLightTexture : 0u) |
                            (mode == RenderMode::kSimple && aoSettings_.enabled && !mirrorPass && !cubePass
                                 ? kVariantAmbientOcclusion
                                 : 0u);
    // The sun through clear glass (raster/sun_glass.h), where a program draws the sun's direct term, the sun
    // is above the horizon and the scene has clear glass: the transmittance map is rebuilt here only when the
    // sun, the geometry or the materials changed.
    uint32_t sunGlass = 0;
    if ((shared & kVariantSun) && v.sun && v.glass) {
      if (!sunGlass_) sunGlass_ = std::make_unique<SunGlassMap>(compiler());
      if (sunGlassDirty_) {
        sunGlass_->setGlass(r);
        sunGlassDirty_ = false;
        ++stats_.sunGlassUploads;
      }
      if (sunGlass_->build(r.sky->sunDirWorld, shadowSettings_.transmittanceMapTexels))
        ++stats_.sunGlassBuilds;
      if (!sunGlass_->empty()) sunGlass = kVariantSunGlass;
    }
    // The per-vertex meshes' program; with light textures and angle-dependent diffuse shares, the share is
    // taken per fragment (kSceneVertex's vShare*).
    const uint32_t variant =
        shared | sunGlass | (v.glass ? kVariantGlass : 0u) | (v.glass && v.frostedGlass ? kVariantFrosted : 0u) |
        (lightMaps && v.lightTexture && v.diffuseByAngle ? kVariantDiffuseByAngle : 0u);
    const uint32_t surfaceVariant =
        shared | sunGlass | kVariantPerFragment | (v.measuredBrdf ? kVariantMeasured : 0u) |
        (v.measuredBrdf && v.goniometric ? kVariantGonio : 0u) |
        (v.textures ? kVariantTextures : 0u) |
        ((phong || sunDirect) && v.normalMaps ? kVariantNormalMap : 0u) |
        ((phong || sunDirect || ibl || v.cubeReflectors) && v.anisotropy ? kVariantAnisotropy : 0u) |
        ((phong || sunDirect || ibl || v.cubeReflectors) && v.textures && v.glossinessTextures
             ? kVariantGlossinessTexture
             : 0u) |
        (v.textures && v.metalnessTextures ? kVariantMetalnessTexture : 0u) |
        (v.textures && v.uv1 ? kVariantUv1 : 0u) | (v.vertexColors ? kVariantVertexColor : 0u) |
        (v.planarReflectors ? kVariantPlanarReflection : 0u) | (v.cubeReflectors ? kVariantCubeReflection : 0u) |
        (v.reflectionFog ? kVariantReflectionFog : 0u) | (lightMaps && v.diffuseByAngle ? kVariantDiffuseByAngle : 0u);
    const vec3 eye(view.worldFromCamera[3]);
    const vec3 viewDir = -glm::normalize(vec3(view.worldFromCamera[2]));
    const rdb::DirectionalAmbient& ambient = sunlight ? r.daylightAmbient : r.ambient;
    vec3 sunLux(0.0f);
    if (v.sun) {
      const rdb::RasterSky& s = *r.sky;
      const double solidAngleSr = 2.0 * kPi * (1.0 - std::cos(double(s.sunHalfAngleRad)));
      sunLux = s.sunRadianceCdM2 * float(solidAngleSr);
    }
    // The sun's shadows (raster/sun_shadows.h), where a program draws the sun's direct term and the sun is
    // above the horizon (v.sun): the volumes are rebuilt here only when the sun or the geometry moved.
    const bool shadows =
        ((variant | surfaceVariant) & kVariantSun) && v.sun && shadowSettings_.mode != SunShadowMode::kOff;
    if (shadows) {
      if (!shadows_) {
        shadows_ = std::make_unique<SunShadows>(compiler());
        shadows_->setProfiling(shadowProfiling_);
      }
      if (shadowGeometryDirty_) {
        shadows_->setGeometry(r, gpu_->positions);
        shadowGeometryDirty_ = false;
        ++stats_.shadowGeometryUploads;
      }
      if (shadows_->build(r.sky->sunDirWorld, shadowSettings_)) ++stats_.shadowBuilds;
    }
    // The measured materials' balls under this frame's lights (raster/ball_texture.h).
    bool nearDeferred = false;
    if (v.measuredBrdf) {
      makeBalls(view, mode);
      glBindFramebuffer(GL_FRAMEBUFFER, gpu_->floatFbo);
      nearDeferred = prepareNearLamps();
    }
    // The opaque per-fragment draws' variant: with near lamps, they record them for kNearLampsCompute.
    const uint32_t opaqueSurfaceVariant = surfaceVariant | (nearDeferred ? kVariantNearDeferred : 0u);
    const GLenum kColorOnly[] = {GL_COLOR_ATTACHMENT0};
    const GLenum kWithNearRecords[] = {GL_COLOR_ATTACHMENT0, GL_COLOR_ATTACHMENT1, GL_COLOR_ATTACHMENT2};
    // The sun's illuminance the scene programs get (uSunNormalLux): 0 in the pass over shadowed pixels.
    vec3 sunPassLux = sunLux;
    // Binds a scene program and sets its uniforms.
    auto use = [&](uint32_t programVariant) -> const SceneProgram& {
      const SceneProgram& p = sceneProgram(programVariant);
      glUseProgram(p.program);
      glUniformMatrix4fv(p.clipFromWorld, 1, GL_FALSE, &clipFromWorld[0][0]);
      glUniform3fv(p.eye, 1, &eye[0]);
      glUniform3fv(p.viewDir, 1, &viewDir[0]);
      glUniform1i(p.orthographic, view.orthographic ? 1 : 0);
      glUniform1i(p.lightCount, GLint(r.lights.size()));
      glUniform3fv(p.ambientUp, 1, &ambient.upLux[0]);
      glUniform3fv(p.ambientDown, 1, &ambient.downLux[0]);
      glUniform1f(p.displayWhite, displayWhiteCdM2_);
      if (v.sun) {
        glUniform3fv(p.sunDir, 1, &r.sky->sunDirWorld[0]);
        glUniform3fv(p.sunNormalLux, 1, &sunPassLux[0]);
      }
      if (programVariant & kVariantIbl) {
        glUniform1i(p.irradianceAmbient, sunlight ? 1 : 0);
        glUniform1f(p.radianceTopLevel, float(specular->settings().radianceLevels - 1));
      }
      if (programVariant & kVariantRoomProbe) {
        glUniform3fv(p.probeCentre, 1, &probe_->centreM()[0]);
        glUniform3fv(p.probeBoxMin, 1, &probe_->boxMinM()[0]);
        glUniform3fv(p.probeBoxMax, 1, &probe_->boxMaxM()[0]);
      }
      if (programVariant & (kVariantFrosted | kVariantPlanarReflection)) {
        if (programVariant & kVariantFrosted) {
          const mat4 worldFromClip = glm::inverse(clipFromWorld);
          glUniformMatrix4fv(p.worldFromClip, 1, GL_FALSE, &worldFromClip[0][0]);
        }
        const vec4 blurView(eye, blurScale(view, heightPx));
        glUniform4fv(p.blurView, 1, &blurView[0]);
      }
      if (programVariant & kVariantSunGlass) {
        glUniformMatrix4fv(p.sunGlassFromWorld, 1, GL_FALSE, &sunGlass_->mapFromWorld()[0][0]);
        glUniform1f(p.sunGlassBias, sunGlass_->biasM());
      }
      return p;
    };
    // Sets a per-fragment draw's material and binds its textures (units 5–7, kSurfaceFragment): which it has
    // (a slot the material does not use is never sampled) and their UV maps.
    auto bindTextures = [&](const SceneProgram& p, const SurfaceDraw& d) {
      const rdb::RasterMaterial& m = r.materials[d.material];
      glUniform1ui(p.material, d.material);
      glUniform1i(p.ballLayer, m.measured == rdb::RasterTextureRef::kNone ? -1 : GLint(2 * m.measured));
      if (m.measured != rdb::RasterTextureRef::kNone) {
        const mat3& ballFromWorld = balls_->ballFromWorld(m.measured);
        glUniformMatrix3fv(p.ballFromWorld, 1, GL_FALSE, &ballFromWorld[0][0]);
        const std::vector<int>& near = balls_->nearLights(m.measured);
        glUniform1i(p.nearLightCount, GLint(near.size()));
        if (!near.empty()) glUniform1iv(p.nearLights, GLsizei(near.size()), near.data());
      }
      const auto slots = textureSlots(m);
      GLuint bits = 0;
      vec4 rows[2 * kTextureSlots];
      for (int k = 0; k < kTextureSlots; ++k) {
        rows[2 * k] = vec4(slots[k]->uvRow0, float(slots[k]->texCoord));
        rows[2 * k + 1] = vec4(slots[k]->uvRow1, 0.0f);
        if (!*slots[k]) continue;
        glBindTextureUnit(kTextureSlotUnits[k], gpu_->textures[slots[k]->texture]);
        glBindSampler(kTextureSlotUnits[k], d.samplers[k]);
        bits |= 1u << k;
      }
      glUniform1ui(p.textureSlots, bits);
      glUniform4fv(p.uvRows, 2 * kTextureSlots, &rows[0][0]);
      if (v.cubeReflectors) {
        // A cube reflector shades with its own maps (captured this frame or before) in place of the sky's.
        const bool cube = d.cubeReflector != rdb::RasterTextureRef::kNone && cubes_ && d.cubeReflector < cubes_->count();
        glUniform1i(p.cubeReflector, cube ? GLint(d.cubeReflector) : -1);
        if (cube) {
          const EnvironmentLight& maps = cubes_->maps(d.cubeReflector);
          glBindTextureUnit(12, maps.irradianceCube());
          glBindTextureUnit(13, maps.radianceCube());
          glBindTextureUnit(14, maps.splitSumTable());
          glUniform1f(p.radianceTopLevel, float(maps.settings().radianceLevels - 1));
        } else if (ibl) {
            glBindTextureUnit(12, environment_->irradianceCube());
          glBindTextureUnit(13, specular->radianceCube());
          glBindTextureUnit(14, specular->splitSumTable());
          glUniform1f(p.radianceTopLevel, float(specular->settings().radianceLevels - 1));
        }
      }
      if (v.reflectionFog) {
        glUniform1f(p.fogDistance, m.hasReflectionFog() ? m.reflectionFogDistanceM : -1.0f);
        glUniform3fv(p.fogColor, 1, &m.reflectionFogColor[0]);
      }
      if (v.planarReflectors) {
        // A reflector shows its image in the real view; in a mirrored pass none does (one reflection deep).
        const bool shows = !mirrorPass && d.reflector != rdb::RasterTextureRef::kNone && !d.blend &&
                           gpu_->reflectionShown.size() > d.reflector && gpu_->reflectionShown[d.reflector];
        glUniform1i(p.reflector, shows ? GLint(d.reflector) : -1);
        if (shows) {
          if (gpu_->reflectionColor[d.reflector]) glBindTextureUnit(11, gpu_->reflectionColor[d.reflector]);
          glUniform3fv(p.mirrorReflection, 1, &m.mirrorReflection[0]);
          glUniform1f(p.mirrorF0, m.mirrorF0);
          glUniform1i(p.sunInReflection, sky && v.sun ? 1 : 0);
          const bool glossy = m.ggxAlpha >= kGlossyMirrorAlpha;
          glUniform1i(p.mirrorGlossy, glossy ? 1 : 0);
          glUniform1f(p.mirrorScale, float(gpu_->reflectionScale[d.reflector]));
          if (m.hasReflectionFog()) {
            glBindTextureUnit(1, gpu_->reflectionDepth[d.reflector]);
            glUniformMatrix4fv(p.mirrorWorldFromClip, 1, GL_FALSE, &gpu_->reflectionWorldFromClip[d.reflector][0][0]);
          }
          if (glossy) {
            glBindTextureUnit(3, mirrorBlur_->pyramid(d.reflector));
            glUniform4iv(p.mirrorFine, 1, mirrorBlur_->fineRegion(d.reflector));
            glUniform4iv(p.mirrorCoarse, 1, mirrorBlur_->coarseRegion(d.reflector));
            const std::vector<vec2>& taps = mirrorBlur_->taps(d.reflector);
            glUniform1i(p.mirrorTapCount, GLint(taps.size()));
            glUniform2fv(p.mirrorTaps, GLsizei(taps.size()), &taps[0][0]);
          }
        }
      }
    };
    auto draw = [](size_t firstIndex, GLsizei count) {
      glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                     reinterpret_cast<const void*>(firstIndex * sizeof(uint32_t)));
    };
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    auto bindScene = [&] {
      const GLuint ssbos[3] = {gpu_->materials, gpu_->lights, gpu_->gonio};
      glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 3, ssbos);
      if (lightMaps && v.lightTexture) {
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 3, gpu_->lightRects);
        glBindTextureUnit(2, gpu_->lightTextures);
      }
      if (sunGlass) glBindTextureUnit(8, sunGlass_->texture());
      if (ibl) {
        glBindTextureUnit(12, environment_->irradianceCube());
        glBindTextureUnit(13, specular->radianceCube());
        glBindTextureUnit(14, specular->splitSumTable());
      }
      if (v.measuredBrdf) {
        glBindTextureUnit(9, balls_->texture());
        glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, balls_->brdfBuffer());
        glBindTextureUnit(10, balls_->tableTexture());
      }
      glBindVertexArray(gpu_->vao);
      if (r.frontLux.empty()) glVertexAttrib3f(3, 0.0f, 0.0f, 0.0f);
      if (r.backLux.empty()) glVertexAttrib3f(4, 0.0f, 0.0f, 0.0f);
      if (r.backSunDirectLux.empty()) glVertexAttrib3f(13, 0.0f, 0.0f, 0.0f);
    };
    // The opaque and cut-out surfaces: the per-vertex meshes in one draw, then the per-fragment ones.
    auto drawOpaque = [&] {
      if (gpu_->perVertexIndexCount > 0) {
        const SceneProgram& p = use(variant);
        if (variant & kVariantGlass) glUniform1i(p.glassPass, 0);  // everything but the glass
        drawVisibleChunks();
      }
      uint32_t current = ~0u;
      const SceneProgram* program = nullptr;
      if (nearDeferred) glNamedFramebufferDrawBuffers(gpu_->floatFbo, 3, kWithNearRecords);
      for (const SurfaceDraw& d : gpu_->surfaceDraws) {
        if (d.blend || d.glass) continue;
        if (mirrorPass && d.reflector == mirrorPass->reflector) continue;  // the mirror itself, on the near plane
        if (cubePass && d.cubeReflector == cubePass->reflector) continue;  // the reflector itself, around the eye
        const uint32_t want = opaqueSurfaceVariant | (d.mask ? kVariantAlphaMask : 0u);
        if (want != current) program = &use(current = want);
        bindTextures(*program, d);
        setFaceCulling(!d.twoSided);
        draw(d.firstIndex, d.indexCount);
      }
      setFaceCulling(false);
      if (nearDeferred) glNamedFramebufferDrawBuffers(gpu_->floatFbo, 1, kColorOnly);
    };
    bindScene();
    drawOpaque();
    if (shadows) {
      // The stencil counts the shadow volumes each visible surface lies in; where it is not 0 the same draws
      // again, at equal depth, without the sun (the colour target holds shared-exponent words: no blending).
      // Glass and blended surfaces, drawn next, get the sun unshadowed.
      shadows_->drawStencil(clipFromWorld);
      bindScene();
      glStencilFunc(GL_NOTEQUAL, 0, 0xff);
      glStencilOp(GL_KEEP, GL_KEEP, GL_KEEP);
      glDepthFunc(GL_EQUAL);
      glDepthMask(GL_FALSE);
      sunPassLux = vec3(0.0f);
      drawOpaque();
      sunPassLux = sunLux;
      glDisable(GL_STENCIL_TEST);
      glDepthFunc(GL_LESS);
      glDepthMask(GL_TRUE);
      lastShadowClipFromWorld_ = clipFromWorld;
      ++stats_.shadowPasses;
    }
    if (nearDeferred) {
      drawNearLamps(clipFromWorld, eye, viewDir, view.orthographic, v.goniometric, widthPx, heightPx);
      bindScene();
    }
    const bool surfaceGlass = std::any_of(gpu_->surfaceDraws.begin(), gpu_->surfaceDraws.end(),
                                          [](const SurfaceDraw& d) { return d.glass; });
    if ((variant & kVariantGlass) && (gpu_->perVertexIndexCount > 0 || surfaceGlass)) {
      // The glass over a copy of that image, which it shows through itself times T(θ) (kSceneFragment). The
      // nearest pane wins where panes overlap (its depth hides the farther one's): what lies behind a pane
      // is seen through that pane alone.
      const GLsizei w = GLsizei(widthPx), h = GLsizei(heightPx);
      if (!gpu_->behindColor) {
        // The target's size (a glossy reflector's pass may use a corner of it).
        glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->behindColor);
        glTextureStorage2D(gpu_->behindColor, 1, GL_RG32UI, GLsizei(width_), GLsizei(height_));
        // An integer texture is complete only with nearest filtering (texelFetch reads 0 otherwise).
        glTextureParameteri(gpu_->behindColor, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(gpu_->behindColor, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      }
      glCopyImageSubData(gpu_->floatColor, GL_TEXTURE_2D, 0, 0, 0, 0, gpu_->behindColor, GL_TEXTURE_2D, 0, 0,
                         0, 0, w, h, 1);
      glBindTextureUnit(4, gpu_->behindColor);
      if (variant & kVariantFrosted) prepareFrostedGlass();
      if (gpu_->perVertexIndexCount > 0) {
        const SceneProgram& p = use(variant);
        glUniform1i(p.glassPass, 1);
        drawVisibleChunks();
      }
      // The textured panes (per fragment), with the glass's own variant: no planar or cube reflector is glass.
      const uint32_t glassVariant =
          (surfaceVariant & ~uint32_t(kVariantPlanarReflection | kVariantCubeReflection | kVariantAmbientOcclusion)) |
          (variant & (kVariantGlass | kVariantFrosted));
      for (const SurfaceDraw& d : gpu_->surfaceDraws) {
        if (!d.glass) continue;
        const SceneProgram& p = use(glassVariant | (d.mask ? kVariantAlphaMask : 0u));
        bindTextures(p, d);
        setFaceCulling(!d.twoSided);
        draw(d.firstIndex, d.indexCount);
      }
      setFaceCulling(false);
    }
    if (v.alphaBlend) {
      // Blended surfaces, after everything else, back to front by their meshes' centres' view depth, without
      // depth writes, "over" into the blend target (cleared to C = 0, T = 1), then composited over the image
      // (kBlendComposite). Within a mesh, triangles keep their order.
      std::vector<size_t>& order = gpu_->blendOrder;
      order.clear();
      for (size_t i = 0; i < gpu_->surfaceDraws.size(); ++i) {
        if (gpu_->surfaceDraws[i].blend) order.push_back(i);
      }
      auto depth = [&](size_t i) { return glm::dot(gpu_->surfaceDraws[i].centreM - eye, viewDir); };
      std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return depth(a) > depth(b); });
      if (!gpu_->blendColor) {
        glCreateTextures(GL_TEXTURE_2D, 1, &gpu_->blendColor);
        glTextureStorage2D(gpu_->blendColor, 1, GL_RGBA32F, GLsizei(width_), GLsizei(height_));
        glCreateFramebuffers(1, &gpu_->blendFbo);
        glNamedFramebufferTexture(gpu_->blendFbo, GL_COLOR_ATTACHMENT0, gpu_->blendColor, 0);
        glNamedFramebufferRenderbuffer(gpu_->blendFbo, GL_DEPTH_STENCIL_ATTACHMENT, GL_RENDERBUFFER,
                                       gpu_->depth);
      }
      glBindFramebuffer(GL_FRAMEBUFFER, gpu_->blendFbo);
      const GLfloat empty[4] = {0.0f, 0.0f, 0.0f, 1.0f};
      glClearNamedFramebufferfv(gpu_->blendFbo, GL_COLOR, 0, empty);
      glEnable(GL_BLEND);
      glBlendFuncSeparate(GL_ONE, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE_MINUS_SRC_ALPHA);
      glDepthMask(GL_FALSE);
      // Blended surfaces are in no depth pre-pass: the ambient occlusion under them is another surface's.
      const SceneProgram& p = use((surfaceVariant | kVariantBlendPass) & ~uint32_t(kVariantAmbientOcclusion));
      for (size_t i : order) {
        const SurfaceDraw& d = gpu_->surfaceDraws[i];
        bindTextures(p, d);
        setFaceCulling(!d.twoSided);
        draw(d.firstIndex, d.indexCount);
      }
      setFaceCulling(false);
      glDepthMask(GL_TRUE);
      glDisable(GL_BLEND);
      glBindFramebuffer(GL_FRAMEBUFFER, gpu_->floatFbo);
      if (!gpu_->composite) {
        gpu_->composite = compileProgram("blend", shaders::kLuminanceEncoding,
                                         {{GL_COMPUTE_SHADER, shaders::kBlendComposite}});
      }
      glUseProgram(gpu_->composite);
      glBindImageTexture(0, gpu_->floatColor, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32UI);
      glBindImageTexture(1, gpu_->blendColor, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      dispatchPerPixel(widthPx, heightPx);
    }
    glBindVertexArray(0);
  }
  glFrontFace(GL_CCW);
  ++stats_.scenePasses;
}

bool Renderer::prepareNearLamps() {
  const uint32_t brdfs = uint32_t(rdb_->measuredBrdfs.size());
  constexpr uint32_t kStride = kMaxNearLights + 1;  // shaders::kNearLampsCompute's nearLists
  std::vector<int32_t> lists(size_t(brdfs) * kStride, 0);
  bool any = false;
  for (uint32_t k = 0; k < brdfs; ++k) {
    const std::vector<int>& near = balls_->nearLights(k);
    lists[k * kStride] = int32_t(near.size());
    std::copy(near.begin(), near.end(), lists.begin() + k * kStride + 1);
    any = any || !near.empty();
  }
  if (!any) return false;
  if (!gpu_->nearLists) {
    glCreateBuffers(1, &gpu_->nearLists);
    glNamedBufferStorage(gpu_->nearLists, GLsizeiptr(lists.size() * sizeof(int32_t)), lists.data(),
                         GL_DYNAMIC_STORAGE_BIT);
  } else {
    GLint64 bytes = 0;
    glGetNamedBufferParameteri64v(gpu_->nearLists, GL_BUFFER_SIZE, &bytes);
    if (size_t(bytes) != lists.size() * sizeof(int32_t)) {
      glDeleteBuffers(1, &gpu_->nearLists);
      gpu_->nearLists = 0;
      return prepareNearLamps();
    }
    glNamedBufferSubData(gpu_->nearLists, 0, GLsizeiptr(lists.size() * sizeof(int32_t)), lists.data());
  }
  if (!gpu_->nearData) {
    const GLsizei w = GLsizei(width_), h = GLsizei(height_);
    const uint32_t zero[4] = {0, 0, 0, 0};
    for (GLuint* t : {&gpu_->nearData, &gpu_->nearLight}) {
      glCreateTextures(GL_TEXTURE_2D, 1, t);
      glTextureStorage2D(*t, 1, GL_RGBA32UI, w, h);
      glClearTexImage(*t, 0, GL_RGBA_INTEGER, GL_UNSIGNED_INT, zero);
    }
    glNamedFramebufferTexture(gpu_->floatFbo, GL_COLOR_ATTACHMENT1, gpu_->nearData, 0);
    glNamedFramebufferTexture(gpu_->floatFbo, GL_COLOR_ATTACHMENT2, gpu_->nearLight, 0);
    if (glCheckNamedFramebufferStatus(gpu_->floatFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE)
      throw std::runtime_error("the OpenGL driver cannot render into RGBA32UI attachments beside RG32UI");
  }
  return true;
}

void Renderer::drawNearLamps(const mat4& clipFromWorld, const vec3& eyeM, const vec3& viewDirWorld,
                             bool orthographic, bool goniometric, uint32_t widthPx, uint32_t heightPx) {
  NearProgram& p = gpu_->nearPrograms[goniometric];
  if (!p.program) {
    const std::string defines =
        std::string("#define FLY_MEASURED\n") + (goniometric ? "#define FLY_GONIO\n" : "") +
        "#define FLY_CORNER_GAIN " + std::to_string(rdb::kCornerGain) + "\n" + "#define FLY_GONIO_GAMMA_STEPS " +
        std::to_string(rdb::kRasterGonioGammaSteps) + "\n" + "#define FLY_GONIO_C_STEPS " +
        std::to_string(rdb::kRasterGonioCSteps) + "\n" + "#define FLY_MAX_NEAR_LIGHTS " +
        std::to_string(kMaxNearLights) + "\n" + "#define FLY_ALBEDO_STEPS " +
        std::to_string(rdb::kRasterAlbedoSteps) + "\n" + "#define FLY_BRDF_BINDING 4\n#define FLY_BRDF_TABLE_UNIT 10\n";
    const std::string source = std::string(shaders::kLuminanceEncoding) + shaders::kGlassPane +
                               shaders::kSceneCommon + shaders::kMeasuredBrdf + shaders::kNearLamp +
                               shaders::kNearLampsCompute;
    p.program = compileProgram(goniometric ? "nearlamps-gonio" : "nearlamps", defines,
                               {{GL_COMPUTE_SHADER, source.c_str()}});
    p.worldFromClip = glGetUniformLocation(p.program, "uWorldFromClip");
    p.eye = glGetUniformLocation(p.program, "uEyeM");
    p.viewDir = glGetUniformLocation(p.program, "uViewDirWorld");
    p.orthographic = glGetUniformLocation(p.program, "uOrthographic");
  }
  glUseProgram(p.program);
  const mat4 worldFromClip = glm::inverse(clipFromWorld);
  glUniformMatrix4fv(p.worldFromClip, 1, GL_FALSE, &worldFromClip[0][0]);
  glUniform3fv(p.eye, 1, &eyeM[0]);
  glUniform3fv(p.viewDir, 1, &viewDirWorld[0]);
  glUniform1i(p.orthographic, orthographic ? 1 : 0);
  const GLuint ssbos[2] = {gpu_->lights, gpu_->gonio};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 1, 2, ssbos);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, balls_->brdfBuffer());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 5, gpu_->nearLists);
  glBindTextureUnit(10, balls_->tableTexture());
  glBindImageTexture(0, gpu_->floatColor, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RG32UI);
  glBindImageTexture(1, gpu_->nearData, 0, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32UI);
  glBindImageTexture(2, gpu_->nearLight, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32UI);
  dispatchPerPixel(widthPx, heightPx);
  ++stats_.nearLampPasses;
}

int Renderer::makeBalls(const View& view, RenderMode mode) {
  if (!rdb_) throw std::logic_error("Renderer::makeBalls before upload");
  const rdb::RasterRdb& r = *rdb_;
  const rdb::RasterVariants& v = r.variants;
  if (!v.measuredBrdf) return 0;
  if (!balls_) balls_ = std::make_unique<BallTextures>(compiler());
  if (ballBrdfsDirty_) {
    balls_->setBrdfs(r);
    ballBrdfsDirty_ = false;
  }
  BallLighting lighting;
  lighting.viewFromWorld = glm::transpose(mat3(view.worldFromCamera));
  lighting.eyeM = vec3(view.worldFromCamera[3]);
  lighting.orthographic = view.orthographic;
  lighting.sun = v.sun;
  if (v.sun) {
    const rdb::RasterSky& s = *r.sky;
    lighting.sunDirWorld = s.sunDirWorld;
    lighting.sunLux = s.sunRadianceCdM2 * float(2.0 * kPi * (1.0 - std::cos(double(s.sunHalfAngleRad))));
  }
  // The sky where it is drawn (sunlight mode) or baked with (light maps); simple mode's directional ambient
  // term as two hemispheres otherwise (none where it is 0).
  if (v.sky && mode != RenderMode::kSimple) {
    lighting.environment = BallLighting::Environment::kSky;
    lighting.skyTexture = gpu_->skyTexture;
    lighting.skyVersion = uint64_t(stats_.skyUploads);
  } else if (maxComponent(r.ambient.upLux) > 0.0f || maxComponent(r.ambient.downLux) > 0.0f) {
    lighting.environment = BallLighting::Environment::kHemispheres;
    lighting.upLux = r.ambient.upLux;
    lighting.downLux = r.ambient.downLux;
  }
  const int made = balls_->update(r, lighting);
  stats_.ballsMade += made;
  stats_.ballsReused += int(r.measuredBrdfs.size()) - made;
  return made;
}

void Renderer::toneMap(const ToneMapSettings& settings) {
  if (!gpu_->floatFbo) throw std::logic_error("Renderer::toneMap before render");
  ToneMapProgram& tone = gpu_->toneMap;
  if (!tone.program) {
    tone.program = compileProgram("tonemap", std::string(toneMapGlsl()) + "\n" + shaders::kLuminanceEncoding,
                                  {{GL_COMPUTE_SHADER, shaders::kToneMapCompute}});
    tone.op = glGetUniformLocation(tone.program, "uOperator");
    tone.exposureScale = glGetUniformLocation(tone.program, "uExposureScale");
    tone.whitePoint = glGetUniformLocation(tone.program, "uWhitePoint");
  }
  glUseProgram(tone.program);
  glUniform1i(tone.op, GLint(settings.op));
  glUniform1f(tone.exposureScale, exposureScale(settings.ev100));
  glUniform1f(tone.whitePoint, settings.whitePoint);
  GLuint luminance = gpu_->floatColor;
  if (bloomSettings_.strength > 0.0f) {
    if (!bloom_) bloom_ = std::make_unique<Bloom>(compiler());
    luminance = bloom_->apply(luminance, width_, height_, exposureScale(settings.ev100), bloomSettings_);
    glUseProgram(tone.program);
  }
  glBindImageTexture(1, luminance, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  glBindImageTexture(0, gpu_->srgbColor, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA8);
  dispatchPerPixel(width_, height_);
  ++stats_.toneMapPasses;
}

void Renderer::present(uint32_t widthPx, uint32_t heightPx) const {
  if (!gpu_->srgbFbo) throw std::logic_error("Renderer::present before toneMap");
  const bool sameSize = widthPx == width_ && heightPx == height_;
  glBlitNamedFramebuffer(gpu_->srgbFbo, 0, 0, 0, GLint(width_), GLint(height_), 0, 0, GLint(widthPx),
                         GLint(heightPx), GL_COLOR_BUFFER_BIT, sameSize ? GL_NEAREST : GL_LINEAR);
}

void Renderer::setSunShadows(const SunShadowSettings& settings) {
  if (settings.visibilityMapTexels < 16 || settings.visibilityMapTexels > 16384) {
    throw std::invalid_argument("the sun's visibility map takes 16 to 16384 texels per side, not " +
                                std::to_string(settings.visibilityMapTexels));
  }
  if (settings.transmittanceMapTexels < 16 || settings.transmittanceMapTexels > 16384) {
    throw std::invalid_argument("the sun's transmittance map takes 16 to 16384 texels per side, not " +
                                std::to_string(settings.transmittanceMapTexels));
  }
  shadowSettings_ = settings;
}

SunShadowCounts Renderer::sunShadowCounts() const {
  return shadows_ ? shadows_->counts() : SunShadowCounts{};
}

void Renderer::setShadowProfiling(bool on) {
  shadowProfiling_ = on;
  if (shadows_) shadows_->setProfiling(on);
}

std::vector<std::pair<std::string, double>> Renderer::sunShadowBuildStagesMs() const {
  return shadows_ ? shadows_->buildStagesMs() : std::vector<std::pair<std::string, double>>{};
}

SunGlassCounts Renderer::sunGlassCounts() const {
  return sunGlass_ ? sunGlass_->counts() : SunGlassCounts{};
}

uint64_t Renderer::shadowVolumeFill() {
  if (!shadows_ || stats_.shadowPasses == 0) return 0;
  glBindFramebuffer(GL_FRAMEBUFFER, gpu_->floatFbo);
  glViewport(0, 0, GLsizei(width_), GLsizei(height_));
  return shadows_->measureFill(lastShadowClipFromWorld_);
}

void Renderer::setAmbientOcclusion(const AmbientOcclusionSettings& settings) {
  if (!(settings.radiusM > 0.0f && settings.radiusM <= 1e4f)) {
    throw std::invalid_argument("the ambient occlusion radius must lie in (0, 10000] metres, not " +
                                std::to_string(settings.radiusM));
  }
  aoSettings_ = settings;
}

void Renderer::setBloom(const BloomSettings& settings) {
  if (!(settings.strength >= 0.0f && settings.strength <= 1.0f)) {
    throw std::invalid_argument("the bloom strength must lie in [0, 1], not " + std::to_string(settings.strength));
  }
  if (!(settings.thresholdExposed > 0.0f && std::isfinite(settings.thresholdExposed))) {
    throw std::invalid_argument("the bloom threshold must be a finite exposed value > 0, not " +
                                std::to_string(settings.thresholdExposed));
  }
  bloomSettings_ = settings;
}

void Renderer::setGlossyReflectionScale(uint32_t scale) {
  if (scale != 0 && scale != 1 && scale != 2 && scale != 4) {
    throw std::invalid_argument("the glossy reflections' pass scale must be 0 (automatic), 1, 2 or 4, not " +
                                std::to_string(scale));
  }
  glossyReflectionScale_ = scale;
}

// The opaque scene's depth for the ambient occlusion: the per-vertex meshes and the opaque and cut-out
// per-fragment draws (cut-outs and clear glass as solid occluders; blended surfaces left out).
void Renderer::drawAmbientOcclusion(const View& view, uint32_t widthPx, uint32_t heightPx) {
  if (!ambientOcclusion_) ambientOcclusion_ = std::make_unique<AmbientOcclusion>(compiler());
  const mat4 clipFromCamera = projection(view, float(widthPx) / float(heightPx));
  ambientOcclusion_->run(clipFromCamera, glm::inverse(view.worldFromCamera), view.orthographic, widthPx, heightPx,
                         aoSettings_.radiusM, [&] {
                           glBindVertexArray(gpu_->vao);
                           auto draw = [](size_t firstIndex, GLsizei count) {
                             glDrawElements(GL_TRIANGLES, count, GL_UNSIGNED_INT,
                                            reinterpret_cast<const void*>(firstIndex * sizeof(uint32_t)));
                           };
                           if (gpu_->perVertexIndexCount > 0) {
                             visibleRanges(gpu_->perVertexChunks, clipFromCamera * glm::inverse(view.worldFromCamera),
                                           NdcRect{}, gpu_->visibleChunks);
                             drawVisibleChunks();
                           }
                           for (const SurfaceDraw& d : gpu_->surfaceDraws) {
                             if (d.blend) continue;
                             setFaceCulling(!d.twoSided);
                             draw(d.firstIndex, d.indexCount);
                           }
                           setFaceCulling(false);
                         });
  glBindTextureUnit(15, ambientOcclusion_->texture());  // shaders::kAoAmbientLookup
}

void Renderer::finish() const {
  glFinish();
}

std::vector<float> Renderer::luminanceRgb() const {
  std::vector<uint32_t> encoded(size_t(width_) * height_ * 2);
  glPixelStorei(GL_PACK_ALIGNMENT, 4);
  glGetTextureImage(gpu_->floatColor, 0, GL_RG_INTEGER, GL_UNSIGNED_INT,
                    GLsizei(encoded.size() * sizeof(uint32_t)), encoded.data());
  std::vector<float> rgb(size_t(width_) * height_ * 3);
  for (uint32_t y = 0; y < height_; ++y) {
    // GL rows start at the bottom.
    const uint32_t* src = encoded.data() + size_t(height_ - 1 - y) * width_ * 2;
    float* dst = rgb.data() + size_t(y) * width_ * 3;
    for (uint32_t x = 0; x < width_; ++x) decodeLuminance(src[2 * x], src[2 * x + 1], dst + 3 * x);
  }
  return rgb;
}

std::vector<uint8_t> Renderer::srgb8() const {
  std::vector<uint8_t> rgba(size_t(width_) * height_ * 4);
  glGetTextureImage(gpu_->srgbColor, 0, GL_RGBA, GL_UNSIGNED_BYTE, GLsizei(rgba.size()), rgba.data());
  std::vector<uint8_t> rgb(size_t(width_) * height_ * 3);
  for (uint32_t y = 0; y < height_; ++y) {
    const uint8_t* src = rgba.data() + size_t(height_ - 1 - y) * width_ * 4;
    uint8_t* dst = rgb.data() + size_t(y) * width_ * 3;
    for (uint32_t x = 0; x < width_; ++x) {
      for (int c = 0; c < 3; ++c) dst[3 * x + c] = src[4 * x + c];
    }
  }
  return rgb;
}

}  // namespace fly::raster
