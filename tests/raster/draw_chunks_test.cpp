// The per-vertex draw's chunks (raster/draw_chunks.h): a chunk is left out only where none of its triangles
// can reach the image, checked against every triangle's clip-space vertices, and views that see everything or
// nothing.
#include "raster/draw_chunks.h"

#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <random>

namespace fly::raster {
namespace {

// A 200 × 200 m ground of 2 · 300² triangles (rows along x) and, above it, scattered small triangles: two
// meshes.
struct Soup {
  std::vector<vec3> positionsM;
  std::vector<uint32_t> indices;
};

Soup groundAndSpecks() {
  Soup s;
  constexpr uint32_t kCells = 300;
  for (uint32_t j = 0; j <= kCells; ++j) {
    for (uint32_t i = 0; i <= kCells; ++i) {
      s.positionsM.push_back(vec3(-100.0f + 200.0f * float(i) / kCells, 0.0f, -100.0f + 200.0f * float(j) / kCells));
    }
  }
  for (uint32_t j = 0; j < kCells; ++j) {
    for (uint32_t i = 0; i < kCells; ++i) {
      const uint32_t a = j * (kCells + 1) + i, b = a + 1, c = a + kCells + 1, d = c + 1;
      s.indices.insert(s.indices.end(), {a, c, b, b, c, d});
    }
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-60.0f, 60.0f);
  for (int k = 0; k < 3000; ++k) {
    const vec3 p(u(rng), 0.5f + 0.1f * std::abs(u(rng)), u(rng));
    const uint32_t first = uint32_t(s.positionsM.size());
    s.positionsM.insert(s.positionsM.end(), {p, p + vec3(0.3f, 0, 0), p + vec3(0, 0.3f, 0)});
    s.indices.insert(s.indices.end(), {first, first + 1, first + 2});
  }
  return s;
}

// Whether a triangle lies wholly outside one clip plane of the rectangle (then it has no pixel there).
bool triangleOutside(const mat4& clipFromWorld, const NdcRect& rect, const vec3& a, const vec3& b, const vec3& c) {
  vec4 v[3] = {clipFromWorld * vec4(a, 1.0f), clipFromWorld * vec4(b, 1.0f), clipFromWorld * vec4(c, 1.0f)};
  auto all = [&](auto outside) { return outside(v[0]) && outside(v[1]) && outside(v[2]); };
  return all([&](const vec4& p) { return p.x < rect.x0 * p.w; }) || all([&](const vec4& p) { return p.x > rect.x1 * p.w; }) ||
         all([&](const vec4& p) { return p.y < rect.y0 * p.w; }) || all([&](const vec4& p) { return p.y > rect.y1 * p.w; }) ||
         all([&](const vec4& p) { return p.z < -p.w; }) || all([&](const vec4& p) { return p.z > p.w; });
}

struct Counts {
  size_t drawn = 0, visibleTriangles = 0, missed = 0;
};

Counts check(const Soup& s, const std::vector<DrawChunk>& chunks, const mat4& clipFromWorld, const NdcRect& rect) {
  std::vector<IndexRange> ranges;
  visibleRanges(chunks, clipFromWorld, rect, ranges);
  std::vector<char> drawn(s.indices.size() / 3, 0);
  Counts n;
  for (size_t r = 0; r < ranges.size(); ++r) {
    if (r > 0) EXPECT_LT(ranges[r - 1].firstIndex + ranges[r - 1].indexCount, ranges[r].firstIndex) << "unmerged";
    for (uint32_t i = ranges[r].firstIndex; i < ranges[r].firstIndex + ranges[r].indexCount; i += 3) drawn[i / 3] = 1;
    n.drawn += ranges[r].indexCount / 3;
  }
  for (size_t t = 0; t < drawn.size(); ++t) {
    const vec3& a = s.positionsM[s.indices[3 * t]];
    const vec3& b = s.positionsM[s.indices[3 * t + 1]];
    const vec3& c = s.positionsM[s.indices[3 * t + 2]];
    if (triangleOutside(clipFromWorld, rect, a, b, c)) continue;
    ++n.visibleTriangles;
    if (!drawn[t]) ++n.missed;
  }
  return n;
}

std::vector<DrawChunk> chunksOf(Soup& s) {
  std::vector<DrawChunk> chunks;
  const uint32_t groundIndices = 300u * 300u * 6u;
  appendDrawChunks(s.indices, 0, groundIndices, s.positionsM, chunks);
  appendDrawChunks(s.indices, groundIndices, uint32_t(s.indices.size()) - groundIndices, s.positionsM, chunks);
  return chunks;
}

TEST(DrawChunks, ChunksCoverTheMeshesInOrderWithTheirBoxes) {
  Soup s = groundAndSpecks();
  const Soup original = s;
  const std::vector<DrawChunk> chunks = chunksOf(s);
  // Each mesh's triangles are reordered among themselves, each with its three indices in winding order.
  using Triangle = std::array<uint32_t, 3>;
  auto trianglesOf = [](const Soup& x, size_t from, size_t to) {
    std::vector<Triangle> t;
    for (size_t i = from; i < to; i += 3) t.push_back({x.indices[i], x.indices[i + 1], x.indices[i + 2]});
    std::sort(t.begin(), t.end());
    return t;
  };
  EXPECT_EQ(trianglesOf(s, 0, 540000), trianglesOf(original, 0, 540000));
  EXPECT_EQ(trianglesOf(s, 540000, s.indices.size()), trianglesOf(original, 540000, s.indices.size()));
  EXPECT_NE(s.indices, original.indices);
  uint32_t next = 0;
  for (const DrawChunk& c : chunks) {
    EXPECT_EQ(c.firstIndex, next);
    EXPECT_LE(c.indexCount, 3 * kTrianglesPerChunk);
    EXPECT_EQ(c.indexCount % 3, 0u);
    for (uint32_t i = c.firstIndex; i < c.firstIndex + c.indexCount; ++i) {
      const vec3& p = s.positionsM[s.indices[i]];
      EXPECT_TRUE(glm::all(glm::greaterThanEqual(p, c.loM)) && glm::all(glm::lessThanEqual(p, c.hiM)));
    }
    next += c.indexCount;
  }
  EXPECT_EQ(next, s.indices.size());
  // No chunk spans the two meshes: the ground's 540 000 indices end a chunk.
  EXPECT_TRUE(std::any_of(chunks.begin(), chunks.end(), [](const DrawChunk& c) { return c.firstIndex + c.indexCount == 540000u; }));
}

// Perspective views from several places and a mirror-like narrow rectangle: no triangle that reaches the
// image is in a chunk left out, and the narrow views leave most of the scene out.
TEST(DrawChunks, NoVisibleTriangleIsLeftOut) {
  Soup s = groundAndSpecks();
  const std::vector<DrawChunk> chunks = chunksOf(s);
  const mat4 proj = glm::perspective(0.9f, 16.0f / 9.0f, 0.05f, 1000.0f);
  const mat4 views[] = {glm::lookAt(vec3(-22, 12, 26), vec3(0), vec3(0, 1, 0)),
                        glm::lookAt(vec3(0, 1.7f, 0), vec3(10, 1.7f, 3), vec3(0, 1, 0)),
                        glm::lookAt(vec3(90, 40, 90), vec3(95, 0, 95), vec3(0, 1, 0))};
  const NdcRect rects[] = {NdcRect{}, NdcRect{-0.1f, -0.3f, 0.05f, -0.2f}};
  for (const mat4& v : views) {
    for (const NdcRect& rect : rects) {
      const Counts n = check(s, chunks, proj * v, rect);
      EXPECT_EQ(n.missed, 0u);
      EXPECT_GE(n.drawn, n.visibleTriangles);
      if (rect.x1 - rect.x0 < 1.0f) EXPECT_LT(n.drawn, s.indices.size() / 3 / 4) << "a narrow view culls little";
    }
  }
}

// A mirror's pass: the oblique near plane on a pool 1 cm above the ground leaves the ground out (it lies
// behind the mirror), the specks above it in.
TEST(DrawChunks, AMirrorsPlaneLeavesOutWhatLiesBehindIt) {
  Soup s = groundAndSpecks();
  const std::vector<DrawChunk> chunks = chunksOf(s);
  // Camera-space mirror plane y = 0.01 (kept side y ≥ 0.01) as the near plane, by Lengyel's construction.
  const vec3 eye(-22, 12, 26);
  const mat4 mirror = glm::scale(glm::translate(mat4(1.0f), vec3(0, 0.02f, 0)), vec3(1, -1, 1));
  const mat4 cameraFromWorld = glm::lookAt(eye, vec3(0), vec3(0, 1, 0)) * mirror;
  mat4 proj = glm::perspective(0.9f, 16.0f / 9.0f, 0.05f, 1000.0f);
  const vec4 planeCamera = glm::transpose(glm::inverse(cameraFromWorld)) * vec4(0, 1, 0, -0.01f);
  const auto sign = [](float x) { return x > 0.0f ? 1.0f : (x < 0.0f ? -1.0f : 0.0f); };
  const vec4 q = glm::inverse(proj) * vec4(sign(planeCamera.x), sign(planeCamera.y), 1.0f, 1.0f);
  const vec4 c = planeCamera * (2.0f / glm::dot(planeCamera, q));
  for (int col = 0; col < 4; ++col) proj[col][2] = c[col] - proj[col][3];
  const Counts n = check(s, chunks, proj * cameraFromWorld, NdcRect{});
  EXPECT_EQ(n.missed, 0u);
  EXPECT_GT(n.visibleTriangles, 100u);
  EXPECT_LE(n.drawn, 3000u + kTrianglesPerChunk) << "the ground behind the mirror is drawn";
}

TEST(DrawChunks, NothingInViewDrawsNothing) {
  Soup s = groundAndSpecks();
  const std::vector<DrawChunk> chunks = chunksOf(s);
  const mat4 proj = glm::perspective(0.9f, 1.0f, 0.05f, 1000.0f);
  const Counts up = check(s, chunks, proj * glm::lookAt(vec3(0, 50, 0), vec3(0, 100, 1), vec3(0, 0, 1)), NdcRect{});
  EXPECT_EQ(up.drawn, 0u);
  std::vector<IndexRange> ranges;
  visibleRanges({}, proj, NdcRect{}, ranges);
  EXPECT_TRUE(ranges.empty());
}

}  // namespace
}  // namespace fly::raster
