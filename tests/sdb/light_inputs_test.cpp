// Lights given by luminous flux (lm) and colour temperature (K) in the scene file: the intensity they get
// emits the flux asked for, checked by integrating over the sphere the very intensity functions the baker
// evaluates; conflicting and out-of-range keys are errors at their JSON path.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <initializer_list>
#include <string>

#include "base/blackbody.h"
#include "base/error.h"
#include "base/spot_cone.h"
#include "sdb/light.h"
#include "sdb/scene_file.h"

namespace fly::sdb {
namespace {

Scene parse(const std::string& text) {
  return parseSceneFile(text, "s.json", FLY_TEST_DATA_DIR);
}

// The one light of a scene file (a copy: the scene is gone after the call).
Light onlyLight(const std::string& text) {
  const Scene s = parse(text);
  EXPECT_EQ(s.lights().size(), 1u);
  return s.lights().begin()->second;
}

// ∫ I(ω) dω over the sphere by the midpoint rule in (θ, φ), θ from the light's −Z axis (its direction),
// φ from +X; I receives the unit direction in the light's frame.
double integrateOverSphere(const std::function<double(double x, double y, double z)>& intensity, int nTheta,
                           int nPhi) {
  double sum = 0.0;
  const double dTheta = kPi / nTheta;
  const double dPhi = 2.0 * kPi / nPhi;
  for (int i = 0; i < nTheta; ++i) {
    const double theta = (i + 0.5) * dTheta;
    const double s = std::sin(theta);
    for (int j = 0; j < nPhi; ++j) {
      const double phi = (j + 0.5) * dPhi;
      sum += intensity(s * std::cos(phi), s * std::sin(phi), -std::cos(theta)) * s;
    }
  }
  return sum * dTheta * dPhi;
}

// The light's flux in lm as the baker sees it: luminance(color) × intensity × the integrated angular factor.
double integratedFluxLm(const Light& l, int nTheta, int nPhi) {
  const float cosInner = std::cos(l.innerConeRad);
  const float cosOuter = std::cos(l.outerConeRad);
  const auto factor = [&](double x, double y, double z) -> double {
    switch (l.type) {
      case LightType::kPoint:
        return 1.0;
      case LightType::kSpot:
        return spotConeAttenuation(static_cast<float>(-z), cosInner, cosOuter);
      // The photometric axis γ = 0 is local −Z, C = 0° local +X and C = 90° local +Y (sdb/light.h): the
      // profile's frame (IesProfile::candelaTowards) is (x, y, −z) of the light's.
      case LightType::kGoniometric:
        return l.ies->candelaTowards(x, y, -z);
      case LightType::kDirectional:
        return 0.0;
    }
    return 0.0;
  };
  return static_cast<double>(luminance(l.color)) * l.intensity * integrateOverSphere(factor, nTheta, nPhi);
}

TEST(LightInputs, PointLightFluxIsIntensityOverTheSphere) {
  const Light l = onlyLight(R"({"fly": 1, "lights": [
      {"type": "point", "position": [0, 2, 0], "flux": 800}]})");
  EXPECT_NEAR(l.intensity, 800.0 / (4.0 * kPi), 1e-4);  // 63.66 cd
  EXPECT_NEAR(luminousFluxLm(l), 800.0, 1e-3);
  EXPECT_NEAR(integratedFluxLm(l, 400, 16), 800.0, 0.01);
}

TEST(LightInputs, SpotLightFluxIntegratesTheConeFalloff) {
  for (const auto& [inner, outer] :
       {std::pair{20, 30}, std::pair{0, 45}, std::pair{0, 90}, std::pair{44, 45}}) {
    SCOPED_TRACE(::testing::Message() << inner << "°–" << outer << "°");
    const Light& l =
        onlyLight(R"({"fly": 1, "lights": [{"type": "spot", "position": [0, 2, 0],
        "direction": [0, -1, 0], "flux": 1200, "innerConeDeg": )" +
                  std::to_string(inner) + R"(, "outerConeDeg": )" + std::to_string(outer) + "}]}");
    EXPECT_NEAR(luminousFluxLm(l), 1200.0, 1200.0 * 1e-6);
    // Numerically, with KHR_lights_punctual's falloff as the baker applies it: within 0.05 %.
    EXPECT_NEAR(integratedFluxLm(l, 20000, 4), 1200.0, 1200.0 * 5e-4);
  }
  // Inner 20°, outer 30°: I = Φ / (2π [(1 − cos 20°) + (cos 20° − cos 30°)/3]) = 1200 lm / 0.5332 sr = 2250 cd.
  const Light l = onlyLight(R"({"fly": 1, "lights": [{"type": "spot", "position": [0, 2, 0],
      "flux": 1200, "innerConeDeg": 20, "outerConeDeg": 30}]})");
  const double ci = std::cos(degToRad(20.0)), co = std::cos(degToRad(30.0));
  EXPECT_NEAR(l.intensity, 1200.0 / (2.0 * kPi * ((1.0 - ci) + (ci - co) / 3.0)), 0.05);
}

TEST(LightInputs, GoniometricLightsAreScaledToTheGivenFlux) {
  for (const char* file : {"ies/asymmetric_c_full_lm63-2002.ies", "ies/bilateral_c_90-270_iesna91.ies",
                           "eulumdat/isym3-c90-c270.ldt", "eulumdat/lambertian-downlight.ldt"}) {
    SCOPED_TRACE(file);
    const Light l = onlyLight(std::string(
                                  R"({"fly": 1, "lights": [{"type": "ies", "position": [0, 3, 0],
        "file": ")") + file + R"(", "flux": 2500}]})");
    ASSERT_TRUE(l.ies);
    EXPECT_NEAR(l.intensity, 2500.0 / l.ies->totalFluxLm(), 1e-6 * l.intensity);
    EXPECT_NEAR(luminousFluxLm(l), 2500.0, 2500.0 * 1e-6);
    // Integrating the interpolated table numerically: within 0.5 % (the midpoint rule against the exact
    // integral of the bilinear interpolant).
    EXPECT_NEAR(integratedFluxLm(l, 720, 720), 2500.0, 2500.0 * 0.005);
  }
  // Without a flux the multiplier is 1 and the light emits the file's own flux: 800 lm for the downlight
  // (1000 lm of lamps at LORL 80 %).
  const Light plain = onlyLight(R"({"fly": 1, "lights": [{"type": "ies", "position": [0, 3, 0],
      "file": "eulumdat/lambertian-downlight.ldt"}]})");
  EXPECT_EQ(plain.intensity, 1.0f);
  EXPECT_NEAR(luminousFluxLm(plain), 800.0, 1.0);
}

TEST(LightInputs, ColourTemperatureGivesTheBlackBodyColourAtUnitLuminance) {
  const Light l = onlyLight(R"({"fly": 1, "lights": [
      {"type": "point", "position": [0, 2, 0], "temperatureK": 2700, "flux": 800}]})");
  EXPECT_EQ(l.temperatureK, 2700.0f);
  const Rgb expected = planckianRec709(2700.0);
  EXPECT_NEAR(l.color.r, expected.r, 1e-6f);
  EXPECT_NEAR(l.color.g, expected.g, 1e-6f);
  EXPECT_NEAR(l.color.b, expected.b, 1e-6f);
  EXPECT_NEAR(luminance(l.color), 1.0f, 1e-6f);
  EXPECT_GT(l.color.r, l.color.b);  // warm
  // Unit luminance: the intensity is the photometric one, and the flux is what was asked for.
  EXPECT_NEAR(l.intensity, 800.0 / (4.0 * kPi), 1e-3);
  EXPECT_NEAR(integratedFluxLm(l, 400, 16), 800.0, 0.01);
  // Also with an intensity in candela, and for a directional light (lux).
  const Light sun = onlyLight(R"({"fly": 1, "lights": [
      {"type": "directional", "direction": [0, -1, 0], "intensity": 1000, "temperatureK": 5800}]})");
  EXPECT_NEAR(luminance(sun.color) * sun.intensity, 1000.0f, 1e-3f);
}

TEST(LightInputs, TintedLightsStillEmitTheGivenFlux) {
  // A colour whose luminance is not 1 scales the intensity, so that colour × intensity emits 800 lm.
  const Light l = onlyLight(R"({"fly": 1, "lights": [
      {"type": "point", "position": [0, 2, 0], "color": [1, 0.5, 0.2], "flux": 800}]})");
  EXPECT_NEAR(luminance(l.color) * l.intensity * 4.0 * kPi, 800.0, 1e-2);
  EXPECT_EQ(l.temperatureK, 0.0f);
}

// Expects an InputError whose text begins with "s.json:<where> (at <path>)" and contains each of `parts`.
void expectError(const std::string& text, const std::string& where, const std::string& path,
                 std::initializer_list<std::string> parts) {
  SCOPED_TRACE(text);
  try {
    parse(text);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string head = "s.json:" + where + " (at " + path + "):";
    EXPECT_EQ(what.substr(0, head.size()), head) << what;
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "missing: " << p << "\n" << what;
  }
}

TEST(LightInputs, ConflictsAndBadValuesAreErrorsAtTheirKey) {
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": 10, "flux": 800}]})",
      "1:81", "/lights/0/flux", {"key \"flux\" conflicts with \"intensity\"", "not both"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "ies", "position": [0, 1, 0], "file": "ies/isotropic_c_1000cd_lm63-2002.ies", "intensity": 2, "flux": 800}]})",
      "1:126", "/lights/0/flux", {"conflicts with \"intensity\"", "multiplier"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 8, "color": [1, 1, 1], "temperatureK": 3000}]})",
      "1:95", "/lights/0/temperatureK", {"key \"temperatureK\" conflicts with \"color\""});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 0}]})", "1:72",
              "/lights/0/flux", {"expected a number in lumens, > 0; got 0"});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": -5}]})", "1:72",
              "/lights/0/flux", {"got -5"});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": "800 lm"}]})", "1:72",
              "/lights/0/flux", {"expected a number in lumens"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 1, "temperatureK": 500}]})",
      "1:91", "/lights/0/temperatureK", {"colour temperature 500 K is outside [1000, 40000] K"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 1, "temperatureK": 50000}]})",
      "1:91", "/lights/0/temperatureK", {"50000 K is outside"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 1, "temperatureK": "warm"}]})",
      "1:91", "/lights/0/temperatureK", {"expected a number in kelvin"});
  expectError(R"({"fly": 1, "lights": [{"type": "directional", "flux": 100}]})", "1:47", "/lights/0/flux",
              {"does not apply to a directional light", "illuminance in lux"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "color": [0, 0, 0], "flux": 100}]})",
      "1:92", "/lights/0/flux", {"luminance 0 emits no flux"});
  // Neither: a point light needs its intensity or its flux.
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0]}]})", "1:23", "/lights/0",
              {"missing key \"intensity\"", "or \"flux\" in lumens"});
  // A flux no single-precision intensity can carry, and a cone too narrow to emit anything.
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "flux": 1e40}]})", "1:72",
              "/lights/0/flux", {"needs an intensity of", "beyond single precision"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "spot", "position": [0, 1, 0], "outerConeDeg": 0.001, "flux": 100}]})",
      "1:94", "/lights/0/flux", {"outer cone is this narrow emits no light"});
}

}  // namespace
}  // namespace fly::sdb
