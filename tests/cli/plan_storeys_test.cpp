// Plans of a building with several storeys (cli/plan_image.h, cli/storeys.h): a grid over two floors that
// overlap in plan gives one plan per storey, each showing its own sensors' values — read back from the PNG
// through the legend, as tests/cli/false_colour_plan_test.cpp does — and --storey draws one storey alone.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/error.h"
#include "base/file_io.h"
#include "base/image_io.h"
#include "base/png_metadata.h"
#include "cli/plan_image.h"
#include "cli/storeys.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

TEST(Storeys, FloorsLessThanTwoMetresAboveAStoreysLowestStayOnIt) {
  // A first floor 3.0 (8 sensors) and a step 3.4 on it; the ground 0 (12), a raised slab 0.3 (6) and table
  // tops 0.75 (2); a roof terrace 6.1 (6) and a chimney top 9.0 (1 sensor), in no particular order.
  std::vector<float> heights;
  auto add = [&](float h, int n) { heights.insert(heights.end(), size_t(n), h); };
  add(3.0f, 8);   // 0–7
  add(0.0f, 12);  // 8–19
  add(9.0f, 1);   // 20
  add(0.3f, 6);   // 21–26
  add(6.1f, 6);   // 27–32
  add(0.75f, 2);  // 33, 34
  add(3.4f, 1);   // 35
  auto range = [](size_t from, size_t to) {
    std::vector<size_t> v;
    for (size_t i = from; i <= to; ++i) v.push_back(i);
    return v;
  };
  const std::vector<Storey> s = gridStoreys(heights);
  ASSERT_EQ(s.size(), 3u);
  std::vector<size_t> ground = range(8, 19);
  for (const size_t i : range(21, 26)) ground.push_back(i);
  ground.insert(ground.end(), {33, 34});
  EXPECT_EQ(s[0].sensors, ground);
  EXPECT_DOUBLE_EQ(s[0].lowestFloorM, 0.0);
  EXPECT_NEAR(s[0].highestFloorM, 0.75, 1e-6);
  EXPECT_NEAR(s[0].mainFloorM, 0.0, 1e-9);
  std::vector<size_t> first = range(0, 7);
  first.push_back(35);
  EXPECT_EQ(s[1].sensors, first);
  EXPECT_NEAR(s[1].mainFloorM, 3.0, 1e-9);
  EXPECT_NEAR(s[1].highestFloorM, 3.4, 1e-6);
  // The chimney top, under a tenth of the largest storey's sensors, stays with the roof terrace below it.
  std::vector<size_t> roof = {20};
  for (const size_t i : range(27, 32)) roof.push_back(i);
  EXPECT_EQ(s[2].sensors, roof);
  EXPECT_NEAR(s[2].mainFloorM, 6.1, 1e-6);
  EXPECT_NEAR(s[2].highestFloorM, 9.0, 1e-6);
  EXPECT_TRUE(gridStoreys({}).empty());
  // A lone small group at the bottom (a sunken court's few sensors) joins the storey above it.
  const std::vector<Storey> sunken =
      gridStoreys({-2.5f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f});
  ASSERT_EQ(sunken.size(), 1u);
  EXPECT_NEAR(sunken[0].lowestFloorM, -2.5, 1e-6);
  EXPECT_NEAR(sunken[0].mainFloorM, 0.0, 1e-9);
  // --storey: a height within a storey's span picks it; below the lowest or 2 m above the highest floor,
  // none.
  EXPECT_EQ(storeyAt(s, 0.0), 0u);
  EXPECT_EQ(storeyAt(s, 2.9), 0u);
  EXPECT_EQ(storeyAt(s, 3.85), 1u);
  EXPECT_EQ(storeyAt(s, 7.0), 2u);
  EXPECT_EQ(storeyAt(s, 10.5), 2u);
  EXPECT_THROW(storeyAt(s, -0.5), UsageError);
  EXPECT_THROW(storeyAt(s, 11.2), UsageError);
}

// Two storeys: a ground slab 6 m × 4 m at y = 0 and above its west part a 4 m × 4 m floor at y = 3 (a slab
// 0.2 m thick), sensors 0.85 m above them 1 m apart.
class TwoStoreys : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fly_storeys_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    rdb::TraceRdbBuilder b;
    const uint32_t grey = b.material(Rgb(0.5f));
    b.grid(vec3(0, 0, 0), vec3(0, 0, 4), vec3(6, 0, 0), 2, grey);     // ground, facing up
    b.grid(vec3(0, 3, 0), vec3(0, 0, 4), vec3(4, 0, 0), 2, grey);     // first floor, facing up
    b.grid(vec3(0, 2.8f, 0), vec3(4, 0, 0), vec3(0, 0, 4), 2, grey);  // its underside, facing down
    b.rdb.boundsM = Bounds3{vec3(0.0f), vec3(6.0f, 3.0f, 4.0f)};
    rdb_ = b.rdb;
    const raytracer::EmbreeScene embree(rdb_);
    sensors_ = gridSensors("0.85,1", GridSpec{0.85f, 1.0f, {}}, "two-storeys", rdb_, embree);
    // Values no storey shares: the ground 100 + 100 x lux, the first floor 2000 + 1000 z lux.
    for (const vec3& p : sensors_.table.positionsM)
      content_.values.push_back(p.y < 2.0f ? 100.0 + 100.0 * p.x : 2000.0 + 1000.0 * p.z);
    content_.title = "Illuminance, lux";
    content_.unit = "lx";
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Reads every sensor of storey k back from its plan's PNG through the legend; returns how many it checked.
  int expectPlanShowsStorey(const PlanImageOptions& o, const PlanStoreys& storeys, size_t k) {
    const PlanSheet sheet = planSheet(o, sensors_, content_, storeys, k, rdb_, scene_);
    const PlanLayout l = falseColourPlanLayout(sheet.grid, sheet.drawing);
    const ImageU8 image = readPng(sheet.path);
    EXPECT_EQ(image.width, l.widthPx);
    auto pixelAt = [&](dvec2 px) {
      const uint8_t* p =
          &image.pixels[(size_t(std::floor(px.y)) * size_t(image.width) + size_t(std::floor(px.x))) *
                        size_t(image.channels)];
      return Rgb8{p[0], p[1], p[2]};
    };
    auto distance = [](const Rgb8& a, const Rgb8& b) {
      return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
    };
    std::vector<Rgb8> legend;
    for (int y = int(l.legendTopPx); y < int(l.legendBottomPx); ++y)
      legend.push_back(pixelAt(dvec2(l.legendLeftPx + 0.5 * l.legendWidthPx, y + 0.5)));
    int checked = 0;
    for (const size_t i : storeys.all[k].sensors) {
      const vec3& p = sensors_.table.positionsM[i];
      const Rgb8 seen = pixelAt(l.pixel(dvec2(p.x, p.z)));
      size_t best = 0;
      for (size_t r = 1; r < legend.size(); ++r) {
        if (distance(legend[r], seen) < distance(legend[best], seen)) best = r;
      }
      const double t =
          (l.legendBottomPx - (l.legendTopPx + double(best) + 0.5)) / (l.legendBottomPx - l.legendTopPx);
      const double value = content_.values[i];
      EXPECT_NEAR(sheet.drawing.scale.valueAt(t), value, 0.04 * value)
          << sheet.path << ": sensor at (" << p.x << ", " << p.y << ", " << p.z << ")";
      ++checked;
    }
    return checked;
  }

  fs::path dir_;
  rdb::TraceRdb rdb_;
  sdb::Scene scene_;
  GridSensors sensors_;
  PlanContent content_;
};

TEST_F(TwoStoreys, EachStoreysPlanShowsItsOwnSensors) {
  ASSERT_EQ(sensors_.table.positionsM.size(), 24u + 16u);
  PlanImageOptions o;
  o.path = (dir_ / "plan.png").string();
  o.dotsPerInch = 300.0;
  const PlanStoreys storeys = planStoreys(o, sensors_);
  ASSERT_EQ(storeys.all.size(), 2u);
  EXPECT_EQ(storeys.drawn, (std::vector<size_t>{0, 1}));
  EXPECT_NEAR(storeys.all[0].mainFloorM, 0.0, 1e-6);
  EXPECT_NEAR(storeys.all[1].mainFloorM, 3.0, 1e-6);
  const std::vector<std::string> lines = writePlanImage(o, sensors_, content_, storeys, rdb_, scene_);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_NE(
      lines[1].find("plan of 16 of 40 sensors, storey 1 of 2 (floor at y = 3 m), section at y = 3.85 m"),
      std::string::npos)
      << lines[1];
  EXPECT_FALSE(fs::exists(dir_ / "plan.png"));
  // The ground floor's plan shows all 24 ground sensors, the ones under the first floor included; the first
  // floor's its 16.
  EXPECT_EQ(expectPlanShowsStorey(o, storeys, 0), 24);
  EXPECT_EQ(expectPlanShowsStorey(o, storeys, 1), 16);
  const PngMetadata m = readPngMetadata(readInputFile(dir_ / "plan-storey1.png", "plan"));
  EXPECT_NEAR(m.dotsPerInch, 300.0, 0.0127);
  bool storeyKey = false;
  for (const auto& [key, value] : m.text) {
    if (key == "Title") EXPECT_EQ(value, "Illuminance, lux, storey 1 of 2 (floor at y = 3 m)");
    storeyKey =
        storeyKey || (key == "fly:storey" && value.find("floors from y = 3 to 3 m") != std::string::npos);
  }
  EXPECT_TRUE(storeyKey);
}

TEST_F(TwoStoreys, StoreyOptionDrawsOneStoreyUnderTheGivenName) {
  PlanImageOptions o;
  o.path = (dir_ / "upper.png").string();
  o.storeyM = 3.0;
  const PlanStoreys storeys = planStoreys(o, sensors_);
  EXPECT_EQ(storeys.drawn, (std::vector<size_t>{1}));
  writePlanImage(o, sensors_, content_, storeys, rdb_, scene_);
  EXPECT_EQ(expectPlanShowsStorey(o, storeys, 1), 16);
  EXPECT_FALSE(fs::exists(dir_ / "upper-storey1.png"));
  o.storeyM = 9.0;
  EXPECT_THROW(planStoreys(o, sensors_), UsageError);
}

}  // namespace
}  // namespace fly::cli
