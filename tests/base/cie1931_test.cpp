#include "base/cie1931.h"

#include <gtest/gtest.h>

#include <cmath>

namespace fly {
namespace {

// CIE standard illuminant A, CIE 015:2018 eq. (3.1): S_A(λ) = 100 (560/λ)⁵ (exp(1.435e7/(2848·560)) − 1) /
// (exp(1.435e7/(2848 λ)) − 1), λ in nm.
double illuminantA(double nm) {
  return 100.0 * std::pow(560.0 / nm, 5.0) * std::expm1(1.435e7 / (2848.0 * 560.0)) /
         std::expm1(1.435e7 / (2848.0 * nm));
}

TEST(Cie1931, IlluminantAHasItsPublishedChromaticity) {
  // CIE 015:2018 Table 9.1 (and ISO 11664-2): x = 0.44757, y = 0.40745 for illuminant A.
  const dvec2 xy = chromaticity(cie1931Tristimulus(illuminantA));
  EXPECT_NEAR(xy.x, 0.44757, 2e-5);
  EXPECT_NEAR(xy.y, 0.40745, 2e-5);
}

TEST(Cie1931, EqualEnergyWhiteIsAtOneThird) {
  // The three functions have equal integrals by construction (CIE 1931), so S = 1 gives x = y = 1/3; the
  // abridged 5 nm table keeps this to 1e-4.
  const dvec3 xyz = cie1931Tristimulus([](double) { return 1.0; });
  const dvec2 xy = chromaticity(xyz);
  EXPECT_NEAR(xy.x, 1.0 / 3.0, 1e-4);
  EXPECT_NEAR(xy.y, 1.0 / 3.0, 1e-4);
  // ∫ V(λ) dλ = 106.857 nm (CIE 015:2018; 683 lm/W × 106.857 nm converts an equal-energy spectrum).
  EXPECT_NEAR(xyz.y, 106.857, 0.01);
}

TEST(Cie1931, PhotopicPeakAndInterpolation) {
  EXPECT_DOUBLE_EQ(cie1931ColourMatching(555.0).y, 1.0);  // V(555 nm) = 1
  const dvec3 a = cie1931ColourMatching(555.0);
  const dvec3 b = cie1931ColourMatching(560.0);
  const dvec3 mid = cie1931ColourMatching(557.5);
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(mid[i], 0.5 * (a[i] + b[i]), 1e-12);
  EXPECT_EQ(cie1931ColourMatching(359.9), dvec3(0.0));
  EXPECT_EQ(cie1931ColourMatching(830.1), dvec3(0.0));
  EXPECT_EQ(cie1931ColourMatching(std::nan("")), dvec3(0.0));
  EXPECT_GT(cie1931ColourMatching(830.0).x, 0.0);
  // A spectrum that is all zero has no chromaticity; it is reported as (0, 0), not NaN.
  EXPECT_EQ(chromaticity(cie1931Tristimulus([](double) { return 0.0; })), dvec2(0.0));
}

}  // namespace
}  // namespace fly
