#include "cli/convergence_plot.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "base/image_io.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

// Errors from 8 % at 0.5 s down to 1 % at 32 s: seconds span the decades 10⁻¹…10², errors 10⁻²…10⁻¹.
const std::vector<raytracer::ConvergencePoint> kHistory = {
    {0.5, 16, 0.08f, 1e6}, {2.0, 64, 0.04f, 1e6}, {8.0, 256, 0.02f, 1e6}, {32.0, 1024, 0.01f, 1e6}};

TEST(ConvergencePlotTest, ConvergencePlotLayoutSpansWholeDecadesLogLinearly) {
  const ConvergencePlotRequest request{.widthPx = 900, .heightPx = 600};
  const ConvergencePlotLayout l = convergencePlotLayout(kHistory, request);
  EXPECT_EQ(l.log10SecondsMin, -1.0);
  EXPECT_EQ(l.log10SecondsMax, 2.0);
  EXPECT_EQ(l.log10ErrorMin, -2.0);
  EXPECT_EQ(l.log10ErrorMax, -1.0);
  const glm::dvec2 bottomLeft = l.pixel(0.1, 0.01), topRight = l.pixel(100.0, 0.1);
  EXPECT_NEAR(bottomLeft.x, l.topLeftPx.x, 1e-9);
  EXPECT_NEAR(bottomLeft.y, l.topLeftPx.y + l.sizePx.y, 1e-9);
  EXPECT_NEAR(topRight.x, l.topLeftPx.x + l.sizePx.x, 1e-9);
  EXPECT_NEAR(topRight.y, l.topLeftPx.y, 1e-9);
  // One decade in time is a third of the width; 1/√10 in error is half the height.
  EXPECT_NEAR(l.pixel(1.0, 0.01).x - bottomLeft.x, l.sizePx.x / 3.0, 1e-9);
  EXPECT_NEAR(bottomLeft.y - l.pixel(0.1, 0.01 * std::sqrt(10.0)).y, l.sizePx.y / 2.0, 1e-9);

  // A target below the points widens the error axis to hold it.
  const ConvergencePlotLayout t =
      convergencePlotLayout(kHistory, {.widthPx = 900, .heightPx = 600, .targetRelativeError = 0.005f});
  EXPECT_EQ(t.log10ErrorMin, -3.0);
}

TEST(ConvergencePlotTest, ConvergencePlotPointsAreDrawnWhereTheLayoutSays) {
  const fs::path png =
      fs::temp_directory_path() /
      ("fly_convergence_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + ".png");
  const ConvergencePlotRequest request{.widthPx = 800, .heightPx = 500, .targetRelativeError = 0.01f};
  drawConvergencePlot(kHistory, png, request);
  const ImageU8 image = readPng(png);
  fs::remove(png);
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, 500);
  ASSERT_EQ(image.channels, 3);
  const ConvergencePlotLayout l = convergencePlotLayout(kHistory, request);
  for (const raytracer::ConvergencePoint& p : kHistory) {
    const glm::dvec2 at = l.pixel(p.seconds, p.relativeErrorP95);
    const uint8_t* px = &image.pixels[3 * (size_t(at.y) * size_t(image.width) + size_t(at.x))];
    EXPECT_EQ(px[0], kConvergencePointRgb[0]) << p.seconds;
    EXPECT_EQ(px[1], kConvergencePointRgb[1]);
    EXPECT_EQ(px[2], kConvergencePointRgb[2]);
  }
}

TEST(ConvergencePlotTest, ConvergencePlotEmptyHistoryAndBadSize) {
  const ConvergencePlotLayout l = convergencePlotLayout({}, {});
  EXPECT_LT(l.log10SecondsMin, l.log10SecondsMax);
  EXPECT_LT(l.log10ErrorMin, l.log10ErrorMax);
  EXPECT_THROW(drawConvergencePlot({}, "unused.png", {.widthPx = 100}), std::invalid_argument);
}

}  // namespace
}  // namespace fly::cli
