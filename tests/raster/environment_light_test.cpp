// The image-based light's maps (raster/environment_light.h) against closed forms and independent CPU
// quadratures: a uniform environment, two hemispheres, a bright cap, and the split-sum table of fly's GGX.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "base/ggx.h"
#include "raster/environment_light.h"
#include "raster/gl_program.h"
#include "raster_test_scenes.h"
#include "split_sum_reference.h"

namespace fly::raster {
namespace {

using test::context;
using test::overWarpedHemisphere;
using test::splitSumByQuadrature;

EnvironmentLight::Compile compiler() { return linkGlProgram; }

// The direction of equirectangular pixel (x, y) of a width × height image (rdb::RasterSky's layout).
vec3 equirectDirection(uint32_t x, uint32_t y, uint32_t width, uint32_t height) {
  const double phi = (x + 0.5) / width * 2.0 * kPi, theta = (y + 0.5) / height * kPi;
  return vec3(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)), float(std::sin(theta) * std::sin(phi)));
}

template <class F>
std::vector<Rgb> equirect(uint32_t width, uint32_t height, const F& radiance) {
  std::vector<Rgb> image(size_t(width) * height);
  for (uint32_t y = 0; y < height; ++y)
    for (uint32_t x = 0; x < width; ++x) image[size_t(y) * width + x] = radiance(equirectDirection(x, y, width, height));
  return image;
}

// The direction through the centre of texel (x, y) of an n × n face (the OpenGL table, as the shaders).
vec3 cubeDirection(uint32_t face, uint32_t x, uint32_t y, uint32_t n) {
  const float s = (float(x) + 0.5f) / float(n) * 2.0f - 1.0f, t = (float(y) + 0.5f) / float(n) * 2.0f - 1.0f;
  const vec3 d[6] = {{1, -t, -s}, {-1, -t, s}, {s, 1, t}, {s, -1, -t}, {s, -t, 1}, {-s, -t, -1}};
  return glm::normalize(d[face]);
}

TEST(EnvironmentLight, UniformEnvironment) {
  context();
  const Rgb l(1000.0f, 500.0f, 250.0f);
  EnvironmentLight env(compiler(), {.cubePx = 32, .radianceLevels = 4, .prefilterSamples = 64, .irradiancePx = 4,
                                    .irradianceQuadPx = 16, .tablePx = 8, .tableSamples = 64});
  env.build(equirect(64, 32, [&](const vec3&) { return l; }), 64, 32);
  double worstE = 0.0, worstL = 0.0;
  for (uint32_t face = 0; face < 6; ++face) {
    for (const Rgb& e : env.readIrradiance(face))
      for (int c = 0; c < 3; ++c) worstE = std::max(worstE, std::abs(e[c] / (kPi * l[c]) - 1.0));
    for (uint32_t k = 0; k < 4; ++k)
      for (const Rgb& r : env.readRadiance(k, face))
        for (int c = 0; c < 3; ++c) worstL = std::max(worstL, std::abs(r[c] / l[c] - 1.0));
  }
  std::printf("uniform environment: irradiance worst relative error %.2e (π L), prefiltered radiance %.2e (L)\n",
              worstE, worstL);
  EXPECT_LT(worstE, 1e-3);
  EXPECT_LT(worstL, 1e-3);
}

// Two uniform hemispheres split at the horizon: a surface tilted from up sees them by its view factors,
// E = π (L_up (1 + n_y)/2 + L_down (1 − n_y)/2).
TEST(EnvironmentLight, IrradianceOfTwoHemispheres) {
  context();
  const float up = 4000.0f, down = 1000.0f;
  EnvironmentLight env(compiler(), {.cubePx = 64, .irradiancePx = 8, .irradianceQuadPx = 32, .tablePx = 8});
  env.build(equirect(256, 128, [&](const vec3& d) { return Rgb(d.y > 0.0f ? up : down); }), 256, 128);
  double worst = 0.0;
  for (uint32_t face = 0; face < 6; ++face) {
    const std::vector<Rgb> e = env.readIrradiance(face);
    for (uint32_t y = 0; y < 8; ++y) {
      for (uint32_t x = 0; x < 8; ++x) {
        const vec3 n = cubeDirection(face, x, y, 8);
        const double want = kPi * (up * (1.0 + n.y) / 2.0 + down * (1.0 - n.y) / 2.0);
        worst = std::max(worst, std::abs(e[y * 8 + x].g / want - 1.0));
      }
    }
  }
  std::printf("two hemispheres (%.0f / %.0f cd/m²): irradiance worst relative error %.4f over 384 normals\n", up,
              down, worst);
  EXPECT_LT(worst, 0.005);
}

TEST(EnvironmentLight, SplitSumTableAgainstQuadrature) {
  context();
  constexpr uint32_t kN = 16;
  EnvironmentLight env(compiler(), {.cubePx = 8, .radianceLevels = 2, .prefilterSamples = 16, .irradiancePx = 1,
                                    .irradianceQuadPx = 8, .tablePx = kN, .tableSamples = 4096});
  env.build(std::vector<Rgb>(8, Rgb(1.0f)), 4, 2);
  const std::vector<vec2> table = env.readSplitSum();
  double worst = 0.0;
  int compared = 0;
  for (uint32_t j : {2u, 5u, 9u, 15u}) {
    for (uint32_t i : {1u, 6u, 12u, 15u}) {
      const float cosO = (float(i) + 0.5f) / kN, rough = (float(j) + 0.5f) / kN;
      const vec2 want = splitSumByQuadrature(cosO, rough * rough);
      const vec2 got = table[j * kN + i];
      const double error = std::max(std::abs(got.x - want.x), std::abs(got.y - want.y)) / (want.x + want.y);
      worst = std::max(worst, error);
      ++compared;
    }
  }
  // A smooth lobe (√α = 1/32): a mirror with Schlick's Fresnel, A + B → 1, B → (1 − cos θo)⁵.
  double mirror = 0.0;
  for (uint32_t i = 0; i < kN; ++i) {
    const float cosO = (float(i) + 0.5f) / kN;
    const vec2 got = table[i];
    mirror = std::max({mirror, std::abs(got.x + got.y - 1.0), std::abs(got.y - std::pow(1.0 - cosO, 5.0))});
  }
  std::printf("split-sum table: worst error %.4f of A + B at %d texels against quadrature; smoothest row within "
              "%.4f of a mirror\n", worst, compared, mirror);
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(mirror, 0.01);
}

// The prefiltered levels against a quadrature of their definition, L_pre(r) = ∫ L(l) p(l) cos θl dl /
// ∫ p(l) cos θl dl with p(l) = D(h) / 4 about n = v = r.
template <class F>
double prefilteredByQuadrature(const vec3& r, float alpha, const F& radiance) {
  const float a2 = alpha * alpha;
  const vec3 t = glm::normalize(glm::cross(std::abs(r.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0), r));
  const mat3 worldFromLocal(t, glm::cross(r, t), r);
  double num = 0.0, den = 0.0;
  overWarpedHemisphere(1024, 512, [&](const vec3& local, double dOmega) {
    const vec3 l = worldFromLocal * local;
    const double w = ggxD(glm::dot(glm::normalize(l + r), r), a2) / 4.0 * local.z * dOmega;
    num += w * radiance(l);
    den += w;
  });
  return num / den;
}

// The worst relative error of levels 1 … 5 on face +Y at texels from its centre to its edge.
template <class F>
double worstPrefilterError(const char* what, const F& radiance) {
  EnvironmentLight env(compiler(), {.cubePx = 128, .radianceLevels = 6, .prefilterSamples = 1024,
                                    .irradiancePx = 4, .irradianceQuadPx = 16, .tablePx = 8});
  env.build(equirect(512, 256, [&](const vec3& d) { return Rgb(float(radiance(d))); }), 512, 256);
  double worst = 0.0;
  for (uint32_t k = 1; k < 6; ++k) {
    const uint32_t n = 128u >> k;
    const std::vector<Rgb> face = env.readRadiance(k, 2);  // +Y
    for (uint32_t x : {n / 2, n / 2 + n / 8, n / 2 + n / 4, n - 1}) {
      const vec3 r = cubeDirection(2, x, n / 2, n);
      const double want = prefilteredByQuadrature(r, env.levelAlpha(k), radiance);
      const double got = face[(n / 2) * n + x].g;
      const double error = std::abs(got / want - 1.0);
      std::printf("%s: level %u (α %.2f) %5.1f° from +Y: %8.1f against %8.1f (%.1f %%)\n", what, k,
                  env.levelAlpha(k), std::acos(std::min(1.0f, r.y)) * 180.0 / kPi, got, want, 100.0 * error);
      worst = std::max(worst, error);
    }
  }
  return worst;
}

// A smooth sky-like environment (brighter overhead and towards +X, a dark lower hemisphere): the prefiltered
// levels within 1 %.
TEST(EnvironmentLight, PrefilteredLevelsOfASmoothEnvironment) {
  context();
  const double worst = worstPrefilterError("smooth", [](const vec3& d) {
    return d.y > 0.0f ? 2000.0 + 6000.0 * d.y + 1500.0 * d.x * d.x + 1000.0 * d.x : 300.0;
  });
  EXPECT_LT(worst, 0.01);
}

// A bright cap of 15° around +Y over a dim rest (100 : 1): the filtered importance sampling's blur (each
// sample reads the mip level whose texel matches its solid angle) moves some of the cap's light towards the
// horizon, where the cosine weighs it less: within 6 %, mostly below.
TEST(EnvironmentLight, PrefilteredLevelsOfABrightCap) {
  context();
  const double capCos = std::cos(15.0 * kPi / 180.0);
  EXPECT_LT(worstPrefilterError("cap", [&](const vec3& d) { return d.y > capCos ? 10000.0 : 100.0; }), 0.06);
}

TEST(EnvironmentLight, RejectsBadSettingsAndImages) {
  context();
  EXPECT_THROW(EnvironmentLight(compiler(), {.cubePx = 4}), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(compiler(), {.cubePx = 64, .radianceLevels = 8}), std::invalid_argument);
  EXPECT_THROW(EnvironmentLight(compiler(), {.cubePx = 64, .irradianceQuadPx = 24}), std::invalid_argument);
  EnvironmentLight env(compiler(), {.cubePx = 8, .radianceLevels = 2, .prefilterSamples = 16, .irradiancePx = 1,
                                    .irradianceQuadPx = 8, .tablePx = 8, .tableSamples = 16});
  std::vector<Rgb> image(8, Rgb(1.0f));
  EXPECT_THROW(env.build(image, 3, 2), std::invalid_argument);
  image[5] = Rgb(1.0f, std::nanf(""), 1.0f);
  try {
    env.build(image, 4, 2);
    ADD_FAILURE() << "a NaN pixel was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pixel (1, 1)"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace fly::raster
