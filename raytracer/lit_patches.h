// Where the sun's direct light (and the sky's) is reflected from, per region of the scene: the distributions
// over triangles with which the integrator's next-event estimation to lit patches (raytracer/integrator.h,
// IntegratorSettings::litPatches; docs/lit-patches.md) picks a point y whose directly lit radiance it
// gathers at a path vertex x.
//
// A region (a cell) is a cube of a uniform grid over the scene's box (of side kCellsPerEdgeLength times the
// median triangle edge, at least 1/kCellsAlongLongestSide of the box's longest side: most cubes that a
// surface crosses then hold some of its vertices) together with one of six bins of the normal's dominant
// axis and sign, so that the inside and the outside face of a wall, or a floor and the
// ceiling above it, have cells of their own. A cell's distribution is learnt before the bake from training
// rays: cosine-distributed rays from the mesh vertices whose position and normal fall into the cell (passing
// straight through clear glass), each hit recording its triangle and a one-sample estimate of the direct
// light that the hit point reflects back along the ray (given by the caller: glossy floors send the sun's
// glint to some cells only). Half of a cell's distribution follows those estimates over the triangles hit,
// half the hits spread evenly over the triangles around each hit triangle (sharing a vertex with it) times
// each face's mean radiance along its normal: smooth over a sun patch, of whose small triangles the training
// rays hit some and miss others. A defensive share kHitShare follows the spread hits alone (a triangle whose
// light the estimates missed keeps some probability). Cells whose training rays mostly escape to the sky (more than kMaxEscapeFraction: open
// ground, the outside of a building) get no distribution: direct light dominates there and the integrator's
// path sampling suffices. Any distribution keeps the integrator unbiased (its multiple importance sampling
// weights use the same densities for both strategies); the training only decides how much the variance
// drops.
//
// Within a triangle, the point is uniform by default. A large triangle that the sun lights only in part (a
// floor of two triangles with a sun patch from a window on it) gets a map (kMaxMapLevel): the triangle split
// recursively into 4^L congruent sub-triangles (each corner's and the middle one, L levels), each with a
// probability proportional to the direct light that kMapPointsPerSubTriangle points in it reflect along its
// normal (for the faces that some cell's distribution holds), mixed with kMapUniformShare of the uniform
// choice (a sliver of light between the points keeps some probability), and a point uniform in the chosen
// sub-triangle. Uniform where every point, or none, is lit. The maps do not depend on the cell (the sun's
// light at y does not depend on x); the integrator's weights evaluate the same density (density()), so
// any map keeps the estimate unbiased.
//
// Deterministic: the training rays are Owen-scrambled Sobol' points seeded per cell, traced in parallel
// with results per cell, so the distributions do not depend on the thread count.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <unordered_map>
#include <vector>

#include "base/math.h"
#include "raytracer/embree_scene.h"

namespace fly::raytracer {

// Training rays per cell.
inline constexpr uint32_t kTrainingRaysPerCell = 2048;
// A cell whose training rays escape more often than this gets no distribution.
inline constexpr float kMaxEscapeFraction = 0.5f;
// The defensive share of a cell's distribution given by its training rays' bare hit counts.
inline constexpr float kHitShare = 0.1f;
// Training points inside triangles: a triangle whose longest edge exceeds the cell's side over this also
// trains from points spread over it (the centroids of a regular split into n² sub-triangles, n ≤
// kMaxTrainingSplit), so that every cell that a large triangle crosses learns from points of its own.
inline constexpr float kTrainingPointsPerCellSide = 8.0f;
inline constexpr uint32_t kMaxTrainingSplit = 64;
// Grid cubes along the scene box's longest side, at most.
inline constexpr float kCellsAlongLongestSide = 64.0f;
// A grid cube's side in median triangle edges, at least.
inline constexpr float kCellsPerEdgeLength = 2.0f;
// A triangle's map splits it until the sub-triangles' longest edge is at most the cell's side over
// kMapSubdivisionsPerCell, at most kMaxMapLevel times (4^5 = 1 024 sub-triangles); over all triangles at most
// kMapSubTriangleBudget sub-triangles are evaluated (the deepest levels are lowered until they fit).
inline constexpr float kMapSubdivisionsPerCell = 32.0f;
inline constexpr uint32_t kMaxMapLevel = 5;
inline constexpr uint64_t kMapSubTriangleBudget = uint64_t{1} << 18;
// Points per sub-triangle at which a map evaluates the direct light.
inline constexpr uint32_t kMapPointsPerSubTriangle = 4;
// The share of a map's probability spread uniformly over its sub-triangles.
inline constexpr float kMapUniformShare = 0.1f;

class LitPatches {
 public:
  static constexpr uint32_t kNoCell = std::numeric_limits<uint32_t>::max();

  // A point of the surfaces from which training rays leave: position (m), unit normal of the side, and the
  // magnitude for ray offsets (EmbreeScene::triangleMagnitudeM).
  struct TrainingPoint {
    vec3 p;
    vec3 n;
    float magnitudeM;
  };

  // passesStraight: per triangle, whether training rays pass straight through it (clear glass).
  // radiance(hit, d, seed): an unbiased one-sample estimate, by the seed's own random numbers, of the
  // luminance (cd/m²) of the direct light that the hit point reflects back along the training ray's unit
  // direction d; called from several threads at once.
  // faceRadiance(t, front): an estimate of the luminance that triangle t's front or back face reflects of its
  // direct light along its normal, averaged over the face (smooth where the one-sample estimates are sparse);
  // called from several threads at once, for the faces that training rays hit.
  using RadianceEstimate = std::function<float(const Hit& hit, const vec3& d, uint64_t seed)>;
  using FaceRadiance = std::function<float(uint32_t t, bool front)>;
  // indices, positionsM: the TraceRdb's triangles (which are neighbours, how long their edges are).
  // maps: whether partly lit triangles get maps (above); without, points are uniform on every triangle.
  LitPatches(const EmbreeScene& scene, std::span<const TrainingPoint> points,
             std::span<const uint8_t> passesStraight, std::span<const uint32_t> indices,
             std::span<const vec3> positionsM, const RadianceEstimate& radiance, const FaceRadiance& faceRadiance,
             bool maps = true);

  // The side (m) of the cells that the constructor gives these points and triangles, and the low corner of
  // the points' box (the grid's origin) in boxLoM.
  static float cellSizeM(std::span<const TrainingPoint> points, std::span<const uint32_t> indices,
                         std::span<const vec3> positionsM, vec3* boxLoM = nullptr);

  // Whether any cell has a distribution.
  bool empty() const { return cells_.empty(); }
  size_t cellCount() const { return cells_.size(); }

  // The cell of a point with unit normal n, or kNoCell where none has a distribution.
  uint32_t cellOf(const vec3& p, const vec3& n) const;

  struct Pick {
    uint32_t triangle;
    float pmf;
    float uRemapped;  // u rescaled within the triangle's interval of the distribution, in [0, 1)
  };
  // A triangle by the cell's distribution.
  Pick sample(uint32_t cell, float u) const;
  // The probability with which sample() picks triangle t in the cell (0 for triangles not in it).
  float pmf(uint32_t cell, uint32_t t) const;

  // A point on the picked triangle from u in [0, 1)²: by the triangle's map, uniform without one. Its barycentric coordinates (u, v) of p1 and p2 (as Hit's), and its
  // density on the triangle relative to the uniform one (the area density is pmf × densityFactor / area).
  struct PointPick {
    vec2 barycentric;
    float densityFactor;
  };
  PointPick samplePoint(const Pick& pick, const vec2& u) const;
  // The probability with which sample() and samplePoint() pick triangle t in the cell times the point's
  // density relative to the uniform one on t, at barycentric coordinates b (0 for triangles not in the
  // cell): the patch strategy's area density is this over t's area.
  float density(uint32_t cell, uint32_t t, const vec2& b) const;
  // Triangles with a map.
  size_t mapCount() const { return mapCount_; }

 private:
  uint64_t keyOf(const vec3& p, const vec3& n) const;

  struct Cell {
    uint32_t first;  // entries first … first + count − 1, sorted by triangle
    uint32_t count;
    uint32_t firstGuide;  // its guide table: guides_[firstGuide … firstGuide + count − 1]
  };
  // pmf()'s table: an open-addressed hash (linear probing) from (cell, triangle) to its probability; the
  // slot of key, or the free one where it would go.
  size_t slotOf(uint64_t key) const;
  vec3 originM_{0.0f};
  float cellSizeM_ = 1.0f;
  std::unordered_map<uint64_t, uint32_t> cellOfKey_;
  std::vector<Cell> cells_;
  // A cell's triangle with its probability and the inclusive running sum of the probabilities within the
  // cell, side by side (one cache line for sample()).
  struct Entry {
    float cdf;
    float pmf;
    uint32_t triangle;
  };
  std::vector<Entry> entries_;
  // Per cell, a guide table of `count` entries (Chen & Asau's guide table, as in Devroye, "Non-Uniform
  // Random Variate Generation", 1986, §III.2.4): entry g is the first index whose running sum exceeds
  // g / count, where sample()'s search for u in [g / count, (g + 1) / count) starts; it finds the entry
  // that a binary search would, in O(1) expected steps.
  std::vector<uint32_t> guides_;
  // pmf()'s hash: key (cell << 32 | triangle) and probability, key kEmptySlot where free; a power-of-two
  // size at least twice the entries.
  static constexpr uint64_t kEmptySlot = std::numeric_limits<uint64_t>::max();
  struct Slot {
    uint64_t key;
    float pmf;
  };
  std::vector<Slot> slots_;
  // Per triangle (empty without maps): its map's level (0: none, uniform) and first running sum in mapCdf_
  // (4^level of them, in the order of the sub-triangles' base-4 index, most significant digit the first
  // split).
  struct MapRef {
    uint32_t first;
    uint32_t level;
  };
  std::vector<MapRef> maps_;
  std::vector<float> mapCdf_;
  size_t mapCount_ = 0;
  // The density factor of the map of triangle t (1: none) at b.
  float mapFactor(uint32_t t, const vec2& b) const;
  void buildMaps(const EmbreeScene& scene, std::span<const uint32_t> indices, std::span<const vec3> positionsM,
                 std::span<const uint64_t> faces, const RadianceEstimate& radiance);
};

}  // namespace fly::raytracer
