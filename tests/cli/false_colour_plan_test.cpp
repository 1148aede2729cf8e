// The false-colour plan read back from its PNG: every sensor's pixel, looked up on the legend bar, gives the
// sensor's value in the legend's numbers; the legend's tick rows have the colours of their values; the file
// carries its metadata and print resolution.
#include "cli/false_colour_plan.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>

#include "base/file_io.h"
#include "base/image_io.h"
#include "base/png_metadata.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

class FalseColourPlan : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("fly_plan_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

Rgb8 pixelAt(const ImageU8& image, dvec2 px) {
  const int x = int(std::floor(px.x)), y = int(std::floor(px.y));
  const uint8_t* p = &image.pixels[(size_t(y) * size_t(image.width) + size_t(x)) * size_t(image.channels)];
  return {p[0], p[1], p[2]};
}

int distance(const Rgb8& a, const Rgb8& b) {
  return std::abs(a.r - b.r) + std::abs(a.g - b.g) + std::abs(a.b - b.b);
}

TEST_F(FalseColourPlan, SensorColoursReadBackAsTheirValuesOnTheLegend) {
  // 8 × 5 sensors 0.5 m apart; lux rising as 150·1.5^(column + row/2) from 150 to 5766 lx; one sensor
  // missing (a column in the room).
  PlanGrid grid;
  grid.values = {8, 5, {}};
  grid.originM = dvec2(-1.75, -1.0);
  grid.spacingM = 0.5;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 8; ++c) grid.values.values.push_back(150.0 * std::pow(1.5, c + 0.5 * r));
  }
  grid.values.values[2 * 8 + 3] = NAN;
  PlanDrawing d;
  d.title = "Illuminance";
  d.unit = "lx";
  d.scale = falseColourScale(grid.values.values, true);
  ASSERT_DOUBLE_EQ(d.scale.minValue, 100.0);
  ASSERT_DOUBLE_EQ(d.scale.maxValue, 10000.0);
  d.northPlan = dvec2(0.0, -1.0);
  d.metadata.text = {{"fly:sky", "cie:1, no sun"}};
  d.metadata.dotsPerInch = 300.0;
  const fs::path png = dir_ / "plan.png";
  drawFalseColourPlan(grid, d, png);
  const PlanLayout l = falseColourPlanLayout(grid, d);
  const ImageU8 image = readPng(png);
  ASSERT_EQ(image.width, l.widthPx);
  ASSERT_EQ(image.height, l.heightPx);

  // The legend bar's colour in each row, at its middle column.
  std::vector<Rgb8> legend;
  for (int y = int(l.legendTopPx); y < int(l.legendBottomPx); ++y) {
    legend.push_back(pixelAt(image, dvec2(l.legendLeftPx + 0.5 * l.legendWidthPx, y + 0.5)));
  }
  // Ticks: the row of each tick value has that value's colour.
  for (const double tick : d.scale.ticks()) {
    const double y = l.legendY(d.scale.fraction(tick));
    const int row = std::clamp(int(std::floor(y)), int(l.legendTopPx), int(l.legendBottomPx) - 1);
    EXPECT_LE(distance(legend[size_t(row - int(l.legendTopPx))], falseColour(d.scale.fraction(tick))), 9)
        << "tick " << tick;
  }
  // Sensors: the legend row nearest in colour to the sensor's pixel, read as a value on the legend's scale.
  int checked = 0;
  for (int r = 0; r < 5; ++r) {
    for (int c = 0; c < 8; ++c) {
      const double value = grid.values.at(c, r);
      const dvec2 px = l.pixel(grid.originM + grid.spacingM * dvec2(c, r));
      const Rgb8 seen = pixelAt(image, px);
      if (!std::isfinite(value)) {
        EXPECT_EQ(distance(seen, Rgb8{255, 255, 255}), 0) << "the missing sensor is white";
        continue;
      }
      size_t best = 0;
      for (size_t k = 1; k < legend.size(); ++k) {
        if (distance(legend[k], seen) < distance(legend[best], seen)) best = k;
      }
      const double t =
          (l.legendBottomPx - (l.legendTopPx + double(best) + 0.5)) / (l.legendBottomPx - l.legendTopPx);
      const double readBack = d.scale.valueAt(t);
      // The map's neighbouring rows differ by a byte or two: a few rows, i.e. ~3 % of the value on this
      // scale.
      EXPECT_NEAR(readBack, value, 0.04 * value) << "sensor (" << c << ", " << r << ")";
      ++checked;
    }
  }
  EXPECT_EQ(checked, 39);

  // The metadata and the print resolution.
  const PngMetadata m = readPngMetadata(readInputFile(png, "plan"));
  ASSERT_EQ(m.text.size(), 1u);
  EXPECT_EQ(m.text[0].first, "fly:sky");
  EXPECT_EQ(m.text[0].second, "cie:1, no sun");
  EXPECT_NEAR(m.dotsPerInch, 300.0, 0.01);
}

TEST_F(FalseColourPlan, LayoutRejectsEmptyGridsAndBadWidths) {
  PlanGrid grid;
  PlanDrawing d;
  EXPECT_THROW(falseColourPlanLayout(grid, d), std::invalid_argument);
  grid.values = {1, 1, {5.0}};
  d.widthPx = 100;
  EXPECT_THROW(falseColourPlanLayout(grid, d), std::invalid_argument);
  d.widthPx = 800;
  grid.spacingM = 0.0;
  EXPECT_THROW(falseColourPlanLayout(grid, d), std::invalid_argument);
  // One sensor is a plan.
  grid.spacingM = 1.0;
  d.scale = falseColourScale(grid.values.values, true);
  EXPECT_NO_THROW(drawFalseColourPlan(grid, d, dir_ / "one.png"));
}

}  // namespace
}  // namespace fly::cli
