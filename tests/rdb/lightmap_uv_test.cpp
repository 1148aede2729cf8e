#include "rdb/lightmap_uv.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>
#include <tuple>
#include <vector>

namespace fly::rdb {
namespace {

struct TestMesh {
  std::vector<vec3> positions;
  std::vector<uint32_t> indices;

  uint32_t vertex(const vec3& p) {
    positions.push_back(p);
    return uint32_t(positions.size() - 1);
  }
  void triangle(uint32_t a, uint32_t b, uint32_t c) { indices.insert(indices.end(), {a, b, c}); }
  // A triangle wound counter-clockwise seen from the side `outward` points to.
  void triangleFacing(uint32_t a, uint32_t b, uint32_t c, const vec3& outward) {
    const vec3 n = glm::cross(positions[b] - positions[a], positions[c] - positions[a]);
    if (glm::dot(n, outward) >= 0.0f) {
      triangle(a, b, c);
    } else {
      triangle(a, c, b);
    }
  }
  void append(const TestMesh& m) {
    const uint32_t base = uint32_t(positions.size());
    positions.insert(positions.end(), m.positions.begin(), m.positions.end());
    for (uint32_t i : m.indices) indices.push_back(base + i);
  }
  size_t triangleCount() const { return indices.size() / 3; }
};

// An axis-aligned box; with sharedVertices its faces share 8 corners, otherwise each face has 4 of its own.
TestMesh box(const vec3& centre, const vec3& size, bool sharedVertices) {
  TestMesh m;
  std::map<std::tuple<float, float, float>, uint32_t> corner;
  auto at = [&](const vec3& p) {
    if (!sharedVertices) return m.vertex(p);
    const auto [it, added] = corner.try_emplace({p.x, p.y, p.z}, uint32_t(m.positions.size()));
    if (added) m.vertex(p);
    return it->second;
  };
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {-1.0f, 1.0f}) {
      vec3 n(0.0f);
      n[axis] = sign;
      vec3 u(0.0f);
      u[(axis + 1) % 3] = 1.0f;
      const vec3 v = glm::cross(n, u);
      const vec3 half = 0.5f * size;
      const vec3 c = centre + n * half;
      const uint32_t a = at(c - u * half - v * half);
      const uint32_t b = at(c + u * half - v * half);
      const uint32_t d = at(c + u * half + v * half);
      const uint32_t e = at(c - u * half + v * half);
      m.triangleFacing(a, b, d, n);
      m.triangleFacing(a, d, e, n);
    }
  }
  return m;
}

// A horizontal grid facing +Y: quadsX × quadsZ quads of `cell` metres from `origin`; skip(i, j) drops one.
template <typename Skip>
TestMesh grid(const vec3& origin, int quadsX, int quadsZ, float cell, Skip skip) {
  TestMesh m;
  for (int j = 0; j <= quadsZ; ++j) {
    for (int i = 0; i <= quadsX; ++i) m.vertex(origin + vec3(float(i) * cell, 0.0f, float(j) * cell));
  }
  auto at = [&](int i, int j) { return uint32_t(j * (quadsX + 1) + i); };
  for (int j = 0; j < quadsZ; ++j) {
    for (int i = 0; i < quadsX; ++i) {
      if (skip(i, j)) continue;
      m.triangleFacing(at(i, j), at(i + 1, j), at(i + 1, j + 1), vec3(0, 1, 0));
      m.triangleFacing(at(i, j), at(i + 1, j + 1), at(i, j + 1), vec3(0, 1, 0));
    }
  }
  return m;
}

TestMesh grid(const vec3& origin, int quadsX, int quadsZ, float cell) {
  return grid(origin, quadsX, quadsZ, cell, [](int, int) { return false; });
}

// An open cylinder around +Y facing outwards.
TestMesh cylinder(float radius, float height, int segments, int rings) {
  TestMesh m;
  for (int j = 0; j <= rings; ++j) {
    for (int i = 0; i < segments; ++i) {
      const float a = 2.0f * kPiF * float(i) / float(segments);
      m.vertex(vec3(radius * std::cos(a), height * float(j) / float(rings), radius * std::sin(a)));
    }
  }
  auto at = [&](int i, int j) { return uint32_t(j * segments + i % segments); };
  for (int j = 0; j < rings; ++j) {
    for (int i = 0; i < segments; ++i) {
      const float a = 2.0f * kPiF * (float(i) + 0.5f) / float(segments);
      const vec3 out(std::cos(a), 0.0f, std::sin(a));
      m.triangleFacing(at(i, j), at(i + 1, j), at(i + 1, j + 1), out);
      m.triangleFacing(at(i, j), at(i + 1, j + 1), at(i, j + 1), out);
    }
  }
  return m;
}

// A UV sphere facing outwards: rings × segments, with triangle fans at the poles.
TestMesh sphere(float radius, int segments, int rings) {
  TestMesh m;
  const uint32_t north = m.vertex(vec3(0, radius, 0));
  for (int j = 1; j < rings; ++j) {
    const float polar = kPiF * float(j) / float(rings);
    for (int i = 0; i < segments; ++i) {
      const float a = 2.0f * kPiF * float(i) / float(segments);
      m.vertex(radius * vec3(std::sin(polar) * std::cos(a), std::cos(polar), std::sin(polar) * std::sin(a)));
    }
  }
  const uint32_t south = m.vertex(vec3(0, -radius, 0));
  auto at = [&](int i, int j) { return uint32_t(1 + (j - 1) * segments + i % segments); };
  auto out = [&](uint32_t a, uint32_t b, uint32_t c) {
    return m.positions[a] + m.positions[b] + m.positions[c];
  };
  for (int i = 0; i < segments; ++i) {
    m.triangleFacing(north, at(i, 1), at(i + 1, 1), out(north, at(i, 1), at(i + 1, 1)));
    m.triangleFacing(south, at(i, rings - 1), at(i + 1, rings - 1),
                     out(south, at(i, rings - 1), at(i + 1, rings - 1)));
    for (int j = 1; j + 1 < rings; ++j) {
      m.triangleFacing(at(i, j), at(i + 1, j), at(i + 1, j + 1),
                       out(at(i, j), at(i + 1, j), at(i + 1, j + 1)));
      m.triangleFacing(at(i, j), at(i + 1, j + 1), at(i, j + 1),
                       out(at(i, j), at(i + 1, j + 1), at(i, j + 1)));
    }
  }
  return m;
}

// A spiral ramp (a helicoid between two radii) facing up: `turns` full turns rising `rise` metres per turn.
// Its normals stay within a few degrees of +Y, so one chart by normals, but its turns lie above each other.
TestMesh helix(float innerRadius, float outerRadius, float turns, float rise, int segmentsPerTurn) {
  TestMesh m;
  const int segments = int(turns * float(segmentsPerTurn));
  for (int i = 0; i <= segments; ++i) {
    const float a = 2.0f * kPiF * float(i) / float(segmentsPerTurn);
    const float y = rise * float(i) / float(segmentsPerTurn);
    m.vertex(vec3(innerRadius * std::cos(a), y, innerRadius * std::sin(a)));
    m.vertex(vec3(outerRadius * std::cos(a), y, outerRadius * std::sin(a)));
  }
  for (int i = 0; i < segments; ++i) {
    const uint32_t a = uint32_t(2 * i);
    m.triangleFacing(a, a + 1, a + 3, vec3(0, 1, 0));
    m.triangleFacing(a, a + 3, a + 2, vec3(0, 1, 0));
  }
  return m;
}

struct CheckOptions {
  bool planarCharts = true;  // every chart is planar: texel density exact per triangle
  bool raster = true;        // rasterise the atlas (overlap and padding)
};

dvec2 texelCoords(const LightmapUv& r, uint32_t outputVertex) {
  return dvec2(r.uv[outputVertex]) * dvec2(double(r.width), double(r.height));
}

double cross2(const dvec2& a, const dvec2& b) {
  return a.x * b.y - a.y * b.x;
}

// Whether the closed triangle and the closed texel square [x, x+1] × [y, y+1] intersect (separating axes).
bool touchesTexel(const dvec2* t, double x, double y) {
  const dvec2 lo = glm::min(t[0], glm::min(t[1], t[2]));
  const dvec2 hi = glm::max(t[0], glm::max(t[1], t[2]));
  if (hi.x < x || lo.x > x + 1 || hi.y < y || lo.y > y + 1) return false;
  const dvec2 square[4] = {{x, y}, {x + 1, y}, {x, y + 1}, {x + 1, y + 1}};
  for (int k = 0; k < 3; ++k) {
    const dvec2 e = t[(k + 1) % 3] - t[k];
    if (e == dvec2(0.0)) continue;
    const dvec2 axis(-e.y, e.x);
    double triLo = INFINITY, triHi = -INFINITY, sqLo = INFINITY, sqHi = -INFINITY;
    for (int i = 0; i < 3; ++i) {
      triLo = std::min(triLo, glm::dot(t[i], axis));
      triHi = std::max(triHi, glm::dot(t[i], axis));
    }
    for (const dvec2& s : square) {
      sqLo = std::min(sqLo, glm::dot(s, axis));
      sqHi = std::max(sqHi, glm::dot(s, axis));
    }
    if (triHi < sqLo || sqHi < triLo) return false;
  }
  return true;
}

// The requirements every result meets; the figures that the tests report.
void checkAtlas(const TestMesh& mesh, const LightmapUv& r, const LightmapUvSettings& s,
                const CheckOptions& o) {
  const size_t triangles = mesh.triangleCount();
  ASSERT_EQ(r.indices.size(), mesh.indices.size());
  ASSERT_EQ(r.chartOfTriangle.size(), triangles);
  ASSERT_EQ(r.uv.size(), r.sourceVertex.size());
  if (triangles == 0) return;
  ASSERT_GE(r.width, 1u);
  ASSERT_GE(r.height, 1u);
  if (!r.exceedsMaxAtlasSize) {
    EXPECT_LE(r.width, uint32_t(s.maxAtlasSize));
    EXPECT_LE(r.height, uint32_t(s.maxAtlasSize));
  }
  EXPECT_LE(r.texelsPerMetre, s.texelsPerMetre);
  EXPECT_EQ(r.densityReduced, r.texelsPerMetre < s.texelsPerMetre);
  EXPECT_GE(r.utilisation, 0.0f);
  EXPECT_LE(r.utilisation, 1.0f);

  // Indices, sources and one chart per output vertex.
  std::vector<uint32_t> chartOfVertex(r.sourceVertex.size(), UINT32_MAX);
  for (size_t i = 0; i < r.indices.size(); ++i) {
    const uint32_t v = r.indices[i];
    ASSERT_LT(v, r.sourceVertex.size());
    ASSERT_EQ(r.sourceVertex[v], mesh.indices[i]) << "corner " << i;
    const uint32_t c = r.chartOfTriangle[i / 3];
    ASSERT_LT(c, r.chartCount);
    if (chartOfVertex[v] == UINT32_MAX) chartOfVertex[v] = c;
    ASSERT_EQ(chartOfVertex[v], c) << "output vertex " << v << " in two charts";
  }
  for (size_t v = 0; v < r.uv.size(); ++v) {
    ASSERT_TRUE(isFinite(r.uv[v])) << "vertex " << v;
    ASSERT_GT(r.uv[v].x, 0.0f);
    ASSERT_LT(r.uv[v].x, 1.0f);
    ASSERT_GT(r.uv[v].y, 0.0f);
    ASSERT_LT(r.uv[v].y, 1.0f);
  }

  // Orientation and texel density, per triangle big enough for float UVs to resolve it.
  const double density = r.texelsPerMetre;
  const double expectedRatio = density * density / (double(r.width) * double(r.height));
  int flipped = 0;
  int offDensity = 0;
  for (size_t t = 0; t < triangles; ++t) {
    const dvec3 a(mesh.positions[mesh.indices[3 * t]]);
    const dvec3 b(mesh.positions[mesh.indices[3 * t + 1]]);
    const dvec3 c(mesh.positions[mesh.indices[3 * t + 2]]);
    const double worldArea = 0.5 * glm::length(glm::cross(b - a, c - a));
    const double longest = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
    if (longest == 0.0 || 2.0 * worldArea / longest < 1e-3 * longest) continue;  // a sliver or degenerate
    if (worldArea * density * density < 1e-2) continue;                          // below float resolution
    const dvec2 ua(r.uv[r.indices[3 * t]]);
    const dvec2 ub(r.uv[r.indices[3 * t + 1]]);
    const dvec2 uc(r.uv[r.indices[3 * t + 2]]);
    const double uvArea = 0.5 * cross2(ub - ua, uc - ua);
    if (!(uvArea > 0.0)) ++flipped;
    if (worldArea * density * density < 0.5) continue;
    const double ratio = uvArea / worldArea / expectedRatio;
    const bool ok = o.planarCharts ? std::abs(ratio - 1.0) <= 0.01 : ratio >= 0.5 && ratio <= 1.01;
    if (!ok) {
      if (offDensity == 0) ADD_FAILURE() << "triangle " << t << ": texel density ratio " << ratio;
      ++offDensity;
    }
  }
  EXPECT_EQ(flipped, 0);
  EXPECT_EQ(offDensity, 0);
  if (!o.raster) return;

  // Conservative rasterisation: no texel touched by two charts, charts ≥ padding apart and from the border,
  // and no texel centre strictly inside two triangles (no overlap within a chart either).
  const size_t w = r.width;
  const size_t h = r.height;
  std::vector<int32_t> owner(w * h, -1);
  std::vector<uint8_t> centreCount(w * h, 0);
  int shared = 0;
  int overlapping = 0;
  for (size_t t = 0; t < triangles; ++t) {
    const dvec2 p[3] = {texelCoords(r, r.indices[3 * t]), texelCoords(r, r.indices[3 * t + 1]),
                        texelCoords(r, r.indices[3 * t + 2])};
    const int32_t chart = int32_t(r.chartOfTriangle[t]);
    const dvec2 lo = glm::min(p[0], glm::min(p[1], p[2]));
    const dvec2 hi = glm::max(p[0], glm::max(p[1], p[2]));
    const double area = cross2(p[1] - p[0], p[2] - p[0]);
    for (size_t y = size_t(std::max(0.0, std::floor(lo.y) - 1)); y < std::min<size_t>(h, size_t(hi.y) + 2);
         ++y) {
      for (size_t x = size_t(std::max(0.0, std::floor(lo.x) - 1)); x < std::min<size_t>(w, size_t(hi.x) + 2);
           ++x) {
        if (!touchesTexel(p, double(x), double(y))) continue;
        int32_t& o2 = owner[y * w + x];
        if (o2 >= 0 && o2 != chart) ++shared;
        o2 = chart;
        if (area <= 1e-9) continue;
        const dvec2 centre(double(x) + 0.5, double(y) + 0.5);
        bool inside = true;
        for (int k = 0; k < 3; ++k) {
          const dvec2 e = p[(k + 1) % 3] - p[k];
          inside = inside && cross2(e, centre - p[k]) > 1e-6 * glm::length(e);
        }
        if (inside && ++centreCount[y * w + x] == 2) ++overlapping;
      }
    }
  }
  EXPECT_EQ(shared, 0) << "texels touched by two charts";
  EXPECT_EQ(overlapping, 0) << "texel centres inside two triangles";
  const int pad = s.paddingTexels;
  int tooClose = 0;
  for (size_t y = 0; y < h; ++y) {
    for (size_t x = 0; x < w; ++x) {
      const int32_t c = owner[y * w + x];
      if (c < 0) continue;
      if (int(x) < pad || int(y) < pad || x + pad >= w || y + pad >= h) ++tooClose;
      for (int dy = -pad; dy <= pad; ++dy) {
        for (int dx = -pad; dx <= pad; ++dx) {
          const int nx = int(x) + dx;
          const int ny = int(y) + dy;
          if (nx < 0 || ny < 0 || nx >= int(w) || ny >= int(h)) continue;
          const int32_t other = owner[size_t(ny) * w + size_t(nx)];
          if (other >= 0 && other != c) ++tooClose;
        }
      }
    }
  }
  EXPECT_EQ(tooClose, 0) << "texels of two charts, or of a chart and the border, closer than the padding";
  // The boxes around each chart's texels are the padding apart too: charts do not nest in each other's gaps.
  std::vector<glm::ivec4> bounds(r.chartCount,
                                 glm::ivec4(INT32_MAX, INT32_MAX, -1, -1));  // x0, y0, x1, y1 inclusive
  for (size_t y = 0; y < h; ++y) {
    for (size_t x = 0; x < w; ++x) {
      const int32_t c = owner[y * w + x];
      if (c < 0) continue;
      glm::ivec4& b = bounds[size_t(c)];
      b = glm::ivec4(std::min(b.x, int(x)), std::min(b.y, int(y)), std::max(b.z, int(x)),
                     std::max(b.w, int(y)));
    }
  }
  int boxesTooClose = 0;
  for (size_t a = 0; a < bounds.size(); ++a) {
    for (size_t b = a + 1; b < bounds.size(); ++b) {
      const int gap = std::max({bounds[b].x - bounds[a].z, bounds[a].x - bounds[b].z,
                                bounds[b].y - bounds[a].w, bounds[a].y - bounds[b].w}) -
                      1;
      if (bounds[a].z >= 0 && bounds[b].z >= 0 && gap < pad) ++boxesTooClose;
    }
  }
  EXPECT_EQ(boxesTooClose, 0) << "chart rectangles closer than the padding";
}

LightmapUvSettings settings(float texelsPerMetre, int maxAtlasSize = 4096, int padding = 2) {
  LightmapUvSettings s;
  s.texelsPerMetre = texelsPerMetre;
  s.maxAtlasSize = maxAtlasSize;
  s.paddingTexels = padding;
  return s;
}

std::vector<uint32_t> chartSizes(const LightmapUv& r) {
  std::vector<uint32_t> sizes(r.chartCount, 0);
  for (uint32_t c : r.chartOfTriangle) ++sizes[c];
  std::sort(sizes.begin(), sizes.end());
  return sizes;
}

TEST(LightmapUv, EmptyMeshGivesAnEmptyAtlas) {
  const std::vector<vec3> positions = {vec3(0), vec3(1, 0, 0)};  // no triangle uses them
  for (const auto& p : {std::vector<vec3>{}, positions}) {
    const LightmapUv r = generateLightmapUv(p, {}, settings(10.0f));
    EXPECT_EQ(r.chartCount, 0u);
    EXPECT_EQ(r.width, 0u);
    EXPECT_EQ(r.height, 0u);
    EXPECT_TRUE(r.uv.empty());
    EXPECT_TRUE(r.sourceVertex.empty());
    EXPECT_TRUE(r.indices.empty());
    EXPECT_FALSE(r.densityReduced);
  }
}

TEST(LightmapUv, RejectsBadInput) {
  const TestMesh m = box(vec3(0), vec3(1), true);
  EXPECT_THROW(generateLightmapUv(m.positions, m.indices, settings(0.0f)), std::invalid_argument);
  EXPECT_THROW(generateLightmapUv(m.positions, m.indices, settings(NAN)), std::invalid_argument);
  EXPECT_THROW(generateLightmapUv(m.positions, m.indices, settings(10.0f, 4, 2)), std::invalid_argument);
  EXPECT_THROW(generateLightmapUv(m.positions, m.indices, settings(10.0f, 4096, -1)), std::invalid_argument);
  const std::vector<uint32_t> twoIndices = {0, 1};
  EXPECT_THROW(generateLightmapUv(m.positions, twoIndices, settings(10.0f)), std::invalid_argument);
  const std::vector<uint32_t> pastTheEnd = {0, 1, 8};
  EXPECT_THROW(generateLightmapUv(m.positions, pastTheEnd, settings(10.0f)), std::invalid_argument);
  std::vector<vec3> notFinite = m.positions;
  notFinite[3].y = INFINITY;
  EXPECT_THROW(generateLightmapUv(notFinite, m.indices, settings(10.0f)), std::invalid_argument);
}

TEST(LightmapUv, CubeGivesSixPlanarChartsAtTheExactDensity) {
  for (bool shared : {true, false}) {
    const TestMesh m = box(vec3(0.3f, 1.0f, -2.0f), vec3(1.0f), shared);
    const LightmapUvSettings s = settings(32.0f);
    const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
    checkAtlas(m, r, s, {});
    EXPECT_EQ(r.chartCount, 6u);
    EXPECT_EQ(chartSizes(r), std::vector<uint32_t>(6, 2));
    EXPECT_EQ(r.sourceVertex.size(), 24u);  // shared corners are split into one vertex per face
    EXPECT_EQ(r.texelsPerMetre, 32.0f);
    EXPECT_FALSE(r.densityReduced);
    // A face is 32 texels, 33 with margins, 35 with padding: two columns and three rows, and the border.
    EXPECT_EQ(r.width, 2u * 35u + 2u);
    EXPECT_EQ(r.height, 3u * 35u + 2u);
    std::printf("cube: %u×%u texels, utilisation %.3f\n", r.width, r.height, double(r.utilisation));
  }
}

TEST(LightmapUv, PlaneWithAHoleIsOneChart) {
  const TestMesh m =
      grid(vec3(-5, 0, -5), 10, 10, 1.0f, [](int i, int j) { return i >= 4 && i < 6 && j >= 4 && j < 6; });
  const LightmapUvSettings s = settings(8.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_EQ(r.chartCount, 1u);
  EXPECT_EQ(r.sourceVertex.size(), 11u * 11u - 1u);  // the hole's centre vertex is unused
  EXPECT_EQ(r.width, 81u + 4u);                      // 80 texels + margins + padding on both sides
  EXPECT_EQ(r.height, 81u + 4u);
}

TEST(LightmapUv, SeamsInTheInputDoNotSplitCharts) {
  // Every quad of a 6 × 4 m floor has its own vertices, some 1e-7 m off (exporter rounding).
  TestMesh m;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 6; ++i) {
      const float jitter = (i + j) % 2 == 0 ? 0.0f : 1e-7f;
      const uint32_t a = m.vertex(vec3(float(i) + jitter, 0.0f, float(j)));
      const uint32_t b = m.vertex(vec3(float(i + 1), 0.0f, float(j) - jitter));
      const uint32_t c = m.vertex(vec3(float(i + 1), 0.0f, float(j + 1)));
      const uint32_t d = m.vertex(vec3(float(i), jitter, float(j + 1)));
      m.triangleFacing(a, b, c, vec3(0, 1, 0));
      m.triangleFacing(a, c, d, vec3(0, 1, 0));
    }
  }
  const LightmapUvSettings s = settings(10.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_EQ(r.chartCount, 1u);
}

TEST(LightmapUv, TwoSidedWallKeepsOneChartPerSide) {
  // A 4 × 3 m wall with a back face: sharing the front's vertices, or with its own at the same places.
  for (bool sharedVertices : {true, false}) {
    TestMesh m = grid(vec3(0), 4, 3, 1.0f);
    TestMesh back = grid(vec3(0), 4, 3, 1.0f);
    const uint32_t base = sharedVertices ? 0u : uint32_t(m.positions.size());
    if (!sharedVertices) m.positions.insert(m.positions.end(), back.positions.begin(), back.positions.end());
    for (size_t i = 0; i < back.indices.size(); i += 3) {
      m.triangle(base + back.indices[i], base + back.indices[i + 2], base + back.indices[i + 1]);
    }
    const LightmapUvSettings s = settings(10.0f);
    const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
    checkAtlas(m, r, s, {});
    EXPECT_EQ(r.chartCount, 2u);
  }
}

TEST(LightmapUv, ChartsTurnToTheirMinimumAreaRectangle) {
  // A 8 m × 1 m strip turned 30° about +Y: its axis-aligned box would be 7.4 m × 4.9 m.
  TestMesh m = grid(vec3(0), 8, 1, 1.0f);
  const glm::mat3 turn = glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(30.0f), vec3(0, 1, 0)));
  for (vec3& p : m.positions) p = turn * p;
  const LightmapUvSettings s = settings(16.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_EQ(r.chartCount, 1u);
  EXPECT_EQ(std::max(r.width, r.height), 8u * 16u + 1u + 4u);
  EXPECT_EQ(std::min(r.width, r.height), 16u + 1u + 4u);
}

TEST(LightmapUv, CylinderSplitsIntoNearPlanarChartsWithoutFlips) {
  const TestMesh m = cylinder(1.0f, 2.0f, 48, 8);
  const LightmapUvSettings s = settings(32.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {.planarCharts = false});
  // 360° in pieces spanning about 2 × 30°.
  EXPECT_GE(r.chartCount, 5u);
  EXPECT_LE(r.chartCount, 12u);
  std::printf("cylinder: %u charts, %u×%u texels, utilisation %.3f\n", r.chartCount, r.width, r.height,
              double(r.utilisation));
}

TEST(LightmapUv, SphereSplitsIntoChartsWithoutFlipsOrOverlaps) {
  const TestMesh m = sphere(1.0f, 64, 32);
  const LightmapUvSettings s = settings(64.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {.planarCharts = false});
  EXPECT_GE(r.chartCount, 8u);
  std::printf("sphere: %u charts, %u×%u texels, utilisation %.3f\n", r.chartCount, r.width, r.height,
              double(r.utilisation));
}

// Triangles of random sizes from 1 mm to 2 m at random places and orientations, some sharing vertices, some
// repeated, some degenerate.
TEST(LightmapUv, RandomTriangleSoup) {
  uint32_t state = 12345;
  auto random = [&]() {
    state = state * 1664525u + 1013904223u;  // Numerical Recipes' LCG: deterministic everywhere
    return float(state >> 8) / float(1 << 24);
  };
  TestMesh m;
  for (int i = 0; i < 3000; ++i) {
    const float size = std::pow(10.0f, -3.0f + 3.3f * random());
    const vec3 c(20.0f * random(), 20.0f * random(), 20.0f * random());
    auto corner = [&]() { return c + size * vec3(random() - 0.5f, random() - 0.5f, random() - 0.5f); };
    const float kind = random();
    if (kind < 0.1f && i > 0) {
      m.triangle(m.indices[3 * size_t(i - 1)], m.indices[3 * size_t(i - 1) + 2],
                 m.vertex(corner()));  // shares an edge
    } else if (kind < 0.15f && i > 0) {
      const size_t t = size_t(random() * float(i - 1));
      m.triangle(m.indices[3 * t], m.indices[3 * t + 1], m.indices[3 * t + 2]);  // a duplicate
    } else if (kind < 0.2f) {
      const vec3 a = corner();
      const vec3 b = corner();
      m.triangle(m.vertex(a), m.vertex(b), m.vertex(0.5f * (a + b)));  // collinear
    } else {
      m.triangle(m.vertex(corner()), m.vertex(corner()), m.vertex(corner()));
    }
  }
  const LightmapUvSettings s = settings(10.0f, 2048);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {.planarCharts = false});
  std::printf("soup: %u charts, %u×%u texels, %.3f texels/m, utilisation %.3f\n", r.chartCount, r.width,
              r.height, double(r.texelsPerMetre), double(r.utilisation));
}

TEST(LightmapUv, SpiralRampThatCoversItselfIsSplit) {
  // Two turns of a ramp: one chart by its normals, but its projection would cover every texel twice.
  const TestMesh m = helix(1.0f, 3.0f, 2.0f, 0.5f, 64);
  const LightmapUvSettings s = settings(16.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {.planarCharts = false});
  EXPECT_GE(r.chartCount, 2u);
  std::printf("spiral ramp: %u charts, utilisation %.3f\n", r.chartCount, double(r.utilisation));
}

TEST(LightmapUv, DensityIsReducedWhenTheAtlasWouldBeTooLarge) {
  // 10 km of terrain and a 1 mm box 2.6 km from the origin in one mesh, at 10 texels/m: 100 000 texels wide.
  TestMesh m = grid(vec3(-5000, 0, -5000), 16, 16, 625.0f);
  m.append(box(vec3(1234.5f, 0.5f, -2345.25f), vec3(0.001f), true));
  const LightmapUvSettings s = settings(10.0f, 512);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_TRUE(r.densityReduced);
  EXPECT_FALSE(r.exceedsMaxAtlasSize);
  EXPECT_EQ(r.chartCount, 7u);  // the terrain and the box's 6 faces, 1 texel each
  // The terrain's side may take all but 7 texels (margins, padding and a 1-texel chart's row); the search
  // ends within 1 % of the largest density that fits.
  EXPECT_LT(r.texelsPerMetre, (512.0f - 7.0f) / 10000.0f);
  EXPECT_GT(r.texelsPerMetre, 0.99f * (512.0f - 8.0f) / 10000.0f);
  std::printf("terrain: %.5f texels/m, %u×%u texels\n", double(r.texelsPerMetre), r.width, r.height);
}

TEST(LightmapUv, DegenerateAndDuplicateTrianglesGetValidUvs) {
  TestMesh m = grid(vec3(0), 4, 4, 1.0f);
  const TestMesh plane = m;
  m.triangle(0, 1, 2);                            // collinear grid vertices: joins the plane's chart
  m.triangle(6, 6, 7);                            // a repeated index
  m.triangle(12, m.vertex(m.positions[12]), 13);  // a copy of a vertex: zero-length edge
  const uint32_t far = m.vertex(vec3(10, 5, 10));
  m.triangle(far, m.vertex(vec3(11, 5, 10)), m.vertex(vec3(12, 5, 10)));  // an isolated line
  m.triangle(far, far, far);                                              // an isolated point
  m.triangle(plane.indices[0], plane.indices[1], plane.indices[2]);       // a duplicate
  m.triangle(plane.indices[3], plane.indices[5], plane.indices[4]);       // its back face
  TestMesh overlay = grid(vec3(1, 0, 1), 1, 1, 1.0f);                     // coplanar geometry of its own
  m.append(overlay);
  const LightmapUvSettings s = settings(16.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  // The point and line share a chart collapsed to one point.
  const size_t line = plane.triangleCount() + 3;
  EXPECT_EQ(r.chartOfTriangle[line], r.chartOfTriangle[line + 1]);
  EXPECT_EQ(r.uv[r.indices[3 * line]], r.uv[r.indices[3 * line + 2]]);
  // The other degenerate triangles join the plane's charts.
  for (size_t t = plane.triangleCount(); t < line; ++t) {
    EXPECT_LT(r.chartOfTriangle[t], r.chartCount - 1) << "triangle " << t;
  }
}

TEST(LightmapUv, MeshOfOnlyDegenerateTrianglesIsOnePoint) {
  TestMesh m;
  const uint32_t a = m.vertex(vec3(0));
  m.triangle(a, m.vertex(vec3(1, 1, 1)), m.vertex(vec3(2, 2, 2)));
  m.triangle(a, a, m.vertex(vec3(0, 5, 0)));
  const LightmapUvSettings s = settings(10.0f);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_EQ(r.chartCount, 1u);
  EXPECT_EQ(r.width, 5u);  // one texel and the padding around it
  EXPECT_EQ(r.height, 5u);
  for (const vec2& uv : r.uv) EXPECT_EQ(uv, vec2(0.5f));
}

TEST(LightmapUv, GrowsPastTheMaximumOnlyWhenOneTexelChartsCannotFit) {
  // Six charts of (1 + 2)² texels need 54 texels; an 8² atlas has 6² inside its padding.
  const TestMesh m = box(vec3(0), vec3(1), true);
  const LightmapUvSettings s = settings(32.0f, 8);
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, r, s, {});
  EXPECT_TRUE(r.densityReduced);
  EXPECT_TRUE(r.exceedsMaxAtlasSize);
  EXPECT_LE(r.width, 8u);
  EXPECT_GT(r.height, 8u);
  EXPECT_EQ(r.chartCount, 6u);
  // The smallest atlas allowed, one texel inside its padding: the charts stand in one column.
  const LightmapUvSettings narrow = settings(32.0f, 5);
  const LightmapUv column = generateLightmapUv(m.positions, m.indices, narrow);
  checkAtlas(m, column, narrow, {});
  EXPECT_TRUE(column.exceedsMaxAtlasSize);
  EXPECT_EQ(column.width, 5u);
  EXPECT_EQ(column.height, 2u + 6u * 3u);
}

TEST(LightmapUv, IsDeterministic) {
  TestMesh m = cylinder(1.0f, 2.0f, 37, 5);
  m.append(helix(1.0f, 2.0f, 1.5f, 0.4f, 40));
  m.append(box(vec3(5, 0, 0), vec3(0.5f, 2.0f, 1.0f), false));
  const LightmapUvSettings s = settings(20.0f, 256);
  const LightmapUv a = generateLightmapUv(m.positions, m.indices, s);
  const LightmapUv b = generateLightmapUv(m.positions, m.indices, s);
  checkAtlas(m, a, s, {.planarCharts = false});
  EXPECT_EQ(a.sourceVertex, b.sourceVertex);
  EXPECT_EQ(a.uv, b.uv);
  EXPECT_EQ(a.indices, b.indices);
  EXPECT_EQ(a.chartOfTriangle, b.chartOfTriangle);
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.texelsPerMetre, b.texelsPerMetre);
}

// 100 352 triangles of rolling terrain (slopes up to about 50°): many charts. The time is printed, not
// asserted (timings belong to bench/); the figure in the report is from an -O2 build.
TEST(LightmapUv, HundredThousandTriangles) {
  const int quads = 224;
  TestMesh m = grid(vec3(-112, 0, -112), quads, quads, 1.0f);
  for (vec3& p : m.positions) {
    p.y = 6.0f * std::sin(0.11f * p.x) * std::cos(0.07f * p.z) + 0.5f * std::sin(0.31f * p.z + 0.5f * p.x);
  }
  const LightmapUvSettings s = settings(4.0f);
  const auto start = std::chrono::steady_clock::now();
  const LightmapUv r = generateLightmapUv(m.positions, m.indices, s);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  checkAtlas(m, r, s, {.planarCharts = false, .raster = false});
  std::printf("%zu triangles: %.3f s, %u charts, %u×%u texels, %.3f texels/m, utilisation %.3f\n",
              m.triangleCount(), seconds, r.chartCount, r.width, r.height, double(r.texelsPerMetre),
              double(r.utilisation));
}

}  // namespace
}  // namespace fly::rdb
