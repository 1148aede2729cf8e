// The OpenGL engine: uploads a RasterRdb and renders a view into a floating-point framebuffer in cd/m², then
// tone-maps it to sRGB in a last pass (luminance stays linear until then; base/tone_map.h). Modes (the FLY
// paper, §1, §3, §6):
//   simple:    per-vertex Phong from the scene's lights and its sun plus the directional ambient term
//              (rdb/raster_rdb.h); no sky behind the scene
//   lightMap:  per-vertex luminance albedo · E / π from the baked vertex light maps (front or back by facing
//              on two-sided meshes); meshes with a light texture: albedo · E / π per fragment from its texels
//              (bilinear); meshes without a light map are shaded as in simple mode. Where the scene has a sky,
//              every material's specular part reflects the room probe (setRoomProbe, raster/room_probe.h),
//              as in sunlight mode. Without it (no sky, or the probe off), an opaque material with uniform
//              reflection (a glTF metal, whose diffuse is 0) adds reflection · E / π
//              (rdb::RasterMaterial::reflection), i.e. it shows as a rough reflector of its reflectance under
//              the baked irradiance, the limit of a rough conductor, not black; Fresnel (dielectric)
//              reflection adds nothing
//   sunlight:  the sky dome and the sun's disc behind the scene; shading from the light maps where present,
//              otherwise the modified Phong with the sun as a directional light and the daylight ambient term.
//              Over light maps that keep the sun's direct part apart (rdb::RasterVariants::sunDirect):
//              albedo · (E − E_sunDirect) / π plus the sun's direct term (Lambert and Phong lobe, normal maps)
//              for the current sun, so the sun moves over one bake (FLY §3; docs/mixed-lighting.md). The sky is
//              also image-based light (setImageBasedLight): its irradiance in place of the directional ambient
//              term, and the room probe's prefiltered radiance (the sky's without it) by the split sum for
//              every material's specular part
// Curved reflectors (rdb::RasterRdb::cubeReflectors) show cube maps of the scene from their centres
// (raster/cube_reflections.h), captured before the frame only when the scene, its light or the mode changed.
// Where the sun's direct term is drawn (simple and sunlight modes: surfaces without light maps, and light maps
// that keep the sun's direct part apart) it is shadowed (setSunShadows; raster/sun_shadows.h): after the
// scene, a z-fail stencil pass of the sun's shadow volumes, then the pixels inside a volume drawn again at
// equal depth without the sun (uSunNormalLux = 0: the colour target cannot blend). Glass and blended surfaces,
// drawn after that, get the sun unshadowed. The volumes are rebuilt only when the sun's direction, the
// geometry, the materials or the settings change. Clear glass casts no volume: the sun passes it times its
// T(θ) (raster/sun_glass.h), from a transmittance map rendered from the sun (the product of the panes' T per
// texel and the height of the one nearest the sun) that the sun term of every surface behind a pane reads per
// fragment — built, and the FLY_SUN_GLASS variants compiled, only in scenes with clear glass and a sun above
// the horizon, rebuilt only when the sun's direction, the geometry, the materials or the map's size change.
// In every mode, clear glass (rdb::RasterMaterial::transmission) adds T(θ) times what lies behind it: the scene
// is drawn without the glass, copied, and the glass drawn over it reading the copy — only in scenes with glass.
// Textured surfaces (and those with COLOR_0 or alpha coverage: rdb::RasterRdb::shadedPerFragment) are shaded per
// fragment with the same terms: base colour texel × factor × COLOR_0 as the albedo, the emission texel, normal
// maps for the Phong and sun terms, each texture read through a GL sampler object of its glTF sampler (wrap
// modes, magnification and minification filters; anisotropic filtering where the minification is mipmapped); cut-outs (alpha MASK) discard below their cut-off; blended surfaces (BLEND)
// are drawn last, back to front by their mesh's centre, without depth writes, into an RGBA32F "over" target
// composited over the image. They are drawn one material per draw (its textures bound), after the one draw of
// the per-vertex meshes; a scene without them draws exactly as before.
// Materials with a measured BRDF (rdb::RasterMeasuredBrdf) are drawn per fragment from their ball textures
// (raster/ball_texture.h; FLY §4), made before the scene pass where the view's rotation or their light changed,
// in every mode: the ball's lights and environment, the lamps near the material's objects evaluated per pixel
// by the same BRDF (BallSettings::nearLightRadii), plus the ball's sun (0 in the shadow pass, times the glass's
// T); in the light-map modes scaled to the baked irradiance (shaders/scene_glsl.h, flyMeasuredLightMap).
// Only the shader variants a scene's features call for are compiled, on first use. Needs a current context
// (raster/gl_context.h) for its whole life.
// A frame's GPU work, kept lean for GPUs whose graphics pipeline is a small part of the chip (the H100: see
// docs/benchmarks.md, fly-bench-raster): a compute pass writes the background (black, or the sky) into every
// pixel in place of a colour clear; the whole scene is one indexed draw (per-mesh material and flags come per
// vertex; per-fragment surfaces add one draw per material); the tone-map pass is a compute pass. Per frame the
// CPU only sets uniforms of cached programs. The
// float image takes 8 bytes a pixel, not RGBA32F's 16: RGB with a shared exponent in an RG32UI target
// (shaders::kLuminanceEncoding: full float range, each channel within 1.9·10⁻⁶ of the pixel's largest).
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/math.h"
#include "base/tone_map.h"
#include "raster/ambient_occlusion.h"
#include "raster/ball_texture.h"
#include "raster/environment_light.h"
#include "raster/bloom.h"
#include "raster/draw_chunks.h"
#include "raster/sun_glass.h"
#include "raster/sun_shadows.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

class CubeReflections;
class RoomProbe;
class MirrorBlur;

enum class RenderMode { kSimple, kLightMap, kSunlight };

const char* renderModeName(RenderMode m);  // "simple", "lightmap", "sunlight"

// The modes `rdb` supports, best first: light maps (baked), sunlight (a sky or sun), simple (always).
std::vector<RenderMode> supportedModes(const rdb::RasterRdb& rdb);

// A camera's view of the scene.
struct View {
  mat4 worldFromCamera{1.0f};  // rigid; the camera looks down its −Z with +Y up
  bool orthographic = false;
  float yfovRad = 0.8726646f;        // perspective: vertical field of view, (0, π)
  float znearM = 0.05f;              // > 0
  float zfarM = 1e30f;               // > znear; ≥ 1e30 = infinite
  float xmagM = 1.0f, ymagM = 1.0f;  // orthographic half extents (xmag is rescaled to the image's aspect)
};

View viewOfCamera(const rdb::RasterCamera& camera);

// A perspective view (50° vertical) from above and to the side (along +X+Z, 30° up) that shows the whole of
// `boundsM` in an image of aspect `aspect` (width / height).
View framingView(const Bounds3& boundsM, float aspect);

// How many times each piece of work ran, so tests can check that only what changed was redone.
struct RendererStats {
  int geometryUploads = 0;
  int materialTableUploads = 0;
  int materialBlockUploads = 0;
  int lightUploads = 0;
  int skyUploads = 0;
  int scenePasses = 0;  // geometry (and sky) passes into the float framebuffer
  int toneMapPasses = 0;
  int shadowGeometryUploads = 0;  // the sun shadows' caster and edge tables (raster/sun_shadows.h)
  int shadowBuilds = 0;           // visibility map and shadow volumes (re)built: a new sun direction or geometry
  int shadowPasses = 0;           // frames drawn with the shadow volumes' stencil pass
  int sunGlassUploads = 0;  // the clear glass's triangles for the sun's transmittance map (raster/sun_glass.h)
  int sunGlassBuilds = 0;   // transmittance map (re)built: a new sun direction or glass
  int textureUploads = 0;             // material textures (rdb::RasterRdb::textures)
  int samplerObjects = 0;             // GL sampler objects: one per distinct glTF sampler drawn with
  float maxAnisotropy = 1.0f;         // the anisotropic filtering the textures get (1: none)
  int ballsMade = 0;    // measured materials' ball textures made (raster/ball_texture.h)
  int ballsReused = 0;  // balls a frame kept because nothing they depend on changed
  int nearLampPasses = 0;  // frames whose measured materials' near lamps were added per pixel (kNearLampsCompute)
  int reflectionPasses = 0;  // mirrored passes drawn for planar reflectors (RasterRdb::planarReflectors)
  // The pixels of those passes' rectangles, summed (a glossy reflector's pass drawn 1/s as wide and high counts
  // 1/s² of its rectangle: setGlossyReflectionScale), and the last glossy pass's scale s.
  int64_t reflectionPassPixels = 0;
  uint32_t lastGlossyReflectionScale = 0;
  // The per-vertex meshes' triangles drawn, summed over passes: the chunks a pass cannot see are left out
  // (raster/draw_chunks.h).
  int64_t perVertexTrianglesDrawn = 0;
  int cubeCaptures = 0;  // cube reflectors' maps captured (six views each): a new scene, light or mode
  int probeCaptures = 0;  // room probes captured (six views each): a new scene, light, mode or eye position
  int environmentBuilds = 0;  // the sky's image-based light maps (re)built: a new sky or sun (EnvironmentLight)
  std::vector<std::string> programs;  // the compiled programs, e.g. "scene+lightmap+twosided", "sky", "tonemap"
};

// The most anisotropic filtering material textures get, where the driver has it (GL 4.6, or
// GL_ARB_/EXT_texture_filter_anisotropic): 16 samples, the usual ceiling.
inline constexpr float kMaxAnisotropy = 16.0f;

// The sky's image-based light maps: a 64² source and radiance cube with 6 levels (α = 0, 0.04, … 1) of 256
// GGX samples a texel, a 16² irradiance cube summed over the 32² level, a 64² split-sum table (at 32² its
// bilinear interpolation overstates a metal's albedo at 85° from the normal by 2 %: the table's steepest part
// lies at grazing angles; tests/engines/material_albedo_test.cpp) — a sky is smooth, and a change of time
// rebuilds them in a few milliseconds on a GPU.
inline constexpr EnvironmentSettings kSkyEnvironmentSettings{.cubePx = 64, .radianceLevels = 6,
                                                             .prefilterSamples = 256, .irradiancePx = 16,
                                                             .irradianceQuadPx = 32, .tablePx = 64,
                                                             .tableSamples = 4096};

class Renderer {
 public:
  Renderer();  // the context must be current
  ~Renderer();
  Renderer(const Renderer&) = delete;
  Renderer& operator=(const Renderer&) = delete;

  // Uploads all of `rdb` (kept by reference: it must outlive the renderer or the next upload).
  void upload(const rdb::RasterRdb& rdb);
  // Re-uploads what updateRasterRdb re-made.
  void update(const rdb::RasterRdb& rdb, const rdb::RasterRdbChanges& changes);

  // Renders `view` in `mode` into the float framebuffer, widthPx × heightPx (1..16384). std::invalid_argument
  // for a mode the scene does not support (supportedModes) or a bad size.
  void render(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx);
  // The tone-map pass over the last render (no geometry is drawn).
  void toneMap(const ToneMapSettings& settings);

  uint32_t width() const { return width_; }
  uint32_t height() const { return height_; }
  // The last render: linear RGB luminance in cd/m², 3 floats per pixel, rows from the top (decoded from
  // shaders::kLuminanceEncoding: each channel within 1.9·10⁻⁶ of the pixel's largest channel).
  std::vector<float> luminanceRgb() const;
  // The last tone-map pass: sRGB-encoded RGB8, 3 bytes per pixel, rows from the top.
  std::vector<uint8_t> srgb8() const;
  // Copies the last tone-map pass into the default framebuffer (a window's back buffer), scaled to fill
  // widthPx × heightPx.
  void present(uint32_t widthPx, uint32_t heightPx) const;

  // The most samples anisotropic filtering takes on material textures, ≥ 1 (1: trilinear only); capped at
  // kMaxAnisotropy and the driver's limit (stats().maxAnisotropy says what applies). Default: that cap.
  void setMaxAnisotropy(float samples);

  // How the sun's direct term is shadowed (raster/sun_shadows.h); std::invalid_argument for a visibility map
  // size outside [16, 16384]. Default: the classic volumes (SunShadowSettings).
  void setSunShadows(const SunShadowSettings& settings);
  // The luminance (cd/m²) at which emission given as a display colour (rdb::RasterMaterial::emissionDisplay)
  // shows its colour: the exposure's white, 1.2 · 2^EV100 (base/tone_map.h). 0 (the default) shows it black;
  // a caller with automatic exposure meters a frame without it first (it would otherwise move the meter).
  void setDisplayWhite(float cdM2) { displayWhiteCdM2_ = std::isfinite(cdM2) && cdM2 > 0.0f ? cdM2 : 0.0f; }
  bool hasDisplayEmission() const;
  // What the last shadow build made (read back from the GPU; zeros before the first).
  SunShadowCounts sunShadowCounts() const;
  // For benchmarks: GPU time stamps around the stages of each shadow build (off by default), and the last
  // build's stages in GPU milliseconds (empty when none was profiled).
  void setShadowProfiling(bool on);
  std::vector<std::pair<std::string, double>> sunShadowBuildStagesMs() const;
  // What the last transmittance map through clear glass drew (raster/sun_glass.h; zeros before the first).
  SunGlassCounts sunGlassCounts() const;
  // The fragments the last frame's shadow volumes rasterise with neither depth nor stencil test (their fill,
  // GL_SAMPLES_PASSED); 0 when it drew none. For benchmarks: it draws the volumes again.
  uint64_t shadowVolumeFill();

  // The measured materials' ball textures' size and environment quadrature (raster/ball_texture.h);
  // std::invalid_argument out of range. Default: BallSettings{}.
  void setBallSettings(const BallSettings& settings);
  // Makes the measured materials' ball textures for `view` in `mode` where what they depend on changed (the
  // view's rotation, the lights, the environment, the BRDFs); render() does this itself. Returns how many it
  // made. For benchmarks, which time this pass alone.
  int makeBalls(const View& view, RenderMode mode);
  // A layer of the ball textures, as last made (BallTextures::readLayer); for tests.
  std::vector<float> ballLayer(uint32_t layer) const;

  // Sunlight mode's image-based light (on by default): the sky image (the sky and ground, without the sun's
  // disc, which stays a directional light) is the environment (raster/environment_light.h), convolved when
  // the sky changes (a new sky, time or sun) at the first sunlight frame after it. Its irradiance replaces the
  // directional ambient term on surfaces without a light map, and its prefiltered radiance by the split sum
  // adds the specular part of every material with a reflection (RasterMaterial::environmentF90; light-mapped
  // ones too, whose light map holds the diffuse part), per fragment, except measured BRDFs (their balls) and
  // planar reflectors that show a mirrored pass. Off: the directional ambient term, as in simple mode.
  void setImageBasedLight(bool on);
  // Light-map and sunlight modes' room probe (on by default; raster/room_probe.h): where a material reflects
  // an environment (RasterMaterial::environmentF90) and the scene has a sky, a cube map captured at the eye,
  // with the box it sees, is the specular environment of every surface (parallax-corrected) in place of the
  // open sky's, so that surfaces indoors reflect the room; the image-based light then also lights light-map
  // mode (its irradiance on surfaces without a light map, the probe's radiance for the specular part, which
  // light-map mode otherwise leaves out). Off: sunlight mode reflects the sky times the light map's specular
  // occlusion, light-map mode reflects nothing.
  void setRoomProbe(bool on);
  // The environment maps' sizes and sample counts; std::invalid_argument out of range (EnvironmentSettings).
  // Default: kSkyEnvironmentSettings.
  void setEnvironmentSettings(const EnvironmentSettings& settings);
  // The last built environment maps (null before the first sunlight frame with image-based light); for tests.
  const EnvironmentLight* environmentLight() const { return environment_.get(); }
  // Simple mode's screen-space ambient occlusion of the ambient term (raster/ambient_occlusion.h);
  // std::invalid_argument for a radius outside (0, 1e4] m. Default: off.
  void setAmbientOcclusion(const AmbientOcclusionSettings& settings);
  // Glare around the sun and bright highlights in the tone-map pass (raster/bloom.h), on the luminance before
  // the display transform; luminanceRgb() stays without it. std::invalid_argument for a strength outside
  // [0, 1] or a threshold ≤ 0. Default: off.
  void setBloom(const BloomSettings& settings);

  // How much coarser than the image a glossy planar reflector's mirrored pass is drawn per axis: 0 (the
  // default) chooses from the lobe, 1, 2 or 4 force that (where the image's size is a multiple of it; else the
  // largest power of two below that divides it). The pass is blurred by at least its own pixels, so the
  // automatic choice takes s (≤ 4) no wider than an eighth of the spread r = 2α · pixels per tan of the sky
  // (the widest: D / (E + D) → 1, α the lobe's narrow width): the image of what lies at D ≥ E / 7 behind the
  // mirror, E the eye's distance, is blurred wider than s and loses nothing; nearer, where the lobe spreads
  // less than s, it shows s-wide, and an object a few pass pixels small is rasterised coarsely: its reflected
  // light is off by up to the share of its outline's pass pixels (docs/reflections.md). Perspective views
  // only; fogged reflectors (their fog reads the pass's depth per pixel) and scenes with frosted glass or
  // measured materials' near lamps (their passes read positions from the target's size) draw full passes.
  // std::invalid_argument for other values.
  void setGlossyReflectionScale(uint32_t scale);
  // Waits until the GPU has finished all work issued so far (glFinish), for timing with a wall clock.
  void finish() const;

  const RendererStats& stats() const { return stats_; }

 private:
  struct Gpu;
  struct SceneProgram;
  // Compiles and links one program of (GL shader type, source) stages, each prefixed by `defines`.
  unsigned compileProgram(const std::string& name, const std::string& defines,
                          std::initializer_list<std::pair<unsigned, const char*>> stages);
  const SceneProgram& sceneProgram(uint32_t variant);
  SunShadows::Compile compiler();  // compileProgram, for SunShadows and SunGlassMap
  unsigned samplerFor(const rdb::RasterTextureRef& ref);
  void uploadGeometry();
  void uploadLightTextures();
  void uploadTextures();
  void uploadMaterials();
  void uploadDraws();
  void uploadLights();
  void uploadSky();
  void resize(uint32_t widthPx, uint32_t heightPx);
  // One pass of the scene into the float target; a mirrored pass (drawReflections) clips at the mirror's plane
  // (world, (n, −d): points with n·p ≥ d are kept) and leaves out the mirror itself.
  struct MirrorPass {
    vec4 planeWorld;
    uint32_t reflector;
    NdcRect rect;  // the mirror's scissor rectangle: the pass draws nothing outside it
    int rectPx[4];  // the same in the pass's pixels: x, y, width, height
  };
  // A face of a cube reflector's capture (captureCubeReflectors) leaves out the reflector.
  struct CubePass {
    uint32_t reflector;
  };
  void renderPass(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx, const MirrorPass* mirrorPass,
                  const CubePass* cubePass);
  void drawVisibleChunks();
  void captureCubeReflectors(RenderMode mode);
  void captureRoomProbe(const vec3& eyeM, RenderMode mode);
  // Before the glass pass of a scene with frosted glass: the copy of the image behind it decoded into a
  // mipmapped texture (unit 3), a copy of the depth buffer (unit 1) and the split sum's table (unit 14;
  // shaders::kSceneVertex, kSceneFragment, FLY_FROSTED).
  void prepareFrostedGlass();
  // An RG32UI luminance image (kLuminanceEncoding) of the target's size decoded into `target` (RGBA32F with
  // a box-filtered mip chain, made at the first call), and the depth buffer's rectangle (x, y, width, height)
  // copied into `target` (made likewise, of the target's size; outside the rectangle undefined: readers read
  // inside it).
  void decodeBlurred(unsigned source, unsigned& target);
  void copyDepth(unsigned& target, int x, int y, int width, int height);
  void drawReflections(const View& view, RenderMode mode, uint32_t widthPx, uint32_t heightPx);
  void drawAmbientOcclusion(const View& view, uint32_t widthPx, uint32_t heightPx);
  // The measured materials' near lamps evaluated once per pixel after the opaque draws (shaders::
  // kNearLampsCompute): prepareNearLamps, after the balls are made, uploads every BRDF's lamps and readies
  // the opaque draws' record images; false when no measured material has a near lamp. drawNearLamps adds
  // the lamps to the image.
  bool prepareNearLamps();
  void drawNearLamps(const mat4& clipFromWorld, const vec3& eyeM, const vec3& viewDirWorld, bool orthographic,
                     bool goniometric, uint32_t widthPx, uint32_t heightPx);

  std::unique_ptr<Gpu> gpu_;
  std::unique_ptr<SunShadows> shadows_;  // made at the first frame that draws the sun's shadows
  SunShadowSettings shadowSettings_;
  float displayWhiteCdM2_ = 0.0f;
  bool shadowProfiling_ = false;
  bool shadowGeometryDirty_ = true;
  std::unique_ptr<SunGlassMap> sunGlass_;  // made at the first frame that draws the sun through clear glass
  bool sunGlassDirty_ = true;
  std::unique_ptr<EnvironmentLight> environment_;  // made at the first sunlight frame with image-based light
  EnvironmentSettings environmentSettings_ = kSkyEnvironmentSettings;
  bool imageBasedLight_ = true;
  bool environmentDirty_ = true;
  std::unique_ptr<CubeReflections> cubes_;  // made at the first frame of a scene with cube reflectors
  bool cubesDirty_ = true;
  RenderMode cubeMode_ = RenderMode::kSimple;
  std::unique_ptr<RoomProbe> probe_;  // made at the first frame that needs it
  bool roomProbe_ = true;             // setRoomProbe
  bool probeDirty_ = true;            // the scene, its light or the image-based light changed
  bool probeActive_ = false;          // this frame uses the probe
  bool capturingProbe_ = false;       // a pass of the probe's capture
  RenderMode probeMode_ = RenderMode::kSimple;
  std::unique_ptr<BallTextures> balls_;  // made at the first frame of a scene with measured materials
  bool ballBrdfsDirty_ = true;
  AmbientOcclusionSettings aoSettings_;
  std::unique_ptr<AmbientOcclusion> ambientOcclusion_;  // made at the first frame that draws it
  BloomSettings bloomSettings_;
  std::unique_ptr<Bloom> bloom_;  // made at the first tone-map pass with bloom
  std::unique_ptr<MirrorBlur> mirrorBlur_;  // made at the first frame showing a glossy planar reflector
  uint32_t glossyReflectionScale_ = 0;      // setGlossyReflectionScale
  // Per planar reflector of an anisotropic material: its lobe's tangent axis t' (world, unit, in its plane:
  // the mean over its vertices of the tangent turned by the material's rotation), made when the scene or its
  // materials change (empty: to be made).
  std::vector<vec3> reflectorTangents_;
  std::vector<char> materialCasts_;  // per material: castsSunShadows
  mat4 lastShadowClipFromWorld_{1.0f};
  const rdb::RasterRdb* rdb_ = nullptr;
  uint32_t width_ = 0, height_ = 0;
  RendererStats stats_;
};

}  // namespace fly::raster
