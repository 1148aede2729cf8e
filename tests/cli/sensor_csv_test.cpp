#include "cli/sensor_csv.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "base/error.h"

namespace fly::cli {
namespace {

TEST(SensorCsv, ColumnsInAnyOrderAndExtraColumnsKept) {
  const SensorTable t = parseSensorCsv("id, nz,ny,nx,z,y,x\r\nA,0,2,0,3,2,1\n\nB,-4,0,0,0,0,0\n", "s.csv");
  EXPECT_EQ(t.header, "id, nz,ny,nx,z,y,x");
  ASSERT_EQ(t.lines.size(), 2u);
  EXPECT_EQ(t.lines[0], "A,0,2,0,3,2,1");
  EXPECT_EQ(t.positionsM[0], vec3(1, 2, 3));
  EXPECT_EQ(t.normals[0], vec3(0, 1, 0));  // (0, 2, 0) normalised
  EXPECT_EQ(t.normals[1], vec3(0, 0, -1));
  EXPECT_EQ(t.lineNumbers, (std::vector<int>{2, 4}));  // the blank line 3 counts
}

// Normals at the ends of the float range: their squared length overflows (3e38) or underflows (1e-30) in
// float; the direction is still well defined and comes out with unit length (found by fuzzing:
// tests/fuzz/corpus/sensor_csv/regression-huge-normal.csv and regression-tiny-normal.csv).
TEST(SensorCsv, HugeAndTinyNormalsComeOutUnitLength) {
  const SensorTable t = parseSensorCsv("x,y,z,nx,ny,nz\n0,0,0,3e38,3e38,3e38\n0,0,0,1e-30,0,0\n", "s.csv");
  ASSERT_EQ(t.normals.size(), 2u);
  const float k = 1.0f / std::sqrt(3.0f);
  EXPECT_NEAR(t.normals[0].x, k, 1e-6f);
  EXPECT_NEAR(t.normals[0].y, k, 1e-6f);
  EXPECT_NEAR(t.normals[0].z, k, 1e-6f);
  EXPECT_EQ(t.normals[1], vec3(1, 0, 0));
}

TEST(SensorCsv, BadInputNamesTheLine) {
  const auto message = [](const char* text) {
    try {
      parseSensorCsv(text, "s.csv");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_NE(message("x,y,nx,ny,nz\n").find("s.csv:1"), std::string::npos);               // no "z" column
  EXPECT_NE(message("x,y,z,nx,ny,nz\n1,2,3,0,0\n").find("s.csv:2"), std::string::npos);  // too few fields
  EXPECT_NE(message("x,y,z,nx,ny,nz\n1,2,3,0,0,0\n").find("zero"), std::string::npos);
  EXPECT_NE(message("x,y,z,nx,ny,nz\n1,inf,3,0,0,1\n").find("not a finite number"), std::string::npos);
  EXPECT_NE(message("x,y,z,nx,ny,nz\n\"1\",2,3,0,0,1\n").find("quoted"), std::string::npos);
  EXPECT_NE(message("").find("no header"), std::string::npos);
  EXPECT_NE(message("x,y,z,nx,ny,nz\n").find("no sensors"), std::string::npos);
}

}  // namespace
}  // namespace fly::cli
