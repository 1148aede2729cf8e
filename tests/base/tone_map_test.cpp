#include "base/tone_map.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

namespace fly {
namespace {

TEST(ToneMap, AutoExposureMapsUniformLuminanceToMiddleGrey) {
  // A uniform 1000 cd/m² field: EV100 = log2(1000 · 100 / 12.5) = log2(8000) ≈ 12.966.
  const std::vector<float> l(1000, 1000.0f);
  const double ev = autoExposureEv100(l);
  EXPECT_NEAR(ev, std::log2(8000.0), 1e-9);
  // Displayed: 1000 / (1.2 · 8000) = 0.1042 (≈ 18 % grey through a meter calibrated with K = 12.5).
  EXPECT_NEAR(toneMap(Rgb(1000.0f), ev, ToneOperator::kLinear).g, 1000.0 / (1.2 * 8000.0), 1e-6);
}

TEST(ToneMap, AutoExposureIgnoresTheBrightestAndDarkestFivePercent) {
  std::vector<float> l(1000, 100.0f);
  for (int i = 0; i < 40; ++i) l[size_t(i)] = 1.0e9f;  // a sun disc: 4 % of the pixels
  for (int i = 40; i < 80; ++i) l[size_t(i)] = 0.0f;  // black pixels are ignored entirely
  for (int i = 80; i < 110; ++i) l[size_t(i)] = 1e-4f;  // 3 % very dark
  EXPECT_NEAR(autoExposureEv100(l), std::log2(100.0 * 100.0 / 12.5), 1e-9);
  EXPECT_EQ(autoExposureEv100(std::vector<float>{0.0f, NAN, INFINITY}), 0.0);
}

TEST(ToneMap, OperatorsAndEncoding) {
  // EV100 chosen so that Lmax = 1.2 · 2^EV = 100 cd/m².
  const double ev = std::log2(100.0 / 1.2);
  EXPECT_NEAR(toneMap(Rgb(50.0f), ev, ToneOperator::kLinear).r, 0.5f, 1e-6f);
  EXPECT_NEAR(toneMap(Rgb(500.0f), ev, ToneOperator::kLinear).r, 1.0f, 1e-6f);
  EXPECT_NEAR(toneMap(Rgb(100.0f), ev, ToneOperator::kReinhard).r, 0.5f, 1e-6f);  // x = 1 → 1/2
  EXPECT_EQ(toneMap(Rgb(-5.0f), ev, ToneOperator::kReinhard), Rgb(0.0f));
  EXPECT_EQ(encodeSrgb8(0.0f), 0);
  EXPECT_EQ(encodeSrgb8(1.0f), 255);
  EXPECT_EQ(encodeSrgb8(0.5f), 188);  // 1.055 · 0.5^(1/2.4) − 0.055 = 0.7354 → 187.5 → 188
  EXPECT_EQ(encodeSrgb8(0.002f), 7);  // linear segment: 12.92 · 0.002 · 255 = 6.59 → 7
  const std::vector<uint8_t> px = toneMapToSrgb8(std::vector<float>{50.0f, 0.0f, 1e30f}, ev, ToneOperator::kLinear);
  EXPECT_EQ(px, (std::vector<uint8_t>{188, 0, 255}));
}

}  // namespace
}  // namespace fly
