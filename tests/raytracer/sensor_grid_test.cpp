#include "raytracer/sensor_grid.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fly::raytracer {
namespace {

void addTriangle(rdb::TraceRdb& rdb, const vec3& a, const vec3& b, const vec3& c) {
  const auto first = static_cast<uint32_t>(rdb.positionsM.size());
  rdb.positionsM.insert(rdb.positionsM.end(), {a, b, c});
  rdb.indices.insert(rdb.indices.end(), {first, first + 1, first + 2});
  rdb.triangleMaterial.push_back(0);
  for (const vec3& p : {a, b, c}) rdb.boundsM.extend(p);
}

// A quad a b c d, counter-clockwise seen from its front.
void addQuad(rdb::TraceRdb& rdb, const vec3& a, const vec3& b, const vec3& c, const vec3& d) {
  addTriangle(rdb, a, b, c);
  addTriangle(rdb, a, c, d);
}

// A horizontal square of half-size halfM at height y around (0, y, 0), facing up or down.
void addSquare(rdb::TraceRdb& rdb, float halfM, float y, bool up) {
  const vec3 a(-halfM, y, -halfM), b(-halfM, y, halfM), c(halfM, y, halfM), d(halfM, y, -halfM);
  if (up) {
    addQuad(rdb, a, b, c, d);
  } else {
    addQuad(rdb, a, d, c, b);
  }
}

// An axis-aligned box from lo to hi with outward faces; without its bottom face if `bottom` is false.
void addBox(rdb::TraceRdb& rdb, const vec3& lo, const vec3& hi, bool bottom = true) {
  const vec3 c[8] = {{lo.x, lo.y, lo.z}, {hi.x, lo.y, lo.z}, {hi.x, hi.y, lo.z}, {lo.x, hi.y, lo.z},
                     {lo.x, lo.y, hi.z}, {hi.x, lo.y, hi.z}, {hi.x, hi.y, hi.z}, {lo.x, hi.y, hi.z}};
  // Outward counter-clockwise faces: −z, +z, −x, +x, +y, −y.
  const int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 4, 7, 3}, {1, 2, 6, 5}, {3, 7, 6, 2}, {0, 1, 5, 4}};
  for (int f = 0; f < (bottom ? 6 : 5); ++f) {
    addQuad(rdb, c[faces[f][0]], c[faces[f][1]], c[faces[f][2]], c[faces[f][3]]);
  }
}

std::vector<GridSensor> grid(const rdb::TraceRdb& rdb, float heightM, float spacingM) {
  const EmbreeScene scene(rdb);
  std::vector<GridSensor> sensors = floorSensorGrid(rdb, scene, heightM, spacingM);
  for (const GridSensor& s : sensors) {
    EXPECT_TRUE(std::isfinite(s.positionM.x) && std::isfinite(s.positionM.y) && std::isfinite(s.positionM.z));
    EXPECT_EQ(s.normal, vec3(0, 1, 0));
    EXPECT_NEAR(s.positionM.y - s.floorHeightM, heightM, 1e-5f);
  }
  return sensors;
}

size_t countAt(const std::vector<GridSensor>& sensors, float floorHeightM) {
  size_t n = 0;
  for (const GridSensor& s : sensors) n += std::abs(s.floorHeightM - floorHeightM) < 1e-4f ? 1 : 0;
  return n;
}

bool inside(const GridSensor& s, float halfM) {
  return std::abs(s.positionM.x) < halfM && std::abs(s.positionM.z) < halfM;
}

TEST(SensorGrid, LatticeIsCentredWithHalfSpacingMargins) {
  rdb::TraceRdb rdb;
  addSquare(rdb, 5.0f, 0.0f, true);  // 10 m × 10 m ground
  EXPECT_EQ(floorGridColumnCount(rdb, 1.0f), 100.0);
  EXPECT_EQ(floorGridColumnCount(rdb, 0.01f), 1e6);
  EXPECT_EQ(floorGridColumnCount(rdb, 3.0f), 9.0);
  EXPECT_EQ(floorGridColumnCount(rdb, 50.0f), 1.0);
  EXPECT_EQ(floorGridColumnCount(rdb::TraceRdb{}, 1.0f), 0.0);

  const std::vector<GridSensor> s = grid(rdb, 0.85f, 1.0f);
  ASSERT_EQ(s.size(), 100u);
  EXPECT_NEAR(s.front().positionM.x, -4.5f, 1e-5f);
  EXPECT_NEAR(s.front().positionM.z, -4.5f, 1e-5f);
  EXPECT_NEAR(s.back().positionM.x, 4.5f, 1e-5f);
  EXPECT_NEAR(s.back().positionM.z, 4.5f, 1e-5f);
  EXPECT_NEAR(s.front().positionM.y, 0.85f, 1e-6f);
  // Ordered by z, then x.
  EXPECT_NEAR(s[1].positionM.x, -3.5f, 1e-5f);
  EXPECT_NEAR(s[1].positionM.z, -4.5f, 1e-5f);
  EXPECT_NEAR(s[10].positionM.x, -4.5f, 1e-5f);
  EXPECT_NEAR(s[10].positionM.z, -3.5f, 1e-5f);

  // 10 m is not a multiple of 3 m: 3 columns centred, 1 m margins.
  const std::vector<GridSensor> coarse = grid(rdb, 0.85f, 3.0f);
  ASSERT_EQ(coarse.size(), 9u);
  EXPECT_NEAR(coarse.front().positionM.x, -3.0f, 1e-5f);
  EXPECT_NEAR(coarse.back().positionM.z, 3.0f, 1e-5f);
}

TEST(SensorGrid, TwoFloorsGetSensorsOnBoth) {
  rdb::TraceRdb rdb;
  addSquare(rdb, 5.0f, 0.0f, true);
  addBox(rdb, vec3(-2, 3.0f, -2), vec3(2, 3.2f, 2));  // a raised slab 0.2 m thick, 4 m × 4 m
  const std::vector<GridSensor> s = grid(rdb, 0.85f, 1.0f);
  // The ground everywhere (the slab's underside is 3 m above it), and the 4 × 4 columns on the slab.
  ASSERT_EQ(s.size(), 116u);
  EXPECT_EQ(countAt(s, 0.0f), 100u);
  EXPECT_EQ(countAt(s, 3.2f), 16u);
  // The ground floor first, then the upper one.
  for (size_t i = 0; i < 100; ++i) EXPECT_NEAR(s[i].positionM.y, 0.85f, 1e-5f);
  for (size_t i = 100; i < s.size(); ++i) {
    EXPECT_NEAR(s[i].positionM.y, 4.05f, 1e-5f);
    EXPECT_TRUE(inside(s[i], 2.0f));
  }
}

TEST(SensorGrid, ObstaclesRemoveTheSensorsUnderThem) {
  for (const bool bottom : {true, false}) {
    SCOPED_TRACE(bottom ? "closed box" : "box without a bottom face");
    rdb::TraceRdb rdb;
    addSquare(rdb, 5.0f, 0.0f, true);
    addBox(rdb, vec3(-1, 0, -1), vec3(1, 2, 1), bottom);  // taller than the height, standing on the ground
    const std::vector<GridSensor> s = grid(rdb, 0.85f, 1.0f);
    // No ground sensor in the 2 × 2 columns inside the box; its top is a floor.
    EXPECT_EQ(countAt(s, 0.0f), 96u);
    EXPECT_EQ(countAt(s, 2.0f), 4u);
    for (const GridSensor& g : s) {
      if (g.floorHeightM < 1.0f) {
        EXPECT_FALSE(inside(g, 1.0f)) << g.positionM.x << " " << g.positionM.z;
      }
    }
  }
  // A table top 0.75 m high: nothing under it (its underside is closer than 0.85 m), sensors above it.
  rdb::TraceRdb rdb;
  addSquare(rdb, 5.0f, 0.0f, true);
  addBox(rdb, vec3(-1, 0.70f, -1), vec3(1, 0.75f, 1));
  const std::vector<GridSensor> s = grid(rdb, 0.85f, 1.0f);
  EXPECT_EQ(countAt(s, 0.0f), 96u);
  EXPECT_EQ(countAt(s, 0.75f), 4u);
}

TEST(SensorGrid, CeilingsAndSlopesAreNotFloors) {
  rdb::TraceRdb ceilingOnly;
  addSquare(ceilingOnly, 5.0f, 2.5f, false);
  EXPECT_TRUE(grid(ceilingOnly, 0.85f, 1.0f).empty());

  // A room's ground under a ceiling 2.5 m up: sensors on the ground only.
  rdb::TraceRdb room;
  addSquare(room, 5.0f, 0.0f, true);
  addSquare(room, 5.0f, 2.5f, false);
  const std::vector<GridSensor> s = grid(room, 0.85f, 1.0f);
  EXPECT_EQ(s.size(), 100u);
  EXPECT_EQ(countAt(s, 0.0f), 100u);
  // A ceiling lower than the height leaves none.
  EXPECT_TRUE(grid(room, 3.0f, 1.0f).empty());

  // A 45° ramp facing up is no floor.
  rdb::TraceRdb ramp;
  addQuad(ramp, vec3(-5, 0, -5), vec3(-5, 10, 5), vec3(5, 10, 5), vec3(5, 0, -5));
  EXPECT_TRUE(grid(ramp, 0.85f, 1.0f).empty());
}

TEST(SensorGrid, SpacingLargerThanTheSceneGivesOneSensorPerFloor) {
  rdb::TraceRdb rdb;
  addSquare(rdb, 5.0f, 0.0f, true);
  addBox(rdb, vec3(-2, 3.0f, -2), vec3(2, 3.2f, 2));
  const std::vector<GridSensor> s = grid(rdb, 0.85f, 50.0f);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_NEAR(s[0].positionM.x, 0.0f, 1e-6f);
  EXPECT_NEAR(s[0].positionM.z, 0.0f, 1e-6f);
  EXPECT_NEAR(s[0].positionM.y, 0.85f, 1e-5f);
  EXPECT_NEAR(s[1].positionM.y, 4.05f, 1e-5f);

  EXPECT_TRUE(grid(rdb::TraceRdb{}, 0.85f, 1.0f).empty());
}

}  // namespace
}  // namespace fly::raytracer
