// The per-vertex meshes' draw cut into chunks of consecutive triangles, each with its world-space bounding
// box, so that a pass draws only the chunks that can reach its image: a mirrored pass (raster/renderer.cpp,
// drawReflections) sees the scene through its mirror's screen rectangle and in front of the mirror's plane,
// which for a pool on the ground leaves out the whole ground. A chunk is left out only where its box lies
// wholly outside one of the view's planes, so a chunk left out has no pixel in the image: the image is the
// same to the bit as with every chunk drawn (the triangles keep their order; only whole runs are skipped).
#pragma once

#include <cstdint>
#include <vector>

#include "base/math.h"

namespace fly::raster {

// One chunk: the element buffer's indices [firstIndex, firstIndex + indexCount) and the box of their
// vertices (world, metres).
struct DrawChunk {
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
  vec3 loM{0.0f}, hiM{0.0f};
};

// A run of consecutive indices to draw.
struct IndexRange {
  uint32_t firstIndex = 0;
  uint32_t indexCount = 0;
};

// Triangles per chunk: small enough that a chunk's box is local (a 387² ground's row is 774 triangles), large
// enough that culling a million triangles costs the CPU microseconds (2 000 boxes against 6 planes).
inline constexpr uint32_t kTrianglesPerChunk = 512;

// Appends the chunks of the triangle list indices[first, first + count) (count a multiple of 3), whose
// vertices are positionsM[index], to `chunks`: runs of kTrianglesPerChunk triangles (the last one shorter).
// A range of more than one chunk is first put into the Morton (Z-) order of its triangles' centroids
// (ties in their order), so that a chunk's box is compact rather than a strip of a long mesh. One mesh at a
// time, so that no chunk spans two meshes and a mesh's triangles stay among themselves.
void appendDrawChunks(std::vector<uint32_t>& indices, uint32_t first, uint32_t count,
                      const std::vector<vec3>& positionsM, std::vector<DrawChunk>& chunks);

// The sub-rectangle of normalised device coordinates a pass draws into, [x0, x1] × [y0, y1] within
// [−1, 1]²: the whole image, or a mirror's scissor rectangle.
struct NdcRect {
  float x0 = -1.0f, y0 = -1.0f, x1 = 1.0f, y1 = 1.0f;
};

// The chunks whose box is not wholly outside one of the six planes of `clipFromWorld`'s view volume narrowed
// to `rect` (the near plane being a mirror's plane where the projection is oblique), as index ranges, runs of
// adjacent visible chunks merged. A small tolerance keeps boxes that touch a plane.
void visibleRanges(const std::vector<DrawChunk>& chunks, const mat4& clipFromWorld, const NdcRect& rect,
                   std::vector<IndexRange>& ranges);

}  // namespace fly::raster
