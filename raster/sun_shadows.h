// The sun's shadows in the GL engine: shadow volumes (Crow 1977; the z-fail stencil test of Everitt and
// Kilgard 2002, "Practical and Robust Stenciled Shadow Volumes") built only from the triangles the sun can
// see, found with a visibility map (the FLY paper, §3: "rendering a scene in an orthographic projection from
// a sunlight view and building a visibility map … encoding index of each triangle by its color").
//
// Casters. Every triangle blocks the sun from both sides (docs/architecture.md), except clear glass
// (rdb::RasterMaterial::transmission > 0: its T(θ) is not drawn, it casts no shadow) and blended surfaces
// (alpha BLEND: they pass 1 − coverage, and cast none). Cut-outs (alpha MASK) cast solid shadows: a shadow
// volume has no holes, so a leaf card or a fence texture's openings shade like the whole triangle.
//
// Why the sun-visible triangles suffice. A point q is in the sun's shadow exactly when the ray from q towards
// the sun hits a caster; the hit farthest from q along that ray lies on a triangle the sun sees, so q lies in
// the shadow prism of a sun-visible triangle (the triangle swept away from the sun to infinity). Conversely
// every point of any caster's prism is shadowed. So the union of the prisms of any set of triangles that
// contains the sun-visible ones is exactly the shadowed region: keeping extra triangles never changes the
// shadow, only its cost.
//
// Which triangles are kept (the visibility map's guarantee). The map is an orthographic view from the sun,
// fitted to the casters' bounds, N × N square texels of side t (SunShadowSettings::visibilityMapTexels); each
// texel holds the caster nearest the sun at the texel's centre. Every point of the image plane lies within
// t/√2 of a texel centre (the corner of its texel), so a disc of radius t/√2 contains a texel centre: a
// triangle whose sun-visible part contains such a disc ("significant") wins that texel and is found. The
// others the map shows are kept too. A triangle it does not show is dropped when
//  - it cannot be seen: its shell (the triangles connected through shared edges, equal positions welded) is
//    closed (every edge used twice, once each way) and faces out (positive signed volume) while the triangle
//    faces away from the sun (or the shell faces in and the triangle faces the sun): the sun's rays reach
//    it only after crossing the shell, taking the shell not to cross itself. (Such a triangle is dropped even
//    where the map shows it: it can only win a texel on its rim or on a coplanar face, by a tie of depths.)
//  - or it lies wholly behind what the map shows over its footprint: where four neighbouring texel centres
//    show one triangle, that triangle covers the square between them (it is convex) at depths no farther than
//    the largest of the four (it is planar); a triangle whose footprint such squares cover and whose nearest
//    vertex is farther from the sun is hidden;
//  - or it passes the depth test (raster/shaders/shadow_glsl.h): at every texel centre c within √2 texels of
//    its footprint, the map shows a surface nearer the sun than the triangle can be within √2 texels of c.
// A triangle whose projected inradius (2 · area / perimeter in the sun's image plane) reaches t/√2 would
// contain such a disc in its visible part, had it one, so it goes straight to the depth test. Sub-texel
// triangles that may be seen (fence bars, small parts) are undecided, and the map is drawn again over the
// square around them at the same N (a finer t), up to twice (kMapLevels in the source) while the square's
// side is at most half the last one's; what is still undecided then takes the depth test. So every
// significant triangle is kept, at each level's t, and so is a larger one whose sun-lit sliver borders what
// the sun sees beyond it (a floor past a wall's edge: the centres there show something farther). What can
// be lost: a triangle the sun sees only through a gap narrower than about a texel between nearer surfaces.
// A closed shell with any kept triangle keeps every triangle that faces the way the sun can see it, so that
// its volume's silhouette is the shell's terminator rather than the rim of what the map happened to show (a
// superset: the shadow is the same). Open shells keep only their own kept triangles: where a large open
// receiver is partly hidden from the sun (a ground under boxes), the rim of its hidden part adds silhouette
// edges that the classic method does not have. The classic method (SunShadowMode::kSunFacing) keeps every
// triangle that faces the sun, and of those facing away a closed shell's that face in and an open shell's that
// the map keeps (its back lit through a gap: a one-sided ceiling under a roof).
//
// Silhouettes. The kept triangles, each turned to face the sun, are counted per undirected edge (equal
// positions welded): +1 where one runs along the edge one way, −1 the other way. Edges with a non-zero count
// are the silhouette of the union of their prisms and are extruded |count| times, so open meshes,
// non-manifold edges and two-sided architectural surfaces need no special case: each prism is closed, and the
// counts sum the prisms' sides. The sides go to the point at infinity away from the sun (w = 0; a directional
// light's prisms all end there, so there is no back cap), drawn with GL_DEPTH_CLAMP; the front caps are the
// kept triangles themselves.
//
// The stencil pass (z-fail): with the scene's depth, the volumes' faces behind the visible surface count +1
// (back faces) and −1 (front faces), so a pixel's count is the number of volumes its surface lies in, right
// with the camera inside a volume too. A lit surface does not shadow itself: its cap is drawn with the
// scene's vertex expression, both invariant (raster/shaders/shadow_glsl.h), without depth clamp as the scene
// is, and pushed back by a polygon offset of a few depth steps, so that the depth test (LESS) counts it as
// behind the surface — which lies on the prism's boundary, outside it — also where a driver's invariant
// positions differ in the last bits (NVIDIA's do). The stencil wraps at 256 overlapping volumes.
//
// All of it runs on the GPU (compute passes, atomic appends, indirect draws); the CPU only welds the edges
// once per geometry and sets uniforms. It is rebuilt when the sun's direction, the geometry or the settings
// change, and never built for a scene without a sun above the horizon.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <initializer_list>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "base/math.h"
#include "rdb/raster_rdb.h"

namespace fly::raster {

enum class SunShadowMode {
  kOff,            // the sun's direct term unshadowed
  // Shadow volumes of the triangles the sun sees (FLY §3's pruning) and those the depth test keeps: fewer,
  // but rebuilt more slowly, and a triangle seen only through a sub-texel gap can be missed.
  kVisibilityMap,
  // Shadow volumes of every triangle facing the sun (the classic method), and of the open shells' triangles
  // facing away those the visibility map keeps: the default.
  kSunFacing,
};

// Whether triangles of material `m` cast the sun's shadows: all but clear glass and blended surfaces.
bool castsSunShadows(const rdb::RasterMaterial& m);

struct SunShadowSettings {
  SunShadowMode mode = SunShadowMode::kSunFacing;
  // Texels per side of the visibility map, [16, 16384] (capped at the driver's largest texture).
  uint32_t visibilityMapTexels = 1024;
  // Texels per side of the sun's transmittance map through clear glass (raster/sun_glass.h), [16, 16384]
  // (capped at the driver's largest texture).
  uint32_t transmittanceMapTexels = 1024;

  bool operator==(const SunShadowSettings&) const = default;
};

// What the last build made, read back from the GPU on request (tests, benchmarks; not per frame).
struct SunShadowCounts {
  uint32_t casterTriangles = 0;   // triangles that can cast (not glass, not blended)
  uint32_t visibleTriangles = 0;  // of them, shown by the visibility map
  uint32_t keptByDepthTest = 0;   // of them, not shown by the map but kept by the depth test
  uint32_t keptTriangles = 0;     // front caps: the triangles whose prisms make the volumes
  uint32_t silhouetteEdges = 0;   // edges with a non-zero count
  uint32_t sideTriangles = 0;     // extruded sides (each silhouette edge |count| times)
  bool lastFrameZFail = false;    // the last stencil pass took z-fail (the near plane may lie in a volume)
  float texelSizeM = 0.0f;        // the visibility map's t
};

class SunShadows {
 public:
  // Compiles a program of (GL shader type, source) stages (the renderer's, which records its name).
  using Compile = std::function<unsigned(const std::string& name, const std::string& defines,
                                         std::initializer_list<std::pair<unsigned, const char*>> stages)>;
  explicit SunShadows(Compile compile);
  ~SunShadows();
  SunShadows(const SunShadows&) = delete;
  SunShadows& operator=(const SunShadows&) = delete;

  // The casters of `rdb` and their welded edges; `positions` is the GL buffer of rdb.positionsM. Then the
  // next build() rebuilds.
  void setGeometry(const rdb::RasterRdb& rdb, unsigned positions);
  // Rebuilds the visibility map and the volumes when the sun direction (unit, towards the sun) or the
  // settings differ from the last build's, or the geometry changed; returns whether it did.
  bool build(const vec3& sunDirWorld, const SunShadowSettings& settings);
  // The stencil pass into the bound framebuffer, whose depth holds the scene's — z-pass without caps when the
  // camera's near plane lies in no volume and no caster is a cut-out, else z-fail (decided on the GPU each
  // frame); leaves the stencil test enabled and the colour and depth writes as they were.
  void drawStencil(const mat4& clipFromWorld);
  // Fragments the volumes rasterise over the framebuffer with neither depth nor stencil test (their fill),
  // counted with a GL_SAMPLES_PASSED query; for benchmarks, not per frame.
  uint64_t measureFill(const mat4& clipFromWorld);
  SunShadowCounts counts() const;
  // GPU time stamps around each stage of build() (GL_TIMESTAMP queries), for benchmarks: off by default.
  // buildStagesMs() waits for the last build's and returns each stage's name and GPU milliseconds.
  void setProfiling(bool on);
  std::vector<std::pair<std::string, double>> buildStagesMs() const;

 private:
  struct Gpu;
  // The caps and sides of the indirect draws at these offsets of the commands buffer.
  void drawVolumes(const mat4& clipFromWorld, intptr_t facingOffset, intptr_t turnedOffset, intptr_t sidesOffset);
  void drawSides(const mat4& clipFromWorld, intptr_t sidesOffset, bool depthClamp);
  std::unique_ptr<Gpu> gpu_;
  Compile compile_;
};

}  // namespace fly::raster
