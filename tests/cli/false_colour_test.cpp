// The false-colour scale and map, the marching-squares iso-lines and the plan section.
#include "cli/false_colour.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cli/iso_contours.h"
#include "cli/plan_section.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::cli {
namespace {

TEST(FalseColour, LogScaleSpansTheDataWithOneTwoFiveTicks) {
  const std::vector<double> lux = {130.0, 0.0, NAN, 870.0, 8700.0};
  const FalseColourScale s = falseColourScale(lux, true);
  EXPECT_DOUBLE_EQ(s.minValue, 100.0);
  EXPECT_DOUBLE_EQ(s.maxValue, 10000.0);
  const std::vector<double> expected = {100, 200, 500, 1000, 2000, 5000, 10000};
  const std::vector<double> ticks = s.ticks();
  ASSERT_EQ(ticks.size(), expected.size());
  for (size_t i = 0; i < ticks.size(); ++i) EXPECT_NEAR(ticks[i], expected[i], 1e-9 * expected[i]);
  EXPECT_NEAR(s.fraction(1000.0), 0.5, 1e-12);
  EXPECT_NEAR(s.valueAt(0.25), 100.0 * std::sqrt(10.0), 1e-9);  // a quarter of two decades up
  EXPECT_EQ(s.fraction(0.0), 0.0);  // no light: the bottom colour, never NaN
  EXPECT_EQ(s.fraction(-5.0), 0.0);
  EXPECT_EQ(s.fraction(1e9), 1.0);
  EXPECT_EQ(s.fraction(NAN), 0.0);
}

TEST(FalseColour, LinearScaleFromZero) {
  const std::vector<double> df = {0.4, 3.7, 2.0};
  const FalseColourScale s = falseColourScale(df, false);
  EXPECT_DOUBLE_EQ(s.minValue, 0.0);
  EXPECT_DOUBLE_EQ(s.maxValue, 4.0);
  const std::vector<double> ticks = s.ticks();
  ASSERT_EQ(ticks.size(), 9u);  // 0, 0.5, … 4
  EXPECT_NEAR(ticks[1], 0.5, 1e-12);
  EXPECT_NEAR(s.fraction(1.0), 0.25, 1e-12);
  // A given range, and data without light.
  const FalseColourScale given = falseColourScale(df, true, std::pair(1.0, 10.0));
  EXPECT_DOUBLE_EQ(given.maxValue, 10.0);
  const std::vector<double> dark = {0.0, 0.0};
  EXPECT_DOUBLE_EQ(falseColourScale(dark, true).maxValue, 10.0);
  EXPECT_DOUBLE_EQ(falseColourScale(dark, false).maxValue, 1.0);
}

TEST(FalseColour, MapBrightensMonotonicallyAndItsColoursDiffer) {
  // Green's cubehelix keeps its brightness λ rising; in sRGB bytes the Rec. 709 luma must rise too (allowing
  // one byte of rounding), from dark to light, and no two colours 1/64 apart may coincide.
  double previous = -1.0;
  for (int i = 0; i <= 256; ++i) {
    const Rgb8 c = falseColour(i / 256.0);
    const double luma = 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b;
    EXPECT_GE(luma, previous - 1.0) << i;
    previous = luma;
  }
  const Rgb8 lo = falseColour(0.0), hi = falseColour(1.0);
  EXPECT_LT(0.2126 * lo.r + 0.7152 * lo.g + 0.0722 * lo.b, 60.0);
  EXPECT_GT(0.2126 * hi.r + 0.7152 * hi.g + 0.0722 * hi.b, 215.0);
  for (int i = 0; i < 64; ++i) {
    const Rgb8 a = falseColour(i / 64.0), b = falseColour((i + 1) / 64.0);
    EXPECT_GT(std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b), 2) << i;
  }
}

TEST(IsoContours, LinearFieldGivesAStraightLine) {
  ScalarGrid g{4, 3, {}};
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 4; ++c) g.values.push_back(10.0 * c);  // v = 10·column
  }
  const auto segments = isoContours(g, 25.0);
  ASSERT_EQ(segments.size(), 2u);  // one per row of squares
  for (const auto& s : segments) {
    EXPECT_NEAR(s[0].x, 2.5, 1e-12);
    EXPECT_NEAR(s[1].x, 2.5, 1e-12);
    EXPECT_NEAR(std::abs(s[1].y - s[0].y), 1.0, 1e-12);
  }
  // Squares with a missing sample get none; a level outside the data none.
  g.values[2] = NAN;  // column 2, row 0
  EXPECT_EQ(isoContours(g, 25.0).size(), 1u);
  EXPECT_TRUE(isoContours(g, 100.0).empty());
}

TEST(IsoContours, CircleOfDistancesAndSaddles) {
  // v = distance from the lattice's centre: the line at level 3 lies within the interpolation error of the
  // circle of radius 3, and closes (every end is shared by two segments).
  ScalarGrid g{13, 13, {}};
  for (int r = 0; r < 13; ++r) {
    for (int c = 0; c < 13; ++c) g.values.push_back(std::hypot(c - 6.0, r - 6.0));
  }
  const auto segments = isoContours(g, 3.0);
  EXPECT_GE(segments.size(), 16u);
  for (const auto& s : segments) {
    for (const dvec2& p : s) EXPECT_NEAR(glm::length(p - dvec2(6.0)), 3.0, 0.1);
  }
  // A saddle: corners 0 and 2 above; its mean above too, so corners 1 and 3 are cut off apart.
  ScalarGrid saddle{2, 2, {1.0, 0.0, 0.0, 1.0}};  // (0,0)=1, (1,0)=0, (0,1)=0, (1,1)=1
  const auto cut = isoContours(saddle, 0.4);
  ASSERT_EQ(cut.size(), 2u);
  for (const auto& s : cut) {
    // Each segment cuts off one of the below corners (1, 0) or (0, 1): both its ends lie near that corner.
    const dvec2 mid = 0.5 * (s[0] + s[1]);
    EXPECT_TRUE(glm::length(mid - dvec2(1, 0)) < 0.5 || glm::length(mid - dvec2(0, 1)) < 0.5);
  }
}

TEST(PlanSection, BoxWallsCutAtMidHeightGiveItsPerimeter) {
  rdb::TraceRdbBuilder b;
  const uint32_t m = b.material(Rgb(0.5f));
  // Walls of a 4 m × 2 m room, 3 m high, and a floor and ceiling (in no cut plane).
  b.grid(vec3(0, 0, 0), vec3(4, 0, 0), vec3(0, 3, 0), 3, m);
  b.grid(vec3(0, 0, 2), vec3(0, 3, 0), vec3(4, 0, 0), 3, m);
  b.grid(vec3(0, 0, 0), vec3(0, 3, 0), vec3(0, 0, 2), 3, m);
  b.grid(vec3(4, 0, 0), vec3(0, 0, 2), vec3(0, 3, 0), 3, m);
  b.grid(vec3(0, 0, 0), vec3(0, 0, 2), vec3(4, 0, 0), 2, m);
  b.grid(vec3(0, 3, 0), vec3(4, 0, 0), vec3(0, 0, 2), 2, m);
  const auto cut = horizontalSection(b.rdb, 1.2);
  double length = 0.0;
  for (const auto& s : cut) {
    length += glm::length(s[1] - s[0]);
    for (const dvec2& p : s) {
      const bool onWall = std::abs(p.x) < 1e-6 || std::abs(p.x - 4) < 1e-6 || std::abs(p.y) < 1e-6 ||
                          std::abs(p.y - 2) < 1e-6;
      EXPECT_TRUE(onWall) << p.x << ", " << p.y;
    }
  }
  EXPECT_NEAR(length, 12.0, 1e-5);
  // A cut through the grid's vertex rows (y = 1 exactly) counts every wall once, not twice.
  double atVertices = 0.0;
  for (const auto& s : horizontalSection(b.rdb, 1.0)) atVertices += glm::length(s[1] - s[0]);
  EXPECT_NEAR(atVertices, 12.0, 1e-5);
  EXPECT_TRUE(horizontalSection(b.rdb, 5.0).empty());
}

}  // namespace
}  // namespace fly::cli
