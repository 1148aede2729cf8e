// The light-texture baker: the irradiance (lux, RGB) averaged over every texel's
// footprint on its mesh, for the TraceRdb's light textures (rdb::TraceLightTexture), as points of the same
// progressive run as the vertex light maps (raytracer/baker.h), then dilated into the padding and made
// consistent across chart seams.
//
// Texels. Each triangle is rasterised conservatively into its atlas: every texel whose square the triangle
// touches. The triangle clipped to the square (Sutherland–Hodgman) is the texel's footprint on it; a texel
// whose footprints have area is baked; one that a triangle reaches into without area (a sliver, a triangle of
// zero UV area) is "empty": reported and filled like the padding (contact along the square's border alone
// does not count). A sample picks a footprint piece by its area in texture
// space and a point uniformly in it, so the texel's value is the mean irradiance over its footprint — what
// the texel stands for — with the shading normal interpolated there.
//
// Leaks. A texel's footprint may cross other geometry (a floor texel under a wall standing on the floor): the
// samples beyond the wall would bring the other side's light into the texel. Every texel has an anchor: the
// point of its footprint at the texel's centre, else the centroid of its largest footprint piece. First the
// anchor is taken out of geometry, as Bakery and Unity's progressive lightmapper do: short probe rays along
// the surface (8 directions, one texel diagonal long, lifted a little off the surface) that hit the back face
// of a one-sided surface (the inside of a closed object) move the anchor just beyond the nearest such face.
// Then every sample point is joined to the anchor by a segment just above the surface; when the segment hits
// anything, the point moves back along it to just before the hit. So every sample lies on the anchor's side
// of all geometry the footprint crosses, and the texel shows the light of that side only. The lift is 10⁻³
// of a texel (at least 16 ray offsets, embree_scene.h), the probes reach 1.5 texels (1/texelsPerMetre each).
// Costs and limits: one more ray per sample; on a convex curved surface whose sagitta over a texel exceeds
// the lift the segment may graze the surface itself, which pulls samples towards the anchor (a narrower
// footprint, never light from elsewhere). The back of a two-sided mesh uses the same anchor, the segment
// lifted to the back.
//
// Dilation. Texels no triangle covers (padding, empty texels) take the mean of their baked or already filled
// 8-neighbours, ring by ring outwards, so that bilinear filtering at a chart's edge never reads unbaked
// texels.
//
// Seams. Where two triangles share an edge (the same two TraceRdb vertices, so the shading is smooth across
// it) but their corners have different UVs, the edge appears twice in the atlas. Bilinear lookups at points
// along both copies (2 per texel of the longer copy) are made equal by Kaczmarz's method: each sweep
// projects the texel values onto "lookup A = lookup B" for one point after another, which from the baked
// values converges to the smallest change (in the least-squares sense) that makes them agree (Castaño,
// "Lightmap seams", 2014, solves the same least-squares problem). 64 sweeps.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "base/color.h"
#include "base/math.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "raytracer/progressive.h"
#include "rdb/trace_rdb.h"

namespace fly::raytracer {

// One baked light texture (of rdb::TraceLightTexture at the same index): per texel, row-major from the top
// row (v = 0), width·height values.
struct LightTexture {
  uint32_t mesh = 0;  // index into TraceRdb::meshes
  uint32_t width = 0;
  uint32_t height = 0;
  // Irradiance on the front (the side of the shading normal) and its standard error, lux per channel. Filled
  // texels (dilated, empty) carry their neighbours' values; seam texels the adjusted mean and the baked
  // error.
  std::vector<Rgb> frontLux;
  std::vector<Rgb> frontStdErrorLux;
  // The back (the side of −normal) of two-sided meshes; empty for one-sided ones.
  std::vector<Rgb> backLux;
  std::vector<Rgb> backStdErrorLux;
  // With a sun (VertexLightMaps::frontSunDirectLux): the part of frontLux / backLux that came straight from
  // the sun's disc, and its standard error, filled and made consistent across seams alike; empty without.
  std::vector<Rgb> frontSunDirectLux;
  std::vector<Rgb> frontSunDirectStdErrorLux;
  std::vector<Rgb> backSunDirectLux;
  std::vector<Rgb> backSunDirectStdErrorLux;
  // With them, the spread of the sun's direct light over each texel's footprint (IrradianceEstimate::
  // sunDirectSpreadLux), filled alike.
  std::vector<Rgb> frontSunDirectSpreadLux;
  std::vector<Rgb> backSunDirectSpreadLux;
  std::vector<uint8_t> baked;  // per texel: 1 where baked, 0 where filled (dilated, empty)
  size_t bakedTexels = 0;      // texels with footprint area: the progressive run's points
  size_t emptyTexels = 0;      // touched by a triangle but without area to sample: filled from neighbours
  size_t seamEdges = 0;        // mesh edges whose two copies in the atlas were made consistent
  uint32_t samples = 0;        // per baked texel (the most any took; its group may have settled earlier)
  // Baked texel sides inside closed objects (TexelSource::isHidden): sampled in the first pass only, left out
  // of the bake's error, their values kept with their errors.
  size_t hiddenTexelSides = 0;
};

// The progressive run's points for the light textures: every baked texel on its front, then on its back for
// two-sided meshes (texture by texture, texel rows from the top). Keeps references to rdb, scene and
// integrator.
class TexelSource final : public SampleSource {
 public:
  // std::invalid_argument when a light texture does not match its mesh (cornerUv size, atlas size 0).
  TexelSource(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator);

  size_t pointCount() const override { return points_.size(); }
  // Per light texture, its fronts and its backs.
  uint32_t groupCount() const override;
  uint32_t groupOf(size_t point) const override;
  bool keepsSunDirect() const override { return integrator_.hasSun(); }
  bool isHidden(size_t point) const override {
    return texels_[points_[point].texel].enclosed[points_[point].back ? 1 : 0];
  }
  PointSample sample(size_t point, SobolSampler& sampler, uint64_t& rays) const override;
  PointSample sample(size_t point, RandomSampler& sampler, uint64_t& rays) const override;

  // The light textures from the estimates of this source's points (pointCount() of them, in point order):
  // baked texels set, the rest dilated, seams made consistent. std::invalid_argument for a wrong count.
  std::vector<LightTexture> finish(std::span<const IrradianceEstimate> estimates) const;

  // The anchor of point's texel, world metres (after the probes moved it out of geometry).
  vec3 anchorM(size_t point) const { return texels_[points_[point].texel].anchorM; }

 private:
  // A triangle of a texel's footprint: part of mesh triangle `triangle`, corners in texel space (x = u·width,
  // y = v·height).
  struct Piece {
    uint32_t triangle = 0;
    vec2 a, b, c;
  };
  struct Texel {
    uint32_t texture = 0;
    uint32_t index = 0;       // j·width + i
    uint32_t firstPiece = 0;  // pieces_[firstPiece … endPiece − 1], pieceCdf_ their cumulative areas
    uint32_t endPiece = 0;
    vec3 anchorM{0.0f};  // front side; the back uses the same point
    uint32_t anchorTriangle = 0;
    // The pieces cover the whole texel square (to kFullSquareTolerance of its area): sampleAt then places
    // its point in the square directly and finds the piece under it, which keeps stratified samples
    // stratified (the same uniform density as choosing a piece by area).
    bool fullSquare = false;
    vec2 cornerTexels{0.0f};  // the square's lower corner in texel space: (i, j)
    // The anchor lies inside a closed object on the front / back (raytracer/enclosure.h): no view reaches
    // that side of the texel. The back of a one-sided texture counts as enclosed.
    bool enclosed[2] = {false, true};
  };
  struct Point {
    uint32_t texel = 0;  // index into texels_
    bool back = false;
  };

  template <class S>
  PointSample sampleAt(size_t point, S& sampler, uint64_t& rays) const;
  // World position and interpolated shading normal (unit, on the front of the geometric normal) at
  // texel-space point x of triangle t of texture k.
  void surfaceAt(uint32_t k, uint32_t t, const vec2& x, vec3& pM, vec3& n) const;
  // The lift off the surface of anchor segments and probes, metres.
  float liftM(uint32_t k, float magnitudeM) const;
  // Chooses the texel's anchor (of its centre and its pieces' centroids, the first not inside a closed
  // object) and sets enclosed.
  void placeAnchor(Texel& texel, bool twoSided);
  // The anchor at texel-space point `at` of piece `piece`, moved out of one-sided objects; returns the
  // geometric normal on the front.
  vec3 anchorAt(Texel& texel, uint32_t piece, const vec2& at);

  const rdb::TraceRdb& rdb_;
  const EmbreeScene& scene_;
  const Integrator& integrator_;
  std::vector<Piece> pieces_;
  std::vector<float> pieceCdf_;  // per piece: the texel's piece areas (texels²) summed up to it
  std::vector<Texel> texels_;    // baked texels, texture by texture, rows from the top
  std::vector<Point> points_;    // fronts, then backs of two-sided meshes
  std::vector<std::vector<uint8_t>> touched_;  // per texture, per texel: a triangle touches it
  std::vector<bool> interiorBackFace_;  // per TraceRdb triangle: its back face is the inside of an object
  float reachM_ = 0.0f;                 // enclosureReachM of the scene
};

}  // namespace fly::raytracer
