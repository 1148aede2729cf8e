#include "base/tone_map.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <regex>
#include <stdexcept>
#include <string>
#include <utility>
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
  for (int i = 0; i < 40; ++i) l[size_t(i)] = 1.0e9f;   // a sun disc: 4 % of the pixels
  for (int i = 40; i < 80; ++i) l[size_t(i)] = 0.0f;    // black pixels are ignored entirely
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
  const std::vector<uint8_t> px =
      toneMapToSrgb8(std::vector<float>{50.0f, 0.0f, 1e30f}, ev, ToneOperator::kLinear);
  EXPECT_EQ(px, (std::vector<uint8_t>{188, 0, 255}));
}

// EV100 for which Lmax = 1.2 · 2^EV100 = 100 cd/m², i.e. x = L / 100.
const double kEvLmax100 = std::log2(100.0 / 1.2);
constexpr float kInf = std::numeric_limits<float>::infinity();

// Hable's curve with the constants of his 2010 post typed in independently, in double precision.
double hableReference(double x) {
  const double a = 0.15, b = 0.50, c = 0.10, d = 0.20, e = 0.02, f = 0.30;
  return (x * (a * x + c * b) + d * e) / (x * (a * x + b) + d * f) - e / f;
}

TEST(ToneMap, ExposureScaleIsInverseLmax) {
  EXPECT_FLOAT_EQ(exposureScale(0.0), float(1.0 / 1.2));
  EXPECT_FLOAT_EQ(exposureScale(kEvLmax100), 0.01f);
  EXPECT_FLOAT_EQ(exposureScale(10.0), float(1.0 / (1.2 * 1024.0)));
}

TEST(ToneMap, ReinhardWithWhitePointMapsTheWhitePointToOne) {
  for (float w : {1.5f, 4.0f, 11.2f, 100.0f}) {
    const ToneMapSettings s{ToneOperator::kReinhard, kEvLmax100, w};
    EXPECT_FLOAT_EQ(toneMap(Rgb(w / exposureScale(kEvLmax100)), s).g, 1.0f) << "white point " << w;
    EXPECT_EQ(toneMap(Rgb(10.0f * w / exposureScale(kEvLmax100)), s), Rgb(1.0f)) << "above the white point";
  }
  // Reinhard 2002 eq. 4 at x = 1, Lw = 4: 1 · (1 + 1/16) / 2 = 17/32; at x = 2: 2 · (1 + 2/16) / 3 = 0.75.
  const ToneMapSettings s{ToneOperator::kReinhard, kEvLmax100, 4.0f};
  EXPECT_NEAR(toneMap(Rgb(100.0f), s).r, 17.0 / 32.0, 1e-6);
  EXPECT_NEAR(toneMap(Rgb(200.0f), s).r, 0.75, 1e-6);
  // Without a white point (≤ 0 or +∞), eq. 3: x / (1 + x).
  EXPECT_NEAR(toneMap(Rgb(300.0f), {ToneOperator::kReinhard, kEvLmax100, 0.0f}).b, 0.75, 1e-6);
  EXPECT_NEAR(toneMap(Rgb(300.0f), {ToneOperator::kReinhard, kEvLmax100, kInf}).b, 0.75, 1e-6);
  // Channels are mapped independently.
  const Rgb c = toneMap(Rgb(0.0f, 100.0f, 200.0f), s);
  EXPECT_NEAR(c.r, 0.0f, 0.0f);
  EXPECT_NEAR(c.g, 17.0 / 32.0, 1e-6);
  EXPECT_NEAR(c.b, 0.75, 1e-6);
}

TEST(ToneMap, FilmicFollowsHablesPublishedCurve) {
  const ToneMapSettings s{ToneOperator::kFilmic, kEvLmax100, 4.0f};
  // display = f(b x) / f(11.2), Hable 2010 with linear white 11.2 and the exposure bias b = 5.0588 that shows
  // the metered grey at 0.18 (the next test).
  const double bias = 5.0588;
  for (double x : {0.0, 0.01, 0.1, 0.18, 0.5, 1.0, 2.0}) {
    const double expected = hableReference(bias * x) / hableReference(11.2);
    EXPECT_NEAR(toneMap(Rgb(float(100.0 * x)), s).g, expected, 2e-6) << "x = " << x;
  }
  EXPECT_NEAR(hableReference(11.2), 0.7251, 1e-4);  // f(W), worked out by hand from the constants
  EXPECT_EQ(toneMap(Rgb(0.0f), s), Rgb(0.0f));      // f(0) = DE/DF − E/F = 0
  EXPECT_EQ(toneMap(Rgb(230.0f), s).r, 1.0f);       // b x > W
  EXPECT_EQ(toneMap(Rgb(1.0e5f), s).r, 1.0f);
  // The whitePoint setting belongs to Reinhard and leaves the filmic curve alone.
  EXPECT_EQ(toneMap(Rgb(42.0f), s), toneMap(Rgb(42.0f), {ToneOperator::kFilmic, kEvLmax100, 1.0f}));
}

// A camera's calibration: an evenly lit 18 % grey card filling the image, metered by the automatic exposure
// (ISO 2720, K = 12.5), shows at 0.46 ± 0.04 of white in sRGB (a camera's JPEG: about 118 of 255), at any
// illuminance from moonlight to the sun's.
TEST(ToneMap, AnEvenlyLitGreyCardShowsAsACameraShowsIt) {
  for (double illuminanceLux : {0.3, 500.0, 100000.0}) {
    const float cardCdM2 = float(0.18 * illuminanceLux / kPi);
    const std::vector<float> image(64 * 64, cardCdM2);
    const double ev100 = autoExposureEv100Histogram(image);
    EXPECT_NEAR(ev100, std::log2(cardCdM2 * 100.0 / 12.5), 1e-6);
    const float shown = encodeSrgb(toneMap(Rgb(cardCdM2), {ToneOperator::kFilmic, ev100, 4.0f}).g);
    EXPECT_NEAR(shown, 0.46f, 0.04f) << illuminanceLux << " lx";
    EXPECT_NEAR(toneMap(Rgb(cardCdM2), {ToneOperator::kFilmic, ev100, 4.0f}).g, kDisplayMiddleGrey, 2e-4f);
  }
}

TEST(ToneMap, OperatorsAreMonotonicWithinZeroOne) {
  const ToneMapSettings settings[] = {{ToneOperator::kLinear, kEvLmax100, 4.0f},
                                      {ToneOperator::kReinhard, kEvLmax100, 4.0f},
                                      {ToneOperator::kReinhard, kEvLmax100, kInf},
                                      {ToneOperator::kFilmic, kEvLmax100, 4.0f}};
  for (const ToneMapSettings& s : settings) {
    float previous = 0.0f;
    for (int i = 0; i <= 1400; ++i) {  // L from 1e-4 to 1e10 cd/m², 100 steps per decade
      const float l = float(std::pow(10.0, -4.0 + i / 100.0));
      const float d = toneMap(Rgb(l), s).r;
      ASSERT_GE(d, previous) << "op " << int(s.op) << ", L = " << l;
      ASSERT_LE(d, 1.0f);
      previous = d;
    }
    EXPECT_GT(previous, 0.999f) << "op " << int(s.op) << " saturates";
  }
}

TEST(ToneMap, NonFiniteAndExtremeInputsGiveFiniteDisplayValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (ToneOperator op : {ToneOperator::kLinear, ToneOperator::kReinhard, ToneOperator::kFilmic}) {
    for (float w : {4.0f, 0.0f, kInf}) {
      const ToneMapSettings s{op, kEvLmax100, w};
      const Rgb zeroNanInf = toneMap(Rgb(0.0f, nan, kInf), s);
      EXPECT_EQ(zeroNanInf.r, 0.0f);
      EXPECT_EQ(zeroNanInf.g, 0.0f);  // NaN displays as black
      EXPECT_GT(zeroNanInf.b, 0.999f);
      EXPECT_LE(zeroNanInf.b, 1.0f);
      EXPECT_EQ(toneMap(Rgb(-kInf, -1.0f, std::numeric_limits<float>::max()), s).x, 0.0f);
      EXPECT_TRUE(isFinite(toneMap(Rgb(std::numeric_limits<float>::max()), s)));
      EXPECT_TRUE(isFinite(toneMap(Rgb(1.0e9f), {op, -40.0, w})));   // very high exposure
      EXPECT_TRUE(isFinite(toneMap(Rgb(1.0e-30f), {op, 40.0, w})));  // very low exposure
    }
  }
  EXPECT_EQ(encodeSrgb(nan), 0.0f);
  EXPECT_FLOAT_EQ(encodeSrgb(kInf), 1.0f);
  EXPECT_EQ(encodeSrgb(-1.0f), 0.0f);
}

TEST(ToneMap, GlslSourceDefinesTheFunctionsWithTheCpuConstants) {
  const std::string glsl = toneMapGlsl();
  EXPECT_NE(glsl.find("vec3 flyToneMap(vec3 cdM2, int op, float exposureScale, float whitePoint)"),
            std::string::npos);
  EXPECT_NE(glsl.find("vec3 flyEncodeSrgb(vec3 v)"), std::string::npos);
  EXPECT_EQ(glsl.find("#version"), std::string::npos);  // the includer chooses the version
  // Every float constant reads back as exactly the C++ value.
  const std::pair<const char*, float> floats[] = {{"kFlyMaxExposedValue", kMaxExposedValue},
                                                  {"kFlyHableA", kHableFilmic.a},
                                                  {"kFlyHableB", kHableFilmic.b},
                                                  {"kFlyHableC", kHableFilmic.c},
                                                  {"kFlyHableD", kHableFilmic.d},
                                                  {"kFlyHableE", kHableFilmic.e},
                                                  {"kFlyHableF", kHableFilmic.f},
                                                  {"kFlyHableW", kHableFilmic.w},
                                                  {"kFlyHableExposureBias", kHableFilmic.exposureBias},
                                                  {"kFlySrgbLinearLimit", 0.0031308f},
                                                  {"kFlySrgbLinearSlope", 12.92f},
                                                  {"kFlySrgbScale", 1.055f},
                                                  {"kFlySrgbOffset", 0.055f},
                                                  {"kFlySrgbGamma", 2.4f}};
  for (const auto& [name, value] : floats) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(glsl, m, std::regex(std::string("const float ") + name + " = ([^;]+);")))
        << name;
    EXPECT_EQ(std::strtof(m[1].str().c_str(), nullptr), value) << name << " = " << m[1];
    EXPECT_NE(m[1].str().find_first_of(".e"), std::string::npos) << name << " is a float literal";
  }
  const std::pair<const char*, ToneOperator> ops[] = {{"kFlyToneLinear", ToneOperator::kLinear},
                                                      {"kFlyToneReinhard", ToneOperator::kReinhard},
                                                      {"kFlyToneFilmic", ToneOperator::kFilmic}};
  for (const auto& [name, op] : ops) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(glsl, m, std::regex(std::string("const int ") + name + " = ([0-9]+);")));
    EXPECT_EQ(std::stoi(m[1].str()), int(op)) << name;
  }
  EXPECT_EQ(int(ToneOperator::kLinear), 0);
  EXPECT_EQ(int(ToneOperator::kReinhard), 1);
  EXPECT_EQ(int(ToneOperator::kFilmic), 2);
  // Balanced braces and parentheses: a cheap syntax check where no GLSL compiler is at hand.
  long braces = 0, parens = 0;
  for (char c : glsl) {
    braces += c == '{' ? 1 : c == '}' ? -1 : 0;
    parens += c == '(' ? 1 : c == ')' ? -1 : 0;
    ASSERT_GE(braces, 0);
    ASSERT_GE(parens, 0);
  }
  EXPECT_EQ(braces, 0);
  EXPECT_EQ(parens, 0);
}

TEST(ToneMap, ToneMapToSrgb8WithSettings) {
  const ToneMapSettings s{ToneOperator::kReinhard, kEvLmax100, 4.0f};
  // x = 4 → 1 → 255; x = 0.5 → 0.5 · 1.03125 / 1.5 = 0.34375 → sRGB 0.6211 → 158.4 → 158.
  const std::vector<uint8_t> px = toneMapToSrgb8(std::vector<float>{400.0f, 50.0f, 0.0f}, s);
  EXPECT_EQ(px, (std::vector<uint8_t>{255, 158, 0}));
}

// A "sky" whose luminance varies smoothly over 2 EV (from 2000 to 8000 cd/m²), one value per pixel.
std::vector<float> gradientImage(size_t n) {
  std::vector<float> l(n);
  for (size_t i = 0; i < n; ++i) l[i] = float(2000.0 * std::exp2(2.0 * (double(i) + 0.5) / double(n)));
  return l;
}

TEST(ToneMap, HistogramAutoExposureMapsUniformLuminanceToMiddleGrey) {
  for (float l : {1.0e-3f, 0.37f, 100.0f, 1000.0f, 3.2e5f}) {
    EXPECT_NEAR(autoExposureEv100Histogram(std::vector<float>(10000, l)), std::log2(double(l) * 100.0 / 12.5),
                1e-9)
        << "L = " << l;
  }
  EXPECT_NEAR(autoExposureEv100Histogram(std::vector<float>{50.0f}), std::log2(400.0), 1e-9);  // one pixel
}

TEST(ToneMap, HistogramAutoExposureIsRobustToASunDiscAndBlackPixels) {
  for (const std::vector<float>& base : {std::vector<float>(100000, 1000.0f), gradientImage(100000)}) {
    const double ev = autoExposureEv100Histogram(base);
    std::vector<float> withSun = base;  // a 0.1 % sun disc at 1e9 cd/m²
    for (size_t i = 0; i < base.size() / 1000; ++i) withSun[i * 997 % base.size()] = 1.0e9f;
    EXPECT_LT(std::abs(autoExposureEv100Histogram(withSun) - ev), 0.1);
    std::vector<float> withBlack = base;  // 5 % black pixels, appended (a black corner)
    withBlack.insert(withBlack.end(), base.size() / 20, 0.0f);
    EXPECT_LT(std::abs(autoExposureEv100Histogram(withBlack) - ev), 0.1);
    std::vector<float> withDark = base;  // 5 % nearly black pixels (0.001 cd/m²)
    withDark.insert(withDark.end(), base.size() / 20, 1.0e-3f);
    EXPECT_LT(std::abs(autoExposureEv100Histogram(withDark) - ev), 0.1);
    // A plain mean of log-luminance, by contrast, moves by ~0.05 · 20 EV = 1 EV with the dark pixels.
  }
}

TEST(ToneMap, HistogramAutoExposureAgreesWithASortedTrimmedMean) {
  // Luminances spread log-uniformly over 1e-2 … 1e6 cd/m² in a scrambled order; the reference sorts them and
  // averages log2 L over the sorted positions [10 %, 90 %) of n. Bins cut by a percentile contribute their
  // mean, so the two agree to a fraction of a bin (0.2 EV) weighted by 2 / (0.8 · 256 bins).
  const size_t n = 50000;
  std::vector<float> l(n);
  for (size_t i = 0; i < n; ++i)
    l[i] = float(std::pow(10.0, -2.0 + 8.0 * double((i * 7919) % n) / double(n)));
  std::vector<double> lg;
  for (float v : l) lg.push_back(std::log2(double(v)));
  std::sort(lg.begin(), lg.end());
  double sum = 0.0;
  for (size_t i = n / 10; i < n * 9 / 10; ++i) sum += lg[i];
  const double reference = sum / double(n * 8 / 10) + std::log2(100.0 / 12.5);
  EXPECT_NEAR(autoExposureEv100Histogram(l), reference, 0.01);
  // Other percentiles, chosen by the caller.
  AutoExposureSettings median;
  median.lowPercentile = 0.49f;
  median.highPercentile = 0.51f;
  EXPECT_NEAR(autoExposureEv100Histogram(l, median), lg[n / 2] + std::log2(100.0 / 12.5), 0.1);
}

TEST(ToneMap, HistogramAutoExposureOfNothingIsTheDocumentedDefault) {
  EXPECT_EQ(autoExposureEv100Histogram({}), 0.0);
  EXPECT_EQ(autoExposureEv100Histogram(std::vector<float>(100, 0.0f)), 0.0);
  EXPECT_EQ(autoExposureEv100Histogram(std::vector<float>{-1.0f, NAN, INFINITY, -INFINITY}), 0.0);
  AutoExposureSettings s;
  s.emptyEv100 = 7.0;
  EXPECT_EQ(autoExposureEv100Histogram(std::vector<float>(100, 0.0f), s), 7.0);
  // Luminances beyond the histogram's range are clamped to its ends: finite, never NaN.
  EXPECT_NEAR(autoExposureEv100Histogram(std::vector<float>(10, 1.0e30f)), 32.0 + 3.0, 1e-9);
  EXPECT_NEAR(autoExposureEv100Histogram(std::vector<float>(10, 1.0e-30f)), -20.0 + 3.0, 1e-9);
}

TEST(ToneMap, HistogramAutoExposureRejectsBadSettings) {
  AutoExposureSettings s;
  s.lowPercentile = 0.9f;
  s.highPercentile = 0.5f;
  EXPECT_THROW(autoExposureEv100Histogram(std::vector<float>{1.0f}, s), std::invalid_argument);
  s = {};
  s.binCount = 0;
  EXPECT_THROW(autoExposureEv100Histogram(std::vector<float>{1.0f}, s), std::invalid_argument);
}

}  // namespace
}  // namespace fly
