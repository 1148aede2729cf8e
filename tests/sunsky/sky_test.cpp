#include "sunsky/sky.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include "base/error.h"
#include "sunsky/cie_sky.h"
#include "sunsky/clear_sky.h"
#include "sunsky/perez_sky.h"
#include "sunsky/sun_disc.h"

namespace fly::sunsky {
namespace {

TEST(SkyQuadrature, ConstantRadianceGivesPi) {
  // ∫ cos θ dω over the hemisphere = π, whatever the peak direction splitting the panels.
  for (const dvec3& peak : {dvec3(0, 0, 1), dvec3(0.3, 0.4, 0.866), dvec3(1, 0, 0), dvec3(0, 0.6, -0.8)}) {
    EXPECT_NEAR(integrateHemisphere([](const dvec3&) { return 1.0; }, peak), kPi, 1e-12);
  }
}

TEST(SkyQuadrature, CosineLobeMatchesClosedForm) {
  // f = cos θ: ∫ cos² θ dω = 2π/3.
  EXPECT_NEAR(integrateHemisphere([](const dvec3& d) { return d.z; }, dvec3(0.6, 0, 0.8)), 2.0 * kPi / 3.0,
              1e-12);
}

TEST(SkyQuadrature, SharpPeakAtTheZenithMatchesClosedForm) {
  // f = exp(k(cos θ − 1)): 2π ∫₀¹ μ e^{k(μ−1)} dμ = 2π (1/k − 1/k² + e^{−k}/k²). k = 200: a peak ≈ 6° wide.
  const double k = 200.0;
  const double exact = 2.0 * kPi * (1.0 / k - 1.0 / (k * k) + std::exp(-k) / (k * k));
  const double got =
      integrateHemisphere([k](const dvec3& d) { return std::exp(k * (d.z - 1.0)); }, dvec3(0, 0, 1));
  EXPECT_NEAR(got / exact, 1.0, 1e-5);
}

TEST(SkyQuadrature, ConeShapedPeakNearTheHorizon) {
  // f = exp(−5γ), γ the angle from a peak 10° above the horizon due west: a cusp like a circumsolar peak.
  // Reference: the midpoint rule about the peak (γ, ψ) on a fine grid.
  const dvec3 peak(-std::cos(degToRad(10.0)), 0.0, std::sin(degToRad(10.0)));
  const auto f = [&peak](const dvec3& d) {
    return std::exp(-5.0 * std::acos(std::clamp(glm::dot(d, peak), -1.0, 1.0)));
  };
  const dvec3 u(0, 1, 0);
  const dvec3 v = glm::cross(peak, u);
  const int n = 1000;
  double reference = 0.0;
  for (int i = 0; i < n; ++i) {
    const double g = (i + 0.5) * kPi / n;
    for (int j = 0; j < 2 * n; ++j) {
      const double psi = (j + 0.5) * kPi / n;
      const dvec3 d = std::cos(g) * peak + std::sin(g) * (std::cos(psi) * u + std::sin(psi) * v);
      if (d.z > 0.0) reference += f(d) * d.z * std::sin(g);
    }
  }
  reference *= (kPi / n) * (kPi / n);
  EXPECT_NEAR(integrateHemisphere(f, peak) / reference, 1.0, 1e-4);
}

TEST(SkyQuadrature, RejectsTooFewSteps) {
  EXPECT_THROW(integrateHemisphere([](const dvec3&) { return 1.0; }, dvec3(0, 0, 1), 1),
               std::invalid_argument);
}

TEST(SkyDirection, AzimuthIsClockwiseFromNorth) {
  const dvec3 east = sunDirectionEnu(90.0, 90.0);
  EXPECT_NEAR(east.x, 1.0, 1e-12);
  EXPECT_NEAR(east.y, 0.0, 1e-12);
  EXPECT_NEAR(east.z, 0.0, 1e-12);
  const dvec3 southHigh = sunDirectionEnu(30.0, 180.0);
  EXPECT_NEAR(southHigh.x, 0.0, 1e-12);
  EXPECT_NEAR(southHigh.y, -0.5, 1e-12);
  EXPECT_NEAR(southHigh.z, std::sqrt(3.0) / 2.0, 1e-12);
  EXPECT_NEAR(sunDirectionEnu(0.0, 123.0).z, 1.0, 1e-15);
  EXPECT_NEAR(sunDirectionEnu(180.0, 0.0).z, -1.0, 1e-15);
}

TEST(SkyDirection, RejectsAnglesOutOfRange) {
  EXPECT_THROW(sunDirectionEnu(-0.1, 0.0), InputError);
  EXPECT_THROW(sunDirectionEnu(180.1, 0.0), InputError);
  EXPECT_THROW(sunDirectionEnu(std::numeric_limits<double>::quiet_NaN(), 0.0), InputError);
  EXPECT_THROW(sunDirectionEnu(45.0, std::numeric_limits<double>::infinity()), InputError);
  try {
    sunDirectionEnu(181.0, 0.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "sun zenith angle 181° is outside [0°, 180°]");
  }
  try {
    sunDirectionEnu(std::numeric_limits<double>::quiet_NaN(), 0.0);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.message(), "sun zenith angle is not a number");
  }
}

TEST(SkyColour, D65WhiteIsNeutral) {
  // The D65 white point (x, y) = (0.3127, 0.3290) (ITU-R BT.709-6) maps to R = G = B = Y.
  const Rgb white = rec709FromChromaticity(0.3127, 0.3290, 100.0);
  EXPECT_NEAR(white.r, 100.0f, 0.1f);
  EXPECT_NEAR(white.g, 100.0f, 0.1f);
  EXPECT_NEAR(white.b, 100.0f, 0.1f);
  EXPECT_NEAR(luminance(white), 100.0f, 1e-3f);
}

TEST(SkyColour, OutOfGamutKeepsLuminanceAndStaysNonNegative) {
  // A spectral orange-red (x, y) = (0.69, 0.31) lies beyond the Rec.709 red primary.
  const Rgb c = rec709FromChromaticity(0.69, 0.31, 50.0);
  EXPECT_GE(c.r, 0.0f);
  EXPECT_GE(c.g, 0.0f);
  EXPECT_GE(c.b, 0.0f);
  EXPECT_NEAR(luminance(c), 50.0f, 1e-3f);
  EXPECT_EQ(rec709FromChromaticity(0.3, 0.3, 0.0), Rgb(0.0f));
}

// Valid inputs drawn at random, each sky probed at random directions above and below the horizon: nothing
// is NaN, Inf or negative.
TEST(SkySweep, NoNanInfOrNegativeForRandomValidInput) {
  std::mt19937 rng(20240611);
  const auto uniform = [&rng](double a, double b) {
    return std::uniform_real_distribution<double>(a, b)(rng);
  };
  const auto check = [&](const Sky& sky, const char* model) {
    for (int i = 0; i < 50; ++i) {
      const dvec3 dir = sunDirectionEnu(uniform(0.0, 180.0), uniform(0.0, 360.0));
      const Rgb l = sky.radianceCdM2(dir);
      ASSERT_TRUE(isFinite(l) && l.r >= 0.0f && l.g >= 0.0f && l.b >= 0.0f) << model;
    }
    // The zenith and the exact horizon.
    ASSERT_TRUE(isFinite(sky.radianceCdM2(dvec3(0, 0, 1))) && isFinite(sky.radianceCdM2(dvec3(0, 1, 0))))
        << model;
    const double e = horizontalIlluminanceLux(sky, 16);
    ASSERT_TRUE(std::isfinite(e) && e >= 0.0) << model;
  };
  for (int trial = 0; trial < 150; ++trial) {
    // Sun angles include the exact zenith, horizon and nadir now and then.
    const double pick = uniform(0.0, 1.0);
    const double sunZenith = pick < 0.05   ? 0.0
                             : pick < 0.1  ? 90.0
                             : pick < 0.15 ? 180.0
                                           : uniform(0.0, 180.0);
    const double sunAzimuth = uniform(-720.0, 720.0);
    const int dayOfYear = 1 + int(uniform(0.0, 365.99));

    const int type = 1 + int(uniform(0.0, 14.99));
    check(makeCieSky(type, sunZenith, sunAzimuth,
                     uniform(0.0, 1.0) < 0.5 ? CieNormalisation::zenithLuminanceCdM2(uniform(0.0, 3e4))
                                             : CieNormalisation::diffuseHorizontalLux(uniform(0.0, 6e4))),
          "CIE");

    PerezSkyInput perez;
    perez.sunZenithDeg = sunZenith;
    perez.sunAzimuthDeg = sunAzimuth;
    perez.dayOfYear = dayOfYear;
    perez.dewPointC = uniform(-40.0, 30.0);
    const bool lux = uniform(0.0, 1.0) < 0.5;
    perez.units = lux ? PerezSkyInput::Units::kIlluminanceLux : PerezSkyInput::Units::kIrradianceWm2;
    const double scale = lux ? 120000.0 : 1000.0;
    perez.directNormal = uniform(0.0, 1.0) < 0.1 ? 0.0 : uniform(0.0, scale);
    perez.diffuseHorizontal = uniform(0.0, 1.0) < 0.1 ? 0.0 : uniform(0.0, 0.5 * scale);
    const PerezSky perezSky = makePerezSky(perez);
    check(perezSky, "Perez");
    ASSERT_TRUE(std::isfinite(perezSky.directNormalLux()) && perezSky.directNormalLux() >= 0.0);

    const double turbidity = uniform(kMinTurbidity, kMaxTurbidity);
    check(makeClearSky(turbidity, sunZenith, sunAzimuth), "clear");
    check(makeClearSky(turbidity, sunZenith, sunAzimuth, uniform(0.0, 5e4)), "clear, normalised");

    SunDiscInput sun;
    sun.zenithDeg = sunZenith;
    sun.azimuthDeg = sunAzimuth;
    sun.turbidity = turbidity;
    sun.pressureHpa = uniform(300.0, 1100.0);
    sun.dayOfYear = dayOfYear;
    const SunDisc disc = clearSkySunDisc(sun);
    ASSERT_TRUE(isFinite(disc.normalIlluminanceLux) && isFinite(disc.radianceCdM2));
    ASSERT_GE(
        std::min({disc.normalIlluminanceLux.r, disc.normalIlluminanceLux.g, disc.normalIlluminanceLux.b}),
        0.0f);
    ASSERT_NEAR(glm::length(disc.dirEnu), 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace fly::sunsky
