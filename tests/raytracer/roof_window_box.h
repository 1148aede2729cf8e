// The box lit through a roof window that the light-path and lit-patch tests share (header-only: the test
// glob compiles *_test.cpp): a closed box [−1, 1]³ of inward-facing walls, 4 × 4 quads a face, whose roof
// (y = 1, facing down) has a 1 m × 1 m hole in the middle, |x|, |z| < 0.5, optionally glazed.
#pragma once

#include <cstdint>

#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer::test {

// A pane of clear glass: Fresnel reflection of F0 = 0.04 as a preset glass, transmission 0.9, sharp.
inline uint32_t clearPaneMaterial(rdb::TraceRdbBuilder& b) {
  const uint32_t pane = b.material(Rgb(0.0f));
  rdb::TraceMaterial& m = b.rdb.materials[pane];
  m.reflection = Rgb(1.0f);
  m.transmission = Rgb(0.9f);
  m.transmissionGlossiness = 0.0f;
  return pane;
}

// The walls and the ceiling of material `walls`, the floor of `floor`, and in the hole a pane of `pane`
// (none when pane is kNoPane).
inline constexpr uint32_t kNoPane = ~0u;
inline void addRoofWindowBox(rdb::TraceRdbBuilder& b, uint32_t walls, uint32_t floor, uint32_t pane = kNoPane) {
  const vec3 lo(-1.0f);
  const vec3 x(2, 0, 0);
  const vec3 y(0, 2, 0);
  const vec3 z(0, 0, 2);
  b.grid(lo, x, y, 4, walls);
  b.grid(lo + z, y, x, 4, walls);
  b.grid(lo, y, z, 4, walls);
  b.grid(lo + x, z, y, 4, walls);
  b.grid(lo, z, x, 4, floor);
  // The roof in four pieces around the hole.
  b.grid(vec3(-1, 1, -1), vec3(2, 0, 0), vec3(0, 0, 0.5f), 4, walls);
  b.grid(vec3(-1, 1, 0.5f), vec3(2, 0, 0), vec3(0, 0, 0.5f), 4, walls);
  b.grid(vec3(-1, 1, -0.5f), vec3(0.5f, 0, 0), vec3(0, 0, 1), 2, walls);
  b.grid(vec3(0.5f, 1, -0.5f), vec3(0.5f, 0, 0), vec3(0, 0, 1), 2, walls);
  if (pane != kNoPane) b.grid(vec3(-0.5f, 1, -0.5f), vec3(1, 0, 0), vec3(0, 0, 1), 2, pane);
}

}  // namespace fly::raytracer::test
