#include "rdb/vertex_weld.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

namespace fly::rdb {
namespace {

TEST(VertexWeld, CoincidentVerticesWithEqualNormalsShareOnePoint) {
  const vec3 up(0, 1, 0), side(1, 0, 0);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<vec3> positions = {
      {0, 0, 0}, {1, 0, 0}, {0, 0, 0},           // 0 and 2 coincide
      {1, 0, 0},                                 // with 1
      {1e-7f, 0, 0},                             // within the tolerance of 0 (1e-6)
      {0, 0, 0},                                 // at 0 but with another normal: a crease
      {0.5f, 0, 0}, {nan, 0, 0}, {nan, 0, 0}};   // apart; non-finite never welds
  const std::vector<vec3> normals = {up, up, up, up, up, side, up, up, up};
  const std::vector<uint32_t> rep = weldCoincidentVertices(positions, normals, 1e-6f);
  EXPECT_EQ(rep, (std::vector<uint32_t>{0, 1, 0, 1, 0, 5, 6, 7, 8}));
  // Without normals, position alone decides.
  EXPECT_EQ(weldCoincidentVertices(positions, {}, 1e-6f)[5], 0u);
  // Normals within 1° are equal; 2° apart are not.
  const float a1 = 0.9f * 3.14159265f / 180.0f, a2 = 2.0f * 3.14159265f / 180.0f;
  const std::vector<vec3> p3 = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
  const std::vector<vec3> n3 = {up, {std::sin(a1), std::cos(a1), 0}, {-std::sin(a2), std::cos(a2), 0}};
  EXPECT_EQ(weldCoincidentVertices(p3, n3, 1e-6f), (std::vector<uint32_t>{0, 0, 2}));
}

TEST(VertexWeld, ToleranceScalesWithTheMesh) {
  EXPECT_FLOAT_EQ(weldToleranceM(10.0f), 1e-5f);
  EXPECT_FLOAT_EQ(weldToleranceM(0.0f), 1e-9f);
  EXPECT_FLOAT_EQ(weldToleranceM(std::numeric_limits<float>::infinity()), 1e-9f);
  // 10 km of ground (tolerance 1 cm): vertices 2 cm apart stay apart, ones 5 mm apart weld.
  const std::vector<vec3> p = {{10000.0f, 0, 0}, {10000.02f, 0, 0}, {10000.005f, 0, 0}};
  const std::vector<uint32_t> rep = weldCoincidentVertices(p, {}, weldToleranceM(10000.0f));
  EXPECT_NE(rep[0], rep[1]);
  EXPECT_EQ(rep[0], rep[2]);
}

}  // namespace
}  // namespace fly::rdb
