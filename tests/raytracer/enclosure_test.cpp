// Points inside closed objects (raytracer/enclosure.h) and what a bake does with them.
#include "raytracer/enclosure.h"

#include <gtest/gtest.h>

#include "raytracer/baker.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using Builder = rdb::TraceRdbBuilder;

// An axis-aligned cube of edge `size` centred at c, its faces facing out (counter-clockwise seen from
// outside), one mesh per face.
void cube(Builder& b, const vec3& c, float size, uint32_t mat, bool twoSided = false) {
  const float h = 0.5f * size;
  const vec3 lo = c - vec3(h);
  const vec3 x(size, 0, 0), y(0, size, 0), z(0, 0, size);
  b.grid(lo + y, z, x, 1, mat, twoSided);   // top, +Y
  b.grid(lo, x, z, 1, mat, twoSided);       // bottom, −Y
  b.grid(lo + x, y, z, 1, mat, twoSided);   // +X
  b.grid(lo, z, y, 1, mat, twoSided);       // −X
  b.grid(lo + z, x, y, 1, mat, twoSided);   // +Z
  b.grid(lo, y, x, 1, mat, twoSided);       // −Z
}

TEST(Enclosure, InsideASmallClosedSolidButNotOutsideItNorInAHall) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.ground(4.0f, 4, mat);                            // the scene: about 11 m across, reach 0.28 m
  cube(b, vec3(0.0f, 0.5f, 0.0f), 0.2f, mat);        // a small closed solid in the air
  const EmbreeScene scene(b.rdb);
  const float reach = enclosureReachM(b.rdb);
  EXPECT_NEAR(reach, kEnclosureReachShare * glm::length(vec3(8.0f, 0.6f, 8.0f)), 1e-3f);
  uint64_t rays = 0;
  // Inside, on the bottom face looking up: every ray meets the inside (the back) of a face within 0.25 m.
  EXPECT_TRUE(isEnclosed(scene, vec3(0.0f, 0.4f, 0.0f), vec3(0, 1, 0), 1.0f, reach, rays));
  // The same face from below, and the top from above: open.
  EXPECT_FALSE(isEnclosed(scene, vec3(0.0f, 0.4f, 0.0f), vec3(0, -1, 0), 1.0f, reach, rays));
  EXPECT_FALSE(isEnclosed(scene, vec3(0.0f, 0.6f, 0.0f), vec3(0, 1, 0), 1.0f, reach, rays));
  // The ground looking up: open.
  EXPECT_FALSE(isEnclosed(scene, vec3(2.0f, 0.0f, 2.0f), vec3(0, 1, 0), 1.0f, reach, rays));
  EXPECT_GT(rays, 0u);

  // A hall of 3 m with its faces facing out, in the same scene: its inside shows backs too, but beyond the
  // reach of a small enclosure, so it stays open (a camera inside sees it).
  Builder hall;
  const uint32_t m2 = hall.material(Rgb(0.5f));
  hall.ground(4.0f, 4, m2);
  cube(hall, vec3(0.0f, 1.6f, 0.0f), 3.0f, m2);
  const EmbreeScene hallScene(hall.rdb);
  EXPECT_FALSE(isEnclosed(hallScene, vec3(0.0f, 0.1f, 0.0f), vec3(0, 1, 0), 1.0f, enclosureReachM(hall.rdb), rays));
  // No reach (an empty scene): nothing is enclosed.
  EXPECT_FALSE(isEnclosed(scene, vec3(0.0f, 0.4f, 0.0f), vec3(0, 1, 0), 1.0f, 0.0f, rays));
}

// A two-sided closed solid in the sun: the backs of its faces (its inside) are hidden, baked in the first pass
// only and left out of the 95th percentile; everything else is baked as without them.
TEST(Enclosure, HiddenVertexSidesTakeTheFirstPassOnlyAndStayOutOfTheError) {
  Builder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.ground(4.0f, 8, mat);
  cube(b, vec3(0.0f, 0.5f, 0.0f), 0.2f, mat, true);
  b.uniformSky(Rgb(2000.0f));
  b.sun(vec3(0.3f, 1.0f, 0.2f), Rgb(50000.0f));
  const EmbreeScene scene(b.rdb);
  BakeSettings settings;
  settings.estimate.firstPassSamples = 16;
  settings.estimate.maxSamples = 64;
  settings.estimate.threads = 2;
  const VertexLightMaps maps = bakeVertexLightMaps(b.rdb, scene, settings);
  ASSERT_EQ(maps.hiddenVertexSides.size(), b.rdb.meshes.size());
  EXPECT_EQ(maps.hiddenVertexSides[0], 0u);  // the ground
  for (size_t m = 1; m < b.rdb.meshes.size(); ++m) {
    EXPECT_EQ(maps.hiddenVertexSides[m], 4u) << "face " << m;  // each face's 4 back sides
    for (uint32_t v = b.rdb.meshes[m].firstVertex; v < b.rdb.meshes[m].firstVertex + 4; ++v) {
      // The inside is dark; its fronts took every pass.
      EXPECT_LT(luminance(maps.backLux[v]), 1e-3f * luminance(maps.frontLux[v]) + 1e-6f);
      EXPECT_EQ(maps.frontSamples[v], 64u);
    }
  }
}

}  // namespace
}  // namespace fly::raytracer
