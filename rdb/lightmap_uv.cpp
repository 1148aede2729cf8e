// Light-map UV generation in five steps:
//  1. Charts: triangles are welded by position and grown into charts over shared edges while their
//     normals stay within 30° of the chart's mean normal.
//  2. Each chart is projected onto the plane of its area-weighted mean normal (isometric for a planar
//     chart); a chart whose projection folds, stretches texels more than 2× or overlaps itself is split
//     until none does.
//  3. Each chart is turned to its minimum-area enclosing rectangle (rotating calipers on its convex hull).
//  4. The rectangles, enlarged by the padding, are packed into the atlas with a skyline packer; the
//     density is reduced uniformly when they do not fit into the largest atlas.
//  5. UVs: chart coordinates in metres × density give texels, divided by the atlas size give UVs.
// Geometry is computed in double precision from the float input, so that a 1 mm detail 10 km from the origin
// projects as accurately as one at the origin; only the final UVs are rounded to float.
#include "rdb/lightmap_uv.h"

#include <algorithm>
#include <cassert>
#include <cfloat>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>

namespace fly::rdb {
namespace {

constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

// Step 1. Vertices closer than 1e-6 of the mesh's bounding-box diagonal are one point when looking for shared
// edges (the input splits vertices at normal and UV seams, exporters round coordinates), but only when also
// closer than 1e-3 of either vertex's shortest edge: a millimetre detail in a 10 km mesh keeps its shape.
constexpr double kWeldPerMeshSize = 1e-6;
constexpr double kWeldPerEdge = 1e-3;
// A triangle whose height is at most one float rounding step (ulp) of its coordinates is degenerate: rounding
// alone can make or unmake it, so its normal is noise.
constexpr double kDegenerateUlps = 1.0;
// More triangles than this on one edge are not a surface but a fan of fins: they do not join each other.
constexpr size_t kMaxPairedUses = 16;
// A triangle joins a chart while its normal is within 30° of the chart's mean normal: flat faces stay whole,
// curved surfaces are cut into pieces that projection stretches by about 1/cos 30° ≈ 1.15 at their rims.
constexpr double kCosChartAngle = 0.86602540378443865;
// Step 2. A chart is split when a triangle's normal is more than 60° from the projection normal: its texels
// would be stretched more than 2× (beyond 90° it folds over). The mean that growing compares with drifts.
constexpr double kCosMaxProjection = 0.5;
// Two triangles of a chart overlap in its plane when they intersect deeper than 1 % of their shortest edge;
// shallower contacts are T-junctions and welded vertices that do not coincide (≤ 2 × kWeldPerEdge apart).
constexpr double kOverlapPerEdge = 1e-2;
// Step 4. A chart lies at least 1/16 texel inside its rectangle, so that rounding UVs to float (by at most
// 2^-25 of the atlas size: 1.2e-4 texels at 4096) cannot move a corner into the padding.
constexpr double kChartMarginTexels = 1.0 / 16.0;

double cross2(const dvec2& a, const dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// The triangles with their normals, in double precision.
struct Triangles {
  std::span<const vec3> positions;
  std::span<const uint32_t> indices;
  size_t count = 0;
  std::vector<dvec3> cross;         // (b − a) × (c − a): the normal times twice the area, m²
  std::vector<uint8_t> degenerate;  // 1 where the normal is noise

  uint32_t corner(size_t t, size_t k) const { return indices[3 * t + k]; }
  dvec3 position(uint32_t v) const { return dvec3(positions[v]); }
};

Triangles measureTriangles(std::span<const vec3> positions, std::span<const uint32_t> indices) {
  Triangles tris{positions, indices, indices.size() / 3, {}, {}};
  tris.cross.resize(tris.count);
  tris.degenerate.resize(tris.count);
  for (size_t t = 0; t < tris.count; ++t) {
    const dvec3 a = tris.position(tris.corner(t, 0));
    const dvec3 b = tris.position(tris.corner(t, 1));
    const dvec3 c = tris.position(tris.corner(t, 2));
    tris.cross[t] = glm::cross(b - a, c - a);
    const double longestEdge = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    const dvec3 magnitude = glm::max(glm::abs(a), glm::max(glm::abs(b), glm::abs(c)));
    const double ulp = FLT_EPSILON * std::max({magnitude.x, magnitude.y, magnitude.z});
    const double height = longestEdge > 0.0 ? glm::length(tris.cross[t]) / longestEdge : 0.0;
    tris.degenerate[t] = height <= kDegenerateUlps * ulp ? 1 : 0;
  }
  return tris;
}

// Step 1: the representative of each used vertex after welding (an earlier vertex within the tolerance of
// both); kNone for unused vertices. Representatives are hashed on grids whose cells are twice the largest
// tolerance of their level, levels a factor of 16 apart: since a vertex's tolerance is tied to its shortest
// edge, a cell holds few vertices even where a small, finely tessellated detail sits in a large mesh.
std::vector<uint32_t> weldVertices(const Triangles& tris) {
  const size_t vertexCount = tris.positions.size();
  std::vector<uint8_t> used(vertexCount, 0);
  for (uint32_t v : tris.indices) used[v] = 1;
  dvec3 lo(std::numeric_limits<double>::infinity());
  dvec3 hi(-std::numeric_limits<double>::infinity());
  for (uint32_t v = 0; v < vertexCount; ++v) {
    if (!used[v]) continue;
    lo = glm::min(lo, tris.position(v));
    hi = glm::max(hi, tris.position(v));
  }
  const double meshTolerance = kWeldPerMeshSize * glm::length(hi - lo);
  std::vector<uint32_t> representative(vertexCount, kNone);
  if (!(meshTolerance > 0.0)) {  // every used vertex is at the same place
    const uint32_t first = uint32_t(std::find(used.begin(), used.end(), 1) - used.begin());
    for (uint32_t v = 0; v < vertexCount; ++v) representative[v] = used[v] ? first : kNone;
    return representative;
  }
  std::vector<double> tolerance(vertexCount, meshTolerance);
  for (size_t t = 0; t < tris.count; ++t) {
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t a = tris.corner(t, k);
      const uint32_t b = tris.corner(t, (k + 1) % 3);
      const double length = glm::length(tris.position(a) - tris.position(b));
      if (length > 0.0) {
        tolerance[a] = std::min(tolerance[a], kWeldPerEdge * length);
        tolerance[b] = std::min(tolerance[b], kWeldPerEdge * length);
      }
    }
  }
  // Level l ∈ [−8, 0] holds tolerances below 16^(l+1) times the mesh tolerance; the lowest also holds smaller
  // ones, down to 0, and keeps cell indices within 64 bits (16^−7 · 1e-6 of the diagonal per cell).
  constexpr int kLowestLevel = -8;
  auto levelOf = [&](double tol) {
    const double level = std::floor(std::log2(tol / meshTolerance) / 4.0);
    return tol > 0.0 ? std::clamp(int(level), kLowestLevel, 0) : kLowestLevel;
  };
  auto levelLimit = [&](int level) { return std::ldexp(meshTolerance, 4 * (level + 1)); };
  struct Cell {
    int64_t x, y, z;
    int level;
    bool operator==(const Cell&) const = default;
  };
  struct CellHash {
    size_t operator()(const Cell& c) const {  // multiplicative hashing (Knuth, TAOCP vol. 3, §6.4)
      return size_t((uint64_t(c.x) * 0x9E3779B97F4A7C15ull) ^ (uint64_t(c.y) * 0xC2B2AE3D27D4EB4Full) ^
                    (uint64_t(c.z) * 0x165667B19E3779F9ull) ^ uint64_t(c.level - kLowestLevel));
    }
  };
  std::unordered_map<Cell, uint32_t, CellHash> cellHead;  // the last representative added to a cell
  cellHead.reserve(vertexCount);
  std::vector<uint32_t> nextInCell(vertexCount, kNone);
  uint32_t levelsUsed = 0;  // bit l − kLowestLevel
  for (uint32_t v = 0; v < vertexCount; ++v) {
    if (!used[v]) continue;
    const dvec3 p = tris.position(v);
    auto findMatch = [&]() {
      for (int level = kLowestLevel; level <= 0; ++level) {
        if (!(levelsUsed >> (level - kLowestLevel) & 1u)) continue;
        const double cellSize = 2.0 * levelLimit(level);
        const double radius = std::min(tolerance[v], levelLimit(level));
        const dvec3 from = glm::floor((p - lo - radius) / cellSize);
        const dvec3 to = glm::floor((p - lo + radius) / cellSize);
        for (double x = from.x; x <= to.x; ++x) {
          for (double y = from.y; y <= to.y; ++y) {
            for (double z = from.z; z <= to.z; ++z) {
              const auto it = cellHead.find({int64_t(x), int64_t(y), int64_t(z), level});
              if (it == cellHead.end()) continue;
              for (uint32_t r = it->second; r != kNone; r = nextInCell[r]) {
                const dvec3 d = glm::abs(tris.position(r) - p);
                if (std::max({d.x, d.y, d.z}) <= std::min(tolerance[v], tolerance[r])) return r;
              }
            }
          }
        }
      }
      return kNone;
    };
    const uint32_t match = findMatch();
    if (match != kNone) {
      representative[v] = match;
      continue;
    }
    representative[v] = v;
    const int level = levelOf(tolerance[v]);
    levelsUsed |= 1u << (level - kLowestLevel);
    const dvec3 cell = glm::floor((p - lo) / (2.0 * levelLimit(level)));
    uint32_t& head =
        cellHead.try_emplace(Cell{int64_t(cell.x), int64_t(cell.y), int64_t(cell.z), level}, kNone)
            .first->second;
    nextInCell[v] = head;
    head = v;
  }
  return representative;
}

// Step 1: neighbour[3t + k] is the triangle across edge k (corners k, k+1) of triangle t, kNone on a border.
// Neighbours use their welded edge in opposite directions (consistently oriented). Where more than two
// triangles use an edge (a back face sharing a wall's vertices, a duplicate, a fin), uses are paired best
// first by how nearly their triangles face the same way, so that the front and the back of a two-sided wall
// each stay connected; an edge with more than kMaxPairedUses uses stays a border (the pairing is cubic).
// Degenerate triangles have no neighbours.
std::vector<uint32_t> findNeighbours(const Triangles& tris, const std::vector<uint32_t>& representative) {
  struct EdgeUse {
    uint64_t key;     // the welded end points, smaller first
    uint32_t corner;  // 3t + k
    bool forward;     // the edge runs from the smaller to the larger end point
  };
  std::vector<EdgeUse> uses;
  uses.reserve(3 * tris.count);
  for (size_t t = 0; t < tris.count; ++t) {
    if (tris.degenerate[t]) continue;
    for (size_t k = 0; k < 3; ++k) {
      const uint32_t a = representative[tris.corner(t, k)];
      const uint32_t b = representative[tris.corner(t, (k + 1) % 3)];
      if (a == b) continue;
      uses.push_back({(uint64_t(std::min(a, b)) << 32) | std::max(a, b), uint32_t(3 * t + k), a < b});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return x.key != y.key ? x.key < y.key : x.corner < y.corner;
  });
  auto facing = [&](uint32_t cornerA, uint32_t cornerB) {
    const dvec3& a = tris.cross[cornerA / 3];
    const dvec3& b = tris.cross[cornerB / 3];
    return glm::dot(a, b) / (glm::length(a) * glm::length(b));
  };
  std::vector<uint32_t> neighbour(3 * tris.count, kNone);
  for (size_t i = 0; i < uses.size();) {
    size_t end = i + 1;
    while (end < uses.size() && uses[end].key == uses[i].key) ++end;
    while (end - i <= kMaxPairedUses) {
      size_t bestA = end;
      size_t bestB = end;
      double bestFacing = -std::numeric_limits<double>::infinity();
      for (size_t a = i; a < end; ++a) {
        if (neighbour[uses[a].corner] != kNone) continue;
        for (size_t b = a + 1; b < end; ++b) {
          if (uses[b].forward == uses[a].forward || neighbour[uses[b].corner] != kNone) continue;
          const double f = facing(uses[a].corner, uses[b].corner);
          if (f > bestFacing) {
            bestFacing = f;
            bestA = a;
            bestB = b;
          }
        }
      }
      if (bestA == end) break;
      neighbour[uses[bestA].corner] = uses[bestB].corner / 3;
      neighbour[uses[bestB].corner] = uses[bestA].corner / 3;
    }
    i = end;
  }
  return neighbour;
}

// Step 1: region growing, breadth first, seeded by the largest remaining triangle. Returns each
// non-degenerate triangle's chart (kNone for degenerate ones) and sets chartCount.
std::vector<uint32_t> growCharts(const Triangles& tris, const std::vector<uint32_t>& neighbour,
                                 uint32_t& chartCount) {
  std::vector<double> doubleArea(tris.count);
  std::vector<uint32_t> seeds;
  for (size_t t = 0; t < tris.count; ++t) {
    doubleArea[t] = glm::length(tris.cross[t]);
    if (!tris.degenerate[t]) seeds.push_back(uint32_t(t));
  }
  std::sort(seeds.begin(), seeds.end(), [&](uint32_t a, uint32_t b) {
    return doubleArea[a] != doubleArea[b] ? doubleArea[a] > doubleArea[b] : a < b;
  });
  std::vector<uint32_t> chart(tris.count, kNone);
  std::vector<uint32_t> queue;
  chartCount = 0;
  for (uint32_t seed : seeds) {
    if (chart[seed] != kNone) continue;
    const uint32_t c = chartCount++;
    chart[seed] = c;
    dvec3 normalSum = tris.cross[seed];
    queue.assign(1, seed);
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t t = queue[head];
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t u = neighbour[3 * size_t(t) + k];
        if (u == kNone || chart[u] != kNone) continue;
        if (glm::dot(tris.cross[u], normalSum) < kCosChartAngle * doubleArea[u] * glm::length(normalSum))
          continue;
        chart[u] = c;
        normalSum += tris.cross[u];
        queue.push_back(u);
      }
    }
  }
  return chart;
}

// The plane a chart is projected onto: the area-weighted mean normal n with a tangent frame (t, b), t × b =
// n, so that triangles facing n keep their counter-clockwise orientation in (t, b) coordinates.
struct ChartPlane {
  dvec3 origin;
  dvec3 t;
  dvec3 b;

  dvec2 project(const dvec3& p) const { return {glm::dot(p - origin, t), glm::dot(p - origin, b)}; }
};

ChartPlane chartPlane(const Triangles& tris, std::span<const uint32_t> members) {
  dvec3 normalSum(0.0);
  for (uint32_t t : members) {
    if (!tris.degenerate[t]) normalSum += tris.cross[t];
  }
  const double length = glm::length(normalSum);
  const dvec3 n = length > 0.0 ? normalSum / length : dvec3(0.0, 0.0, 1.0);
  // Tangent from Duff et al. 2017, "Building an Orthonormal Basis, Revisited" (no branch on the normal's
  // direction other than its z sign).
  const double sign = std::copysign(1.0, n.z);
  const double a = -1.0 / (sign + n.z);
  const dvec3 t(1.0 + sign * n.x * n.x * a, sign * n.x * n.y * a, -sign * n.x);
  return {tris.position(tris.corner(members[0], 0)), t, glm::cross(n, t)};
}

double shortestEdge(const dvec2* tri) {
  return std::min({glm::length(tri[1] - tri[0]), glm::length(tri[2] - tri[1]), glm::length(tri[0] - tri[2])});
}

// Separating-axis test of two triangles in the plane (each edge normal is a candidate axis): true when their
// interiors intersect deeper than kOverlapPerEdge of their shortest edge.
bool trianglesOverlap(const dvec2* a, const dvec2* b) {
  const double tolerance = kOverlapPerEdge * std::min(shortestEdge(a), shortestEdge(b));
  for (const dvec2* tri : {a, b}) {
    for (size_t k = 0; k < 3; ++k) {
      const dvec2 edge = tri[(k + 1) % 3] - tri[k];
      const dvec2 axis = dvec2(-edge.y, edge.x) / glm::length(edge);
      double minA = std::numeric_limits<double>::infinity();
      double maxA = -minA;
      double minB = minA;
      double maxB = -minA;
      for (size_t i = 0; i < 3; ++i) {
        minA = std::min(minA, glm::dot(a[i], axis));
        maxA = std::max(maxA, glm::dot(a[i], axis));
        minB = std::min(minB, glm::dot(b[i], axis));
        maxB = std::max(maxB, glm::dot(b[i], axis));
      }
      if (maxA <= minB + tolerance || maxB <= minA + tolerance) return false;
    }
  }
  return true;
}

// Whether any two of the triangles (corners q[3i], q[3i+1], q[3i+2]) overlap. A uniform grid with about one
// cell per triangle finds the candidate pairs; a pair is tested only in the cell holding the lower corner of
// the intersection of their bounding boxes, so once.
bool anyOverlap(const std::vector<dvec2>& q) {
  const size_t n = q.size() / 3;
  if (n < 2) return false;
  dvec2 lo(std::numeric_limits<double>::infinity());
  dvec2 hi(-std::numeric_limits<double>::infinity());
  for (const dvec2& p : q) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  const dvec2 extent = glm::max(hi - lo, dvec2(std::numeric_limits<double>::min()));
  const double cellsX = std::clamp(std::sqrt(double(n) * extent.x / extent.y), 1.0, 1024.0);
  const double cellsY = std::clamp(double(n) / cellsX, 1.0, 1024.0);
  const size_t nx = size_t(cellsX);
  const size_t ny = size_t(cellsY);
  const dvec2 cellsPerMetre = dvec2(double(nx), double(ny)) / extent;
  auto cellOf = [&](const dvec2& p) {
    const dvec2 c = (p - lo) * cellsPerMetre;
    return std::pair<size_t, size_t>(std::min(size_t(std::max(c.x, 0.0)), nx - 1),
                                     std::min(size_t(std::max(c.y, 0.0)), ny - 1));
  };
  std::vector<dvec2> boxLo(n);
  std::vector<dvec2> boxHi(n);
  std::vector<size_t> cellStart(nx * ny + 1, 0);
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<size_t> fill;
    if (pass == 1) fill.assign(cellStart.begin(), cellStart.end() - 1);
    std::vector<uint32_t> items(pass == 1 ? cellStart.back() : 0);
    for (size_t i = 0; i < n; ++i) {
      if (pass == 0) {
        boxLo[i] = glm::min(q[3 * i], glm::min(q[3 * i + 1], q[3 * i + 2]));
        boxHi[i] = glm::max(q[3 * i], glm::max(q[3 * i + 1], q[3 * i + 2]));
      }
      const auto [x0, y0] = cellOf(boxLo[i]);
      const auto [x1, y1] = cellOf(boxHi[i]);
      for (size_t y = y0; y <= y1; ++y) {
        for (size_t x = x0; x <= x1; ++x) {
          if (pass == 0) {
            ++cellStart[y * nx + x + 1];
          } else {
            items[fill[y * nx + x]++] = uint32_t(i);
          }
        }
      }
    }
    if (pass == 0) {
      for (size_t c = 0; c < nx * ny; ++c) cellStart[c + 1] += cellStart[c];
      continue;
    }
    for (size_t c = 0; c < nx * ny; ++c) {
      for (size_t i = cellStart[c]; i < cellStart[c + 1]; ++i) {
        for (size_t j = i + 1; j < cellStart[c + 1]; ++j) {
          const uint32_t a = items[i];
          const uint32_t b = items[j];
          const dvec2 overlapLo = glm::max(boxLo[a], boxLo[b]);
          const dvec2 overlapHi = glm::min(boxHi[a], boxHi[b]);
          if (overlapLo.x > overlapHi.x || overlapLo.y > overlapHi.y) continue;
          const auto [ox, oy] = cellOf(overlapLo);
          if (oy * nx + ox != c) continue;
          if (trianglesOverlap(&q[3 * size_t(a)], &q[3 * size_t(b)])) return true;
        }
      }
    }
  }
  return false;
}

// Step 2: whether a chart projects onto its plane with every triangle facing the plane's normal within 60°
// and no two triangles overlapping. `scratch` holds the projected corners.
bool projectsCleanly(const Triangles& tris, std::span<const uint32_t> members, std::vector<dvec2>& scratch) {
  const ChartPlane plane = chartPlane(tris, members);
  scratch.resize(3 * members.size());
  for (size_t i = 0; i < members.size(); ++i) {
    const uint32_t t = members[i];
    for (size_t k = 0; k < 3; ++k) scratch[3 * i + k] = plane.project(tris.position(tris.corner(t, k)));
    const double projectedDoubleArea =
        cross2(scratch[3 * i + 1] - scratch[3 * i], scratch[3 * i + 2] - scratch[3 * i]);
    if (!(projectedDoubleArea >= kCosMaxProjection * glm::length(tris.cross[t]))) return false;
  }
  return !anyOverlap(scratch);
}

// Step 2: splits a chart at the middle of the longest side of its triangles' centroid box into the
// edge-connected pieces on either side (single triangles when all centroids coincide). Each piece is smaller,
// and a single triangle always projects cleanly, so repeated splitting ends. `group` labels triangles with
// unique ids, new ones from nextGroup on.
std::vector<std::vector<uint32_t>> splitChart(const Triangles& tris, const std::vector<uint32_t>& neighbour,
                                              std::span<const uint32_t> members, std::vector<uint32_t>& group,
                                              uint32_t& nextGroup) {
  std::vector<std::vector<uint32_t>> pieces;
  std::vector<dvec3> centroid(members.size());
  dvec3 lo(std::numeric_limits<double>::infinity());
  dvec3 hi(-std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < members.size(); ++i) {
    const uint32_t t = members[i];
    centroid[i] = (tris.position(tris.corner(t, 0)) + tris.position(tris.corner(t, 1)) +
                   tris.position(tris.corner(t, 2))) /
                  3.0;
    lo = glm::min(lo, centroid[i]);
    hi = glm::max(hi, centroid[i]);
  }
  const dvec3 extent = hi - lo;
  const int axis = extent.x >= extent.y && extent.x >= extent.z ? 0 : (extent.y >= extent.z ? 1 : 2);
  if (!(extent[axis] > 0.0)) {
    for (uint32_t t : members) pieces.push_back({t});
    return pieces;
  }
  const double middle = 0.5 * (lo[axis] + hi[axis]);
  const uint32_t sideGroup = nextGroup;
  nextGroup += 2;
  for (size_t i = 0; i < members.size(); ++i)
    group[members[i]] = sideGroup + (centroid[i][axis] > middle ? 1 : 0);
  for (uint32_t seed : members) {
    const uint32_t side = group[seed];
    if (side != sideGroup && side != sideGroup + 1) continue;  // already in a piece
    const uint32_t piece = nextGroup++;
    group[seed] = piece;
    std::vector<uint32_t> queue{seed};
    for (size_t head = 0; head < queue.size(); ++head) {
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t u = neighbour[3 * size_t(queue[head]) + k];
        if (u == kNone || group[u] != side) continue;
        group[u] = piece;
        queue.push_back(u);
      }
    }
    std::sort(queue.begin(), queue.end());
    pieces.push_back(std::move(queue));
  }
  return pieces;
}

// Triangle lists per chart: the triangles of chart c are items[start[c] … start[c+1]), in index order.
struct ChartLists {
  std::vector<uint32_t> start;
  std::vector<uint32_t> items;

  std::span<const uint32_t> operator[](size_t c) const {
    return std::span<const uint32_t>(items).subspan(start[c], start[c + 1] - start[c]);
  }
};

ChartLists listCharts(const std::vector<uint32_t>& chartOfTriangle, uint32_t chartCount) {
  ChartLists lists{std::vector<uint32_t>(chartCount + size_t(1), 0),
                   std::vector<uint32_t>(chartOfTriangle.size())};
  for (uint32_t c : chartOfTriangle) ++lists.start[c + size_t(1)];
  for (size_t c = 0; c < chartCount; ++c) lists.start[c + 1] += lists.start[c];
  std::vector<uint32_t> fill(lists.start.begin(), lists.start.end() - 1);
  for (size_t t = 0; t < chartOfTriangle.size(); ++t) lists.items[fill[chartOfTriangle[t]]++] = uint32_t(t);
  return lists;
}

// Step 2: the grown charts, split until each projects cleanly. Returns each non-degenerate triangle's final
// chart (kNone for degenerate ones) and sets chartCount.
std::vector<uint32_t> splitUntilClean(const Triangles& tris, const std::vector<uint32_t>& neighbour,
                                      std::vector<uint32_t> group, uint32_t grownCount,
                                      uint32_t& chartCount) {
  std::vector<uint32_t> grownOf = group;
  for (uint32_t& c : grownOf) c = c == kNone ? grownCount : c;  // degenerate triangles in one extra list
  const ChartLists grown = listCharts(grownOf, grownCount + 1);
  std::vector<uint32_t> chart(tris.count, kNone);
  std::vector<dvec2> scratch;
  uint32_t nextGroup = grownCount;
  chartCount = 0;
  for (uint32_t c = 0; c < grownCount; ++c) {
    if (projectsCleanly(tris, grown[c], scratch)) {
      for (uint32_t t : grown[c]) chart[t] = chartCount;
      ++chartCount;
      continue;
    }
    std::vector<std::vector<uint32_t>> pending = splitChart(tris, neighbour, grown[c], group, nextGroup);
    std::reverse(pending.begin(), pending.end());  // first piece first
    while (!pending.empty()) {
      const std::vector<uint32_t> piece = std::move(pending.back());
      pending.pop_back();
      if (projectsCleanly(tris, piece, scratch)) {
        for (uint32_t t : piece) chart[t] = chartCount;
        ++chartCount;
        continue;
      }
      std::vector<std::vector<uint32_t>> parts = splitChart(tris, neighbour, piece, group, nextGroup);
      for (auto it = parts.rbegin(); it != parts.rend(); ++it) pending.push_back(std::move(*it));
    }
  }
  return chart;
}

// Degenerate triangles join the chart of the first non-degenerate triangle that shares a welded corner with
// them, so they cost no texels; those with no such neighbour share one extra chart collapsed to a point.
// Returns that chart's id, or kNone when there is none.
uint32_t attachDegenerateTriangles(const Triangles& tris, const std::vector<uint32_t>& representative,
                                   std::vector<uint32_t>& chart, uint32_t& chartCount) {
  std::vector<uint32_t> vertexChart(tris.positions.size(), kNone);
  for (size_t t = 0; t < tris.count; ++t) {
    if (tris.degenerate[t]) continue;
    for (size_t k = 0; k < 3; ++k) {
      uint32_t& c = vertexChart[representative[tris.corner(t, k)]];
      if (c == kNone) c = chart[t];
    }
  }
  uint32_t pointChart = kNone;
  for (size_t t = 0; t < tris.count; ++t) {
    if (!tris.degenerate[t]) continue;
    for (size_t k = 0; k < 3 && chart[t] == kNone; ++k)
      chart[t] = vertexChart[representative[tris.corner(t, k)]];
    if (chart[t] == kNone) {
      if (pointChart == kNone) pointChart = chartCount++;
      chart[t] = pointChart;
    }
  }
  return pointChart;
}

// Andrew's monotone chain (Andrew 1979, "Another efficient algorithm for convex hulls in two dimensions"):
// the convex hull counter-clockwise, without collinear points.
std::vector<dvec2> convexHull(std::vector<dvec2> points) {
  std::sort(points.begin(), points.end(),
            [](const dvec2& a, const dvec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  points.erase(std::unique(points.begin(), points.end()), points.end());
  if (points.size() < 3) return points;
  std::vector<dvec2> hull(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {  // lower hull
    while (k >= 2 && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {  // upper hull
    while (k >= lower && cross2(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0.0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);  // the last point repeats the first
  return hull;
}

// Step 3: the unit direction of a side of the minimum-area rectangle enclosing a convex polygon
// (counter-clockwise). Such a rectangle has a side on a polygon edge (Freeman & Shapira 1975); rotating
// calipers (Toussaint 1983, "Solving geometric problems with the rotating calipers") visit every edge with
// the three other extreme points advancing monotonically, O(n) in all.
dvec2 minimumAreaRectangleDirection(const std::vector<dvec2>& hull) {
  const size_t n = hull.size();
  if (n < 3) return n == 2 ? glm::normalize(hull[1] - hull[0]) : dvec2(1.0, 0.0);
  auto at = [&](size_t i) { return hull[i % n]; };
  size_t right = 0;  // farthest along the edge direction e
  size_t top = 0;    // farthest along the inward normal of the edge
  size_t left = 0;   // farthest against e
  double bestArea = std::numeric_limits<double>::infinity();
  dvec2 best(1.0, 0.0);
  for (size_t i = 0; i < n; ++i) {
    const dvec2 e = glm::normalize(at(i + 1) - at(i));
    const dvec2 inward(-e.y, e.x);
    if (i == 0) {
      for (size_t j = 1; j < n; ++j) {
        if (glm::dot(hull[j], e) > glm::dot(hull[right], e)) right = j;
        if (glm::dot(hull[j], inward) > glm::dot(hull[top], inward)) top = j;
        if (glm::dot(hull[j], e) < glm::dot(hull[left], e)) left = j;
      }
    }
    // An extreme point advances while the next vertex lies farther along d, at most one turn: the edges of a
    // closed polygon cannot all advance, but rounding on nearly coincident vertices could make them seem to.
    auto advance = [&](size_t& j, const dvec2& d) {
      for (size_t step = 0; step < n && glm::dot(at(j + 1) - at(j), d) > 0.0; ++step) ++j;
    };
    advance(right, e);
    advance(top, inward);
    advance(left, -e);
    const double area = glm::dot(at(right) - at(left), e) * glm::dot(at(top) - at(i), inward);
    if (area < bestArea) {
      bestArea = area;
      best = e;
    }
  }
  return best;
}

// A chart after steps 2 and 3: its output vertices' coordinates lie in [0, width] × [0, height] metres,
// width ≥ height.
struct ChartShape {
  uint32_t firstVertex = 0;
  uint32_t vertexCount = 0;
  double width = 0.0;   // metres
  double height = 0.0;  // metres
};

// Texels a chart side of `metres` needs at `density` texels/m, margins included; capped far above any atlas
// so that absurd densities do not overflow.
int64_t texelSpan(double metres, double density) {
  return int64_t(std::clamp(std::ceil(metres * density + 2.0 * kChartMarginTexels), 1.0, 0x1p40));
}

// Chart rectangles placed in the atlas (step 4).
struct Packing {
  std::vector<int64_t> x, y;  // per chart: the rectangle's upper-left texel
  std::vector<int64_t> w, h;  // per chart: the rectangle's size, texels
  int64_t width = 0;
  int64_t height = 0;
};

// Skyline bottom-left packing (Jylänki 2010, "A Thousand Ways to Pack the Bin — A Practical Approach to
// Two-Dimensional Rectangle Bin Packing", SKYLINE-BL): the packed rectangles' lower profile (rows grow
// downwards) is a list of horizontal segments, and each rectangle goes where its far edge ends nearest to
// row 0, leftmost on ties.
class Skyline {
 public:
  explicit Skyline(int64_t width) : width_(width), segments_{{0, 0, width}} {}

  // Places a w × h rectangle, w ≤ the bin's width; returns its corner.
  std::pair<int64_t, int64_t> place(int64_t w, int64_t h) {
    size_t best = 0;
    int64_t bestEnd = std::numeric_limits<int64_t>::max();
    for (size_t i = 0; i < segments_.size() && segments_[i].x + w <= width_; ++i) {
      int64_t y = 0;
      int64_t covered = 0;
      for (size_t j = i; covered < w && y + h < bestEnd; ++j) {
        y = std::max(y, segments_[j].y);
        covered += segments_[j].width;
      }
      if (covered >= w && y + h < bestEnd) {
        best = i;
        bestEnd = y + h;
      }
    }
    assert(bestEnd != std::numeric_limits<int64_t>::max() && "rectangle wider than the bin");
    const int64_t x = segments_[best].x;
    const int64_t end = x + w;
    size_t last = best;  // the first segment not covered completely
    while (last < segments_.size() && segments_[last].x + segments_[last].width <= end) ++last;
    if (last < segments_.size() && segments_[last].x < end) {
      segments_[last].width -= end - segments_[last].x;
      segments_[last].x = end;
    }
    segments_.erase(segments_.begin() + std::ptrdiff_t(best), segments_.begin() + std::ptrdiff_t(last));
    segments_.insert(segments_.begin() + std::ptrdiff_t(best), Segment{x, bestEnd, w});
    if (best + 1 < segments_.size() && segments_[best + 1].y == bestEnd) {
      segments_[best].width += segments_[best + 1].width;
      segments_.erase(segments_.begin() + std::ptrdiff_t(best + 1));
    }
    if (best > 0 && segments_[best - 1].y == bestEnd) {
      segments_[best - 1].width += segments_[best].width;
      segments_.erase(segments_.begin() + std::ptrdiff_t(best));
    }
    return {x, bestEnd - h};
  }

 private:
  struct Segment {
    int64_t x;
    int64_t y;  // the first free row above [x, x + width)
    int64_t width;
  };
  int64_t width_;
  std::vector<Segment> segments_;
};

// Step 4: packs the rectangles packing.w × packing.h in `order` into a bin `binWidth` texels wide, each
// followed by `padding` free texels to its right and below and the whole bin offset by `padding`, so that
// charts are `padding` apart from each other and from the atlas border. False as soon as the atlas would be
// higher than maxHeight or its area (which only grows) reach maxArea.
bool packRectangles(const std::vector<uint32_t>& order, int64_t padding, int64_t binWidth, int64_t maxHeight,
                    double maxArea, Packing& packing) {
  Skyline skyline(binWidth);
  packing.width = 0;
  packing.height = 0;
  for (uint32_t c : order) {
    const auto [x, y] = skyline.place(packing.w[c] + padding, packing.h[c] + padding);
    packing.x[c] = x + padding;
    packing.y[c] = y + padding;
    packing.width = std::max(packing.width, packing.x[c] + packing.w[c] + padding);
    packing.height = std::max(packing.height, packing.y[c] + packing.h[c] + padding);
    if (packing.height > maxHeight || double(packing.width) * double(packing.height) >= maxArea) return false;
  }
  return true;
}

// Step 4 at one density (texels/m): the charts' rectangles, tallest first as Jylänki recommends for skyline
// packers, in bins from the width of a square of their padded area up to about twice that, at most
// maxBinWidth; keeps the packing of least area. False when no bin gives an atlas at most maxHeight high.
bool packAtDensity(const std::vector<ChartShape>& charts, double density, int64_t padding,
                   int64_t maxBinWidth, int64_t maxHeight, Packing& best) {
  const size_t n = charts.size();
  Packing packing;
  packing.x.resize(n);
  packing.y.resize(n);
  packing.w.resize(n);
  packing.h.resize(n);
  std::vector<uint32_t> order(n);
  int64_t widest = 0;
  double paddedArea = 0.0;
  for (size_t c = 0; c < n; ++c) {
    packing.w[c] = texelSpan(charts[c].width, density);
    packing.h[c] = texelSpan(charts[c].height, density);
    widest = std::max(widest, packing.w[c] + padding);
    paddedArea += double(packing.w[c] + padding) * double(packing.h[c] + padding);
    order[c] = uint32_t(c);
  }
  if (widest > maxBinWidth) return false;
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    if (packing.h[a] != packing.h[b]) return packing.h[a] > packing.h[b];
    return packing.w[a] != packing.w[b] ? packing.w[a] > packing.w[b] : a < b;
  });
  double bestArea = std::numeric_limits<double>::infinity();
  int64_t previousWidth = 0;
  for (int k = 0; k < 8; ++k) {
    const double width = std::ceil(std::sqrt(paddedArea) * std::pow(1.1, k));
    const int64_t binWidth = std::clamp(int64_t(std::min(width, 0x1p40)), widest, maxBinWidth);
    if (binWidth == previousWidth) continue;
    previousWidth = binWidth;
    if (packRectangles(order, padding, binWidth, maxHeight, bestArea, packing)) {
      bestArea = double(packing.width) * double(packing.height);
      best = packing;
    }
  }
  return bestArea < std::numeric_limits<double>::infinity();
}

struct AtlasResult {
  Packing packing;
  double density = 0.0;  // texels/m
  bool reduced = false;
  bool exceedsMax = false;
};

// Step 4: the packing at the requested density when it fits into maxAtlasSize², otherwise at the
// largest uniformly reduced density found (to within 1 %) that fits. Reduced densities are searched between
// one bounded by area (no packing can fit more padded texels than the atlas has) and one that packs, found by
// lowering the fill factor the area is assumed to reach; a bisection closes the gap.
AtlasResult packAtlas(const std::vector<ChartShape>& charts, const LightmapUvSettings& settings) {
  const double requested = settings.texelsPerMetre;
  const int64_t padding = settings.paddingTexels;
  const int64_t maxSize = settings.maxAtlasSize;
  const int64_t maxBin = maxSize - padding;
  auto paddedArea = [&](double density) {
    double area = 0.0;
    for (const ChartShape& c : charts) {
      area += double(texelSpan(c.width, density) + padding) * double(texelSpan(c.height, density) + padding);
    }
    return area;
  };
  auto tryPack = [&](double density, Packing& packing) {
    return packAtDensity(charts, density, padding, maxBin, maxSize, packing);
  };

  AtlasResult result;
  if (tryPack(requested, result.packing)) {
    result.density = requested;
    return result;
  }
  result.reduced = true;
  double widestChart = 0.0;
  for (const ChartShape& c : charts) widestChart = std::max(widestChart, c.width);
  // Below this scale of the requested density every chart is one texel (with a margin to spare against
  // rounding), and the area stops shrinking.
  const double minScale =
      widestChart > 0.0 ? std::min(1.0, (1.0 - 3.0 * kChartMarginTexels) / (widestChart * requested)) : 1.0;
  // The largest scale in [minScale, 1] whose padded area is at most `limit` (0 when there is none), by
  // bisection on a log scale: the padded area grows monotonically with the scale.
  auto largestScaleWithArea = [&](double limit) {
    if (paddedArea(minScale * requested) > limit) return 0.0;
    if (paddedArea(requested) <= limit) return 1.0;
    double lo = minScale;
    double hi = 1.0;
    for (int i = 0; i < 40; ++i) {
      const double mid = std::sqrt(lo * hi);
      (paddedArea(mid * requested) <= limit ? lo : hi) = mid;
    }
    return lo;
  };
  const double binArea = double(maxBin) * double(maxBin);
  double fails = largestScaleWithArea(binArea);
  double fits = 0.0;
  Packing packing;
  for (double fill = 0.9; fill > 0.1 && fits == 0.0; fill *= 0.9) {
    const double scale = largestScaleWithArea(fill * binArea);
    if (scale == 0.0) break;
    if (tryPack(scale * requested, packing)) {
      fits = scale;
      result.packing = packing;
    } else {
      fails = scale;
    }
  }
  if (fits == 0.0) {
    result.density = minScale * requested;
    if (!tryPack(result.density, result.packing)) {
      // More charts than the largest atlas has room for, even at one texel each: grow downwards.
      result.exceedsMax = true;
      [[maybe_unused]] const bool packed = packAtDensity(charts, result.density, padding, maxBin,
                                                         std::numeric_limits<int64_t>::max(), result.packing);
      assert(packed && "one-texel charts fit a bin 1 + padding wide");
    }
    return result;
  }
  while (fails > 1.01 * fits) {
    const double scale = std::sqrt(fits * fails);
    if (tryPack(scale * requested, packing)) {
      fits = scale;
      result.packing = packing;
    } else {
      fails = scale;
    }
  }
  result.density = fits * requested;
  return result;
}

void checkPreconditions(std::span<const vec3> positions, std::span<const uint32_t> indices,
                        const LightmapUvSettings& settings) {
  const std::string where = "generateLightmapUv: ";
  if (!(std::isfinite(settings.texelsPerMetre) && settings.texelsPerMetre > 0.0f)) {
    throw std::invalid_argument(where + "texelsPerMetre must be finite and > 0, got " +
                                std::to_string(settings.texelsPerMetre));
  }
  if (settings.paddingTexels < 0) {
    throw std::invalid_argument(where + "paddingTexels must be >= 0, got " +
                                std::to_string(settings.paddingTexels));
  }
  if (settings.maxAtlasSize < 2 * settings.paddingTexels + 1) {
    throw std::invalid_argument(where + "maxAtlasSize " + std::to_string(settings.maxAtlasSize) +
                                " leaves no texel inside a padding of " +
                                std::to_string(settings.paddingTexels));
  }
  if (indices.size() % 3 != 0 || indices.size() > kNone) {
    throw std::invalid_argument(where + "index count " + std::to_string(indices.size()) +
                                " is not a multiple of 3 below 2^32");
  }
  for (uint32_t v : indices) {
    if (v >= positions.size()) {
      throw std::invalid_argument(where + "index " + std::to_string(v) + " is past the vertex count " +
                                  std::to_string(positions.size()));
    }
    if (!isFinite(positions[v])) {
      throw std::invalid_argument(where + "position of vertex " + std::to_string(v) + " is not finite");
    }
  }
}

}  // namespace

LightmapUv generateLightmapUv(std::span<const vec3> positionsWorld, std::span<const uint32_t> indices,
                              const LightmapUvSettings& settings) {
  checkPreconditions(positionsWorld, indices, settings);
  LightmapUv out;
  if (indices.empty()) return out;

  // Steps 1 and 2.
  const Triangles tris = measureTriangles(positionsWorld, indices);
  const std::vector<uint32_t> representative = weldVertices(tris);
  const std::vector<uint32_t> neighbour = findNeighbours(tris, representative);
  uint32_t grownCount = 0;
  std::vector<uint32_t> grown = growCharts(tris, neighbour, grownCount);
  out.chartOfTriangle = splitUntilClean(tris, neighbour, std::move(grown), grownCount, out.chartCount);
  const uint32_t pointChart =
      attachDegenerateTriangles(tris, representative, out.chartOfTriangle, out.chartCount);

  // Output vertices, one per input vertex and chart, and each chart's coordinates (steps 2 and 3).
  const ChartLists charts = listCharts(out.chartOfTriangle, out.chartCount);
  std::vector<ChartShape> shapes(out.chartCount);
  std::vector<dvec2> local;  // per output vertex, metres in its chart's rectangle
  std::vector<uint32_t> vertexChart(positionsWorld.size(), kNone);
  std::vector<uint32_t> outputVertex(positionsWorld.size());
  out.indices.resize(indices.size());
  for (uint32_t c = 0; c < out.chartCount; ++c) {
    ChartShape& shape = shapes[c];
    shape.firstVertex = uint32_t(out.sourceVertex.size());
    for (uint32_t t : charts[c]) {
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t v = tris.corner(t, k);
        if (vertexChart[v] != c) {
          vertexChart[v] = c;
          outputVertex[v] = uint32_t(out.sourceVertex.size());
          out.sourceVertex.push_back(v);
        }
        out.indices[3 * size_t(t) + k] = outputVertex[v];
      }
    }
    shape.vertexCount = uint32_t(out.sourceVertex.size()) - shape.firstVertex;
    local.resize(out.sourceVertex.size(), dvec2(0.0));
    if (c == pointChart) continue;  // all its vertices at one point
    const std::span<dvec2> coords(local.data() + shape.firstVertex, shape.vertexCount);
    const ChartPlane plane = chartPlane(tris, charts[c]);
    for (uint32_t i = 0; i < shape.vertexCount; ++i) {
      coords[i] = plane.project(tris.position(out.sourceVertex[shape.firstVertex + i]));
    }
    const dvec2 e = minimumAreaRectangleDirection(convexHull({coords.begin(), coords.end()}));
    dvec2 lo(std::numeric_limits<double>::infinity());
    dvec2 hi(-std::numeric_limits<double>::infinity());
    for (dvec2& p : coords) {
      p = dvec2(glm::dot(p, e), cross2(e, p));  // rotation by −angle(e): orientation is kept
      lo = glm::min(lo, p);
      hi = glm::max(hi, p);
    }
    shape.width = hi.x - lo.x;
    shape.height = hi.y - lo.y;
    const bool turn = shape.height > shape.width;  // lying rectangles pack tighter on a skyline
    for (dvec2& p : coords)
      p = turn ? dvec2(hi.y - p.y, p.x - lo.x) : p - lo;  // a quarter turn keeps orientation
    if (turn) std::swap(shape.width, shape.height);
  }

  // Steps 4 and 5.
  const AtlasResult atlas = packAtlas(shapes, settings);
  const Packing& packing = atlas.packing;
  out.width = uint32_t(packing.width);
  out.height = uint32_t(packing.height);
  out.texelsPerMetre = float(atlas.density);
  out.densityReduced = atlas.reduced;
  out.exceedsMaxAtlasSize = atlas.exceedsMax;
  out.uv.resize(out.sourceVertex.size());
  const dvec2 atlasSize(double(packing.width), double(packing.height));
  for (uint32_t c = 0; c < out.chartCount; ++c) {
    const ChartShape& shape = shapes[c];
    // Centred in its rectangle, which leaves at least kChartMarginTexels on each side.
    const dvec2 corner(double(packing.x[c]) + 0.5 * (double(packing.w[c]) - shape.width * atlas.density),
                       double(packing.y[c]) + 0.5 * (double(packing.h[c]) - shape.height * atlas.density));
    for (uint32_t i = shape.firstVertex; i < shape.firstVertex + shape.vertexCount; ++i) {
      out.uv[i] = vec2((corner + local[i] * atlas.density) / atlasSize);
    }
  }
  double coveredTexels = 0.0;
  for (size_t t = 0; t < tris.count; ++t) {
    if (tris.degenerate[t]) continue;
    const dvec2 a = local[out.indices[3 * t]];
    coveredTexels += 0.5 * cross2(local[out.indices[3 * t + 1]] - a, local[out.indices[3 * t + 2]] - a);
  }
  out.utilisation = float(coveredTexels * atlas.density * atlas.density / (atlasSize.x * atlasSize.y));
  return out;
}

}  // namespace fly::rdb
