// Ball textures (raster/ball_texture.h; FLY §4) against the SDB's own BRDF evaluation on the CPU: the ball
// per texel under 5 distant lights, the environment term against fine quadrature, a rendered sphere per pixel,
// where the distant-light approximation breaks down, and what is left out or reused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "../support/helsinki_daylight.h"
#include "../support/measured_tables.h"
#include "raster/ball_texture.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/car_paint_brdf.h"
#include "sdb/material.h"
#include "sdb/measured_brdf.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

// A paint whose coat (GGX α 0.08) keeps its highlight several texels wide on a 256² ball and several pixels
// on the 160² sphere, so that the per-pixel comparisons measure the method, not the sampling of a
// sub-pixel highlight (the silver preset's α 0.01 is measured apart below).
sdb::CarPaintBrdf testPaint() {
  sdb::CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.35f, 0.05f, 0.04f);
  p.lobes[0] = {Rgb(0.4f, 0.3f, 0.2f), 0.25f};
  p.lobes[1] = {Rgb(0.05f, 0.05f, 0.1f), 0.6f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.08f;
  return p;
}

// The silver metallic preset's paint (sdb/material_presets.cpp): a coat of GGX α 0.01.
sdb::CarPaintBrdf silverPaint() {
  sdb::CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.1f);
  p.lobes[0] = {Rgb(0.45f, 0.46f, 0.48f), 0.2f};
  p.lobes[1] = {Rgb(0.1f), 0.5f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.01f;
  return p;
}

// The BRDF under test as the SDB evaluates it.
struct Brdf {
  std::shared_ptr<const sdb::MeasuredBrdf> table;
  sdb::CarPaintBrdf paint;
  Rgb operator()(const vec3& wi, const vec3& wo) const {
    return table ? table->evalPerSr(wi, wo) : paint.evalPerSr(wi, wo);
  }
};

// The 5 lights of the tests: directions towards them (world) and illuminance (lux), some coloured, one
// grazing, one from below the ball's equator.
struct TestLight {
  vec3 toLight;
  Rgb lux;
};
std::vector<TestLight> fiveLights() {
  return {{glm::normalize(vec3(0.3f, 0.5f, 1.0f)), Rgb(1000.0f)},
          {glm::normalize(vec3(-0.6f, 0.2f, 0.8f)), Rgb(700.0f, 650.0f, 500.0f)},
          {glm::normalize(vec3(0.5f, -0.4f, 0.7f)), Rgb(400.0f, 450.0f, 600.0f)},
          {glm::normalize(vec3(-0.2f, -0.7f, 0.6f)), Rgb(800.0f)},
          {glm::normalize(vec3(0.95f, 0.3f, 0.1f)), Rgb(300.0f)}};
}

// Luminance at the surface point with normal n seen from direction wo (both world), under `lights` (distant),
// by the SDB's evaluation in a frame about n.
Rgb referenceLuminance(const Brdf& brdf, const vec3& n, const vec3& wo, const std::vector<TestLight>& lights) {
  const vec3 t = glm::normalize(glm::cross(std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0), n));
  const vec3 b = glm::cross(n, t);
  auto local = [&](const vec3& d) { return vec3(glm::dot(d, t), glm::dot(d, b), glm::dot(d, n)); };
  Rgb l(0.0f);
  for (const TestLight& light : lights) {
    const vec3 wi = local(light.toLight);
    if (wi.z > 0.0f) l += brdf(wi, local(wo)) * wi.z * light.lux;
  }
  return l;
}

// A scene of one sphere (radius 1 at the origin, 64 × 128 quads) of the BRDF, the given directional lights and
// no ambient light: the ball's environment term is tested apart.
struct SphereScene {
  sdb::Scene scene;
  rdb::RasterRdb rdb;
};
SphereScene sphereScene(const Brdf& brdf, const std::vector<TestLight>& lights) {
  SphereScene s;
  sdb::Material m;
  m.name = "paint";
  if (brdf.table) {
    m.measuredBrdf = brdf.table;
  } else {
    m.carPaint = brdf.paint;
  }
  const sdb::MaterialId mat = s.scene.addMaterial(m).id;
  s.scene.addNode({.name = "sphere", .meshes = {s.scene.addMesh(test::uvSphere(vec3(0.0f), 1.0f, 64, 128, mat)).id}});
  for (const TestLight& tl : lights) {
    sdb::Light l;
    l.type = sdb::LightType::kDirectional;
    l.color = tl.lux / maxComponent(tl.lux);
    l.intensity = maxComponent(tl.lux);
    // The light's node looks down its −Z, away from the light.
    const vec3 up = std::abs(tl.toLight.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0);
    s.scene.addNode({.name = "light", .parentFromLocal = sdb::lookAtTransform(vec3(0.0f), -tl.toLight, up),
                     .light = s.scene.addLight(l).id});
  }
  s.rdb = rdb::buildRasterRdb(s.scene);
  s.rdb.ambient = {};
  return s;
}

// Orthographic, looking down −Z from +Z at the unit sphere, 1.1 m half height.
View frontView() {
  View v;
  v.worldFromCamera = glm::translate(mat4(1.0f), vec3(0.0f, 0.0f, 5.0f));
  v.orthographic = true;
  v.ymagM = 1.1f;
  v.znearM = 0.1f;
  v.zfarM = 10.0f;
  return v;
}

// √(Σ (a − b)²) / √(Σ b²) over the channels of the samples compared: the RMS error relative to the RMS of the
// reference.
struct RelativeRms {
  double errorSq = 0.0, referenceSq = 0.0;
  size_t count = 0;
  void add(const Rgb& a, const Rgb& b) {
    for (int c = 0; c < 3; ++c) {
      errorSq += double(a[c] - b[c]) * (a[c] - b[c]);
      referenceSq += double(b[c]) * b[c];
    }
    ++count;
  }
  double value() const { return referenceSq > 0.0 ? std::sqrt(errorSq / referenceSq) : 0.0; }
};

// The ball's layer 0 (view frame = world frame here) against the SDB's evaluation at each texel's normal.
double ballError(const Brdf& brdf, uint32_t sizePx, float* maxLuminance = nullptr) {
  context();
  const std::vector<TestLight> lights = fiveLights();
  const SphereScene s = sphereScene(brdf, lights);
  Renderer renderer;
  renderer.setBallSettings({sizePx, 64, 16});
  renderer.upload(s.rdb);
  renderer.render(frontView(), RenderMode::kSimple, 32, 32);
  EXPECT_EQ(renderer.stats().ballsMade, 1);
  const std::vector<float> ball = renderer.ballLayer(0);
  RelativeRms rms;
  float peak = 0.0f;
  for (uint32_t j = 0; j < sizePx; ++j) {
    for (uint32_t i = 0; i < sizePx; ++i) {
      const float x = (float(i) + 0.5f) / float(sizePx) * 2.0f - 1.0f;
      const float y = (float(j) + 0.5f) / float(sizePx) * 2.0f - 1.0f;
      if (x * x + y * y >= 1.0f) continue;
      const vec3 n(x, y, std::sqrt(1.0f - x * x - y * y));
      const Rgb want = referenceLuminance(brdf, n, vec3(0, 0, 1), lights);
      const float* got = &ball[4 * (size_t(j) * sizePx + i)];
      rms.add(Rgb(got[0], got[1], got[2]), want);
      peak = std::max(peak, luminance(want));
    }
  }
  if (maxLuminance) *maxLuminance = peak;
  return rms.value();
}

TEST(BallTexture, CarPaintBallMatchesTheSdbPerTexel) {
  float peak = 0.0f;
  const double err = ballError({nullptr, testPaint()}, 256, &peak);
  std::printf("car-paint ball 256², 5 lights: RMS relative error %.2e (peak %.0f cd/m²)\n", err, double(peak));
  EXPECT_LT(err, 0.02);
  EXPECT_GT(peak, 100.0f);  // the lights reach the ball
}

TEST(BallTexture, SilverMetallicBallMatchesTheSdbPerTexel) {
  const double err = ballError({nullptr, silverPaint()}, 256);
  std::printf("silver metallic ball 256², 5 lights: RMS relative error %.2e\n", err);
  EXPECT_LT(err, 0.02);
}

TEST(BallTexture, MerlTableBallMatchesTheSdbPerTexel) {
  const double err = ballError({fly::test::tableOf(testPaint()), {}}, 128);
  std::printf("MERL-table ball 128², 5 lights: RMS relative error %.2e\n", err);
  EXPECT_LT(err, 0.02);
}

// The rendered sphere (orthographic: the view direction is the ball's at every pixel) against the SDB's
// evaluation at each pixel's exact normal; pixels within 17° of the silhouette (n·v < 0.3) are left out
// (there the 128-segment mesh's facets and interpolated normals, not the ball, decide).
double sphereError(const Brdf& brdf, uint32_t ballPx, const View& view, bool perspectiveEye, size_t* compared) {
  context();
  const std::vector<TestLight> lights = fiveLights();
  const SphereScene s = sphereScene(brdf, lights);
  Renderer renderer;
  renderer.setBallSettings({ballPx, 64, 16});
  renderer.upload(s.rdb);
  constexpr uint32_t kPx = 160;
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const std::vector<float> img = renderer.luminanceRgb();
  const mat4 worldFromCamera = view.worldFromCamera;
  const vec3 eye(worldFromCamera[3]);
  RelativeRms rms;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const float ndcX = (float(x) + 0.5f) / kPx * 2.0f - 1.0f, ndcY = 1.0f - (float(y) + 0.5f) / kPx * 2.0f;
      // The pixel's ray (camera frame), then world.
      vec3 origin, dir;
      if (perspectiveEye) {
        const float t = std::tan(0.5f * view.yfovRad);
        origin = eye;
        dir = glm::normalize(mat3(worldFromCamera) * vec3(ndcX * t, ndcY * t, -1.0f));
      } else {
        origin = vec3(worldFromCamera * vec4(ndcX * view.ymagM, ndcY * view.ymagM, 0.0f, 1.0f));
        dir = -vec3(worldFromCamera[2]);
      }
      const float b = glm::dot(origin, dir), c = glm::dot(origin, origin) - 1.0f;
      const float disc = b * b - c;
      if (disc <= 0.0f) continue;
      const vec3 p = origin + (-b - std::sqrt(disc)) * dir;
      const vec3 n = glm::normalize(p);
      const vec3 wo = -dir;
      if (glm::dot(n, wo) < 0.3f) continue;
      const float* got = &img[3 * (size_t(y) * kPx + x)];
      rms.add(Rgb(got[0], got[1], got[2]), referenceLuminance(brdf, n, wo, lights));
    }
  }
  *compared = rms.count;
  return rms.value();
}

TEST(BallTexture, RenderedSphereMatchesTheSdbPerPixel) {
  size_t compared = 0;
  const double err = sphereError({nullptr, testPaint()}, 256, frontView(), false, &compared);
  std::printf("car-paint sphere 160², orthographic, ball 256²: RMS relative error %.4f over %zu pixels\n", err,
              compared);
  EXPECT_GT(compared, 10000u);
  EXPECT_LT(err, 0.02);
}

// The same sphere in perspective (0.9 rad vertical field, from 2.6 m: the sphere fills the view): sphere
// mapping takes the ball's normal halfway between the reflection and the view axis, exact for a BRDF that
// depends on the reflection direction alone; a car paint's Fresnel and diffuse terms see the angle to the
// view axis instead of the pixel's. Measured, not hidden.
TEST(BallTexture, RenderedSphereInPerspective) {
  size_t compared = 0;
  const double filling = sphereError({nullptr, testPaint()}, 256, test::lookAtView(vec3(0.0f, 0.0f, 2.6f), vec3(0.0f), 10.0f),
                                     true, &compared);
  std::printf("car-paint sphere 160², perspective 0.9 rad from 2.6 m (filling the view), ball 256²: RMS relative "
              "error %.4f over %zu pixels\n",
              filling, compared);
  EXPECT_GT(compared, 5000u);
  EXPECT_LT(filling, 0.06);
  const double small = sphereError({nullptr, testPaint()}, 256, test::lookAtView(vec3(0.0f, 0.0f, 8.0f), vec3(0.0f), 20.0f),
                                   true, &compared);
  std::printf("car-paint sphere 160², perspective 0.9 rad from 8 m (±7° of the view), ball 256²: RMS relative "
              "error %.4f over %zu pixels\n",
              small, compared);
  EXPECT_GT(compared, 1000u);
  EXPECT_LT(small, 0.02);
  // The same sphere 25° off the view axis: the ball's frame turns towards it (ballFrame), so the error stays
  // that of its own angular extent.
  const double aside = sphereError({nullptr, testPaint()}, 256,
                                   test::lookAtView(vec3(0.0f, 0.0f, 8.0f), vec3(3.73f, 0.0f, 0.0f), 20.0f), true,
                                   &compared);
  std::printf("car-paint sphere 160², perspective 0.9 rad from 8 m, 25° off the view axis, ball 256²: RMS "
              "relative error %.4f over %zu pixels\n",
              aside, compared);
  EXPECT_GT(compared, 800u);
  EXPECT_LT(aside, 0.02);
}

// The environment term (simple mode's directional ambient as two hemispheres, 12 000 lux above, 2 000 lux
// below the horizon; no lights) against fine quadrature of ∫ f cos θi L dωi on the CPU (1024 × 1024 half
// vectors, the same warp) at 49 texels spread over the ball, in a view tilted 30° down so the horizon crosses
// the ball.
// The steps² midpoint grid of half vectors (θh = u² · π/2, φh) for the ball texel of view-frame normal nView,
// ωo = the view's +Z: visit(ωi local, ωo local, ωi world, dω) for every ωi above the surface.
template <class Visit>
void forEachHalfVectorCell(const mat3& worldFromView, const vec3& nView, int steps, const Visit& visit) {
  const vec3 n = worldFromView * nView;
  const vec3 wo = worldFromView * vec3(0.0f, 0.0f, 1.0f);
  const vec3 t = glm::normalize(glm::cross(std::abs(n.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0), n));
  const vec3 bt = glm::cross(n, t);
  const vec3 woLocal(glm::dot(wo, t), glm::dot(wo, bt), glm::dot(wo, n));
  for (int p = 0; p < steps; ++p) {
    const double u = (p + 0.5) / steps, thetaH = u * u * kPi / 2;
    for (int q = 0; q < steps; ++q) {
      const double phi = 2.0 * kPi * (q + 0.5) / steps;
      const vec3 h(float(std::sin(thetaH) * std::cos(phi)), float(std::sin(thetaH) * std::sin(phi)),
                   float(std::cos(thetaH)));
      const float woDotH = glm::dot(woLocal, h);
      if (woDotH <= 0.0f) continue;
      const vec3 wi = 2.0f * woDotH * h - woLocal;
      if (wi.z <= 0.0f) continue;
      const double dOmega = 4.0 * woDotH * std::sin(thetaH) * kPi * u / steps * 2.0 * kPi / steps;
      visit(wi, woLocal, wi.x * t + wi.y * bt + wi.z * n, dOmega);
    }
  }
}

TEST(BallTexture, EnvironmentTermAgainstFineQuadrature) {
  context();
  const Brdf brdf{nullptr, testPaint()};
  SphereScene s = sphereScene(brdf, {});
  s.rdb.ambient.upLux = Rgb(12000.0f);
  s.rdb.ambient.downLux = Rgb(2000.0f);
  Renderer renderer;
  constexpr uint32_t kBall = 64;
  renderer.setBallSettings({kBall, kBall, 16});
  renderer.upload(s.rdb);
  const View view = test::lookAtView(vec3(0.0f, 2.5f, 4.33f), vec3(0.0f), 20.0f);
  renderer.render(view, RenderMode::kSimple, 16, 16);
  const std::vector<float> ball = renderer.ballLayer(0);
  const mat3 worldFromView(view.worldFromCamera);
  RelativeRms rms;
  double worstIrradiance = 0.0;
  for (int a = 0; a < 7; ++a) {
    for (int b = 0; b < 7; ++b) {
      const uint32_t i = uint32_t(4 + a * 9), j = uint32_t(4 + b * 9);
      const float x = (float(i) + 0.5f) / kBall * 2.0f - 1.0f, y = (float(j) + 0.5f) / kBall * 2.0f - 1.0f;
      if (x * x + y * y >= 0.97f) continue;
      dvec3 sum(0.0);
      double irradiance = 0.0;
      forEachHalfVectorCell(worldFromView, vec3(x, y, std::sqrt(1.0f - x * x - y * y)), 1024,
                            [&](const vec3& wi, const vec3& woLocal, const vec3& wiWorld, double dOmega) {
                              const double radiance = (wiWorld.y > 0.0f ? 12000.0 : 2000.0) / kPi;
                              sum += dvec3(brdf(wi, woLocal)) * (double(wi.z) * radiance * dOmega);
                              irradiance += wi.z * radiance * dOmega;
                            });
      const float* got = &ball[4 * (size_t(j) * kBall + i)];
      rms.add(Rgb(got[0], got[1], got[2]), Rgb(sum));
      worstIrradiance = std::max(worstIrradiance, std::abs(double(got[3]) - irradiance) / irradiance);
    }
  }
  std::printf("environment term (two hemispheres, 16² half vectors) at %zu texels: RMS relative error %.4f; "
              "irradiance (a) worst relative error %.4f\n",
              rms.count, rms.value(), worstIrradiance);
  EXPECT_GT(rms.count, 30u);
  EXPECT_LT(rms.value(), 0.02);
  EXPECT_LT(worstIrradiance, 0.005);
}

// Where the distant-light approximation breaks down: a 20 000 cd point light at d = 1.5 … 200 sphere radii from
// the centre of the unit sphere. In the ball (nearLightRadii 0) it is seen from the centre (one direction,
// I/d²) while each point of the sphere sees it from its own direction at its own distance: the error grows as
// R/d. By default a lamp within 50 radii of the objects' bounding box (1.73 m here) is evaluated per pixel
// instead, exactly; farther ones stay in the ball, whose error there is below 1 %.
double pointLightError(float dSphereRadii, float nearLightRadii) {
  const Brdf brdf{nullptr, testPaint()};
  const vec3 towards = glm::normalize(vec3(0.3f, 0.5f, 1.0f));
  SphereScene s = sphereScene(brdf, {});
  sdb::Light l;
  l.type = sdb::LightType::kPoint;
  l.intensity = 20000.0f;
  const float d = dSphereRadii;
  s.scene.addNode({.name = "lamp", .parentFromLocal = glm::translate(mat4(1.0f), d * towards),
                   .light = s.scene.addLight(l).id});
  s.rdb = rdb::buildRasterRdb(s.scene);
  s.rdb.ambient = {};
  Renderer renderer;
  BallSettings settings{256, 64, 16};
  settings.nearLightRadii = nearLightRadii;
  renderer.setBallSettings(settings);
  renderer.upload(s.rdb);
  constexpr uint32_t kPx = 128;
  const View view = frontView();
  renderer.render(view, RenderMode::kSimple, kPx, kPx);
  const std::vector<float> img = renderer.luminanceRgb();
  RelativeRms rms;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const float px = ((float(x) + 0.5f) / kPx * 2.0f - 1.0f) * view.ymagM;
      const float py = (1.0f - (float(y) + 0.5f) / kPx * 2.0f) * view.ymagM;
      if (px * px + py * py >= 0.91f) continue;  // n·v ≥ 0.3
      const vec3 n(px, py, std::sqrt(1.0f - px * px - py * py));
      const vec3 toLamp = d * towards - n;
      const float dist2 = glm::dot(toLamp, toLamp);
      const Rgb want =
          referenceLuminance(brdf, n, vec3(0, 0, 1), {{glm::normalize(toLamp), Rgb(20000.0f / dist2)}});
      const float* got = &img[3 * (size_t(y) * kPx + x)];
      rms.add(Rgb(got[0], got[1], got[2]), want);
    }
  }
  return rms.value();
}

TEST(BallTexture, DistantLightApproximationBreaksDownNearALargeObject) {
  context();
  std::vector<double> inBall, byDefault;
  for (float d : {1.5f, 2.0f, 3.0f, 5.0f, 10.0f, 20.0f, 200.0f}) {
    inBall.push_back(pointLightError(d, 0.0f));
    byDefault.push_back(pointLightError(d, BallSettings{}.nearLightRadii));
    std::printf("point light at %.1f sphere radii: RMS relative error %.4f in the ball, %.4f by default\n",
                double(d), inBall.back(), byDefault.back());
  }
  EXPECT_GT(inBall.front(), 0.3);  // 1.5 radii: the ball's one direction is far from most points'
  EXPECT_LT(inBall[5], 0.1);       // 20 radii
  for (size_t k = 1; k < inBall.size(); ++k) EXPECT_LT(inBall[k], inBall[k - 1]);
  for (double e : byDefault) EXPECT_LT(e, 0.01);
}

// Fine quadrature (512² half vectors) of ∫ f cos θi L dωi on the CPU for the ball texel of view-frame
// normal nView, with ωo = the view's +Z and `radiance` a function of the world direction.
template <class Radiance>
Rgb environmentReference(const Brdf& brdf, const mat3& worldFromView, const vec3& nView, const Radiance& radiance) {
  dvec3 sum(0.0);
  forEachHalfVectorCell(worldFromView, nView, 512,
                        [&](const vec3& wi, const vec3& woLocal, const vec3& wiWorld, double dOmega) {
                          sum += dvec3(brdf(wi, woLocal) * radiance(wiWorld)) * (double(wi.z) * dOmega);
                        });
  return Rgb(sum);
}

// Sunlight mode: the environment is the sky image (Helsinki, clear, 21 June 15:00; its ground below the
// horizon) and the sun a distant light in layer 1. Both layers at texels spread over the ball against the
// CPU: the sky by fine quadrature of the same image (bilinear, as the GPU samples it), the sun per texel.
TEST(BallTexture, SkyAndSunInSunlightMode) {
  context();
  const Brdf brdf{nullptr, testPaint()};
  SphereScene s = sphereScene(brdf, {});
  fly::test::setHelsinkiClearSky(s.scene, "2026-06-21T15:00");
  s.rdb = rdb::buildRasterRdb(s.scene);
  ASSERT_TRUE(s.rdb.sky && s.rdb.sky->hasSun);
  const rdb::RasterSky& sky = *s.rdb.sky;
  auto skyRadiance = [&](const vec3& d) {
    double phi = std::atan2(double(d.z), double(d.x));
    if (phi < 0.0) phi += 2.0 * kPi;
    const double theta = std::acos(std::clamp(double(d.y), -1.0, 1.0));
    const double x = phi / (2.0 * kPi) * sky.width - 0.5, y = theta / kPi * sky.height - 0.5;
    const int x0 = int(std::floor(x)), y0 = int(std::floor(y));
    const float fx = float(x - x0), fy = float(y - y0);
    auto at = [&](int i, int j) {
      i = ((i % int(sky.width)) + int(sky.width)) % int(sky.width);
      j = std::clamp(j, 0, int(sky.height) - 1);
      return sky.radianceCdM2[size_t(j) * sky.width + size_t(i)];
    };
    return (1 - fy) * ((1 - fx) * at(x0, y0) + fx * at(x0 + 1, y0)) + fy * ((1 - fx) * at(x0, y0 + 1) + fx * at(x0 + 1, y0 + 1));
  };
  constexpr uint32_t kBall = 64;
  const View view = test::lookAtView(vec3(0.0f, 1.0f, 4.9f), vec3(0.0f), 20.0f);
  const mat3 worldFromView(view.worldFromCamera);
  const Rgb sunLux =
      sky.sunRadianceCdM2 * float(2.0 * kPi * (1.0 - std::cos(double(sky.sunHalfAngleRad))));
  // The environment image at the ball's resolution (the quadrature alone), then at a quarter of it (the
  // default ratio: bilinear between its texels too).
  for (const uint32_t envPx : {kBall, kBall / 4}) {
    Renderer renderer;
    renderer.setBallSettings({kBall, envPx, 16});
    renderer.upload(s.rdb);
    renderer.render(view, RenderMode::kSunlight, 16, 16);
    const std::vector<float> skyLayer = renderer.ballLayer(0), sunLayer = renderer.ballLayer(1);
    RelativeRms skyRms, sunRms;
    for (int a = 0; a < 7; ++a) {
      for (int b = 0; b < 7; ++b) {
        const uint32_t i = uint32_t(4 + a * 9), j = uint32_t(4 + b * 9);
        const float x = (float(i) + 0.5f) / kBall * 2.0f - 1.0f, y = (float(j) + 0.5f) / kBall * 2.0f - 1.0f;
        if (x * x + y * y >= 0.97f) continue;
        const vec3 nView(x, y, std::sqrt(1.0f - x * x - y * y));
        const size_t texel = 4 * (size_t(j) * kBall + i);
        skyRms.add(Rgb(skyLayer[texel], skyLayer[texel + 1], skyLayer[texel + 2]),
                   environmentReference(brdf, worldFromView, nView, skyRadiance));
        const Rgb sunWant = referenceLuminance(brdf, worldFromView * nView, worldFromView * vec3(0, 0, 1),
                                               {{sky.sunDirWorld, sunLux}});
        sunRms.add(Rgb(sunLayer[texel], sunLayer[texel + 1], sunLayer[texel + 2]), sunWant);
      }
    }
    std::printf("sunlight mode, ball 64², environment image %u²: sky term (16² half vectors) RMS relative error "
                "%.4f, sun term %.2e, at %zu texels\n",
                envPx, skyRms.value(), sunRms.value(), skyRms.count);
    // The clear sky's circumsolar aureole is its sharpest feature.
    EXPECT_LT(skyRms.value(), envPx == kBall ? 0.015 : 0.03);
    EXPECT_LT(sunRms.value(), 0.01);
  }
}

// Light-map mode: the ball's distribution scaled to the baked irradiance (raster/renderer.h). With light
// maps that hold exactly the irradiance the ball's own lights and the near lamp give each vertex (the sphere
// shadows nothing),
// the image is simple mode's; with half of it, half; where the lights give nothing, albedo · E / π.
TEST(BallTexture, LightMapModeScalesTheBallToTheBakedIrradiance) {
  context();
  const Brdf brdf{nullptr, testPaint()};
  // Lights from +X only, so the −X half of the sphere gets none of their light.
  const std::vector<TestLight> lights = {{glm::normalize(vec3(1.0f, 0.3f, 0.6f)), Rgb(1000.0f)},
                                         {glm::normalize(vec3(0.8f, -0.4f, 0.2f)), Rgb(500.0f, 450.0f, 400.0f)}};
  SphereScene s = sphereScene(brdf, lights);
  // And a 20 000 cd lamp 2.3 m from the centre, on the same side: a near lamp, evaluated per pixel.
  const vec3 lampM(2.0f, 1.0f, 0.5f);
  sdb::Light lamp;
  lamp.intensity = 20000.0f;
  s.scene.addNode({.name = "lamp", .parentFromLocal = glm::translate(mat4(1.0f), lampM), .light = s.scene.addLight(lamp).id});
  s.rdb = rdb::buildRasterRdb(s.scene);
  auto storeOf = [&](float scale, float floorLux) {
    rdb::LightMapStore store;
    for (const rdb::RasterMesh& m : s.rdb.meshes) {
      rdb::MeshLightMap map{m.sdbNodeId, m.sdbMeshId, {}, {}};
      for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) {
        Rgb e(floorLux);
        const vec3 n = s.rdb.normals[v], toLamp = lampM - s.rdb.positionsM[v];
        for (const TestLight& l : lights) e += scale * l.lux * std::max(0.0f, glm::dot(n, l.toLight));
        e += Rgb(scale * 20000.0f * std::max(0.0f, glm::dot(n, glm::normalize(toLamp))) / glm::dot(toLamp, toLamp));
        map.frontLux.push_back(e);
      }
      store.meshes.push_back(std::move(map));
    }
    return store;
  };
  constexpr uint32_t kPx = 96;
  auto render = [&](const rdb::LightMapStore* store, RenderMode mode) {
    rdb::RasterRdb r = rdb::buildRasterRdb(s.scene, store);
    r.ambient = {};
    Renderer renderer;
    renderer.setBallSettings({128, 32, 4});
    renderer.upload(r);
    renderer.render(frontView(), mode, kPx, kPx);
    return std::pair(renderer.luminanceRgb(), r.materials.at(r.meshes.at(0).material).diffuse);
  };
  const std::vector<float> simple = render(nullptr, RenderMode::kSimple).first;
  const rdb::LightMapStore exact = storeOf(1.0f, 0.0f), half = storeOf(0.5f, 0.0f), lifted = storeOf(1.0f, 100.0f);
  const std::vector<float> same = render(&exact, RenderMode::kLightMap).first;
  const std::vector<float> halved = render(&half, RenderMode::kLightMap).first;
  const auto [floored, albedo] = render(&lifted, RenderMode::kLightMap);
  RelativeRms sameRms, halfRms;
  double darkSide = 0.0, darkWant = 0.0;
  size_t dark = 0;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const float px = ((float(x) + 0.5f) / kPx * 2.0f - 1.0f) * 1.1f, py = (1.0f - (float(y) + 0.5f) / kPx * 2.0f) * 1.1f;
      if (px * px + py * py >= 0.91f) continue;
      const size_t i = 3 * (size_t(y) * kPx + x);
      const Rgb want(simple[i], simple[i + 1], simple[i + 2]);
      sameRms.add(Rgb(same[i], same[i + 1], same[i + 2]), want);
      halfRms.add(Rgb(halved[i], halved[i + 1], halved[i + 2]), 0.5f * want);
      const vec3 n(px, py, std::sqrt(1.0f - px * px - py * py));
      bool unlit = glm::dot(n, glm::normalize(lampM - n)) < -0.1f;
      for (const TestLight& l : lights) unlit &= glm::dot(n, l.toLight) < -0.1f;
      if (unlit) {
        darkSide += luminance(Rgb(floored[i], floored[i + 1], floored[i + 2]));
        darkWant += luminance(albedo) * 100.0 / kPi;
        ++dark;
      }
    }
  }
  std::printf("light-map mode: exact light maps %.4f, halved %.4f (RMS relative to simple mode); unlit side "
              "%.3f of albedo · E / π over %zu pixels\n",
              sameRms.value(), halfRms.value(), darkSide / darkWant, dark);
  EXPECT_LT(sameRms.value(), 0.02);
  EXPECT_LT(halfRms.value(), 0.02);
  EXPECT_GT(dark, 500u);
  EXPECT_NEAR(darkSide / darkWant, 1.0, 0.01);
}

// The near lamps are added after the opaque draws, once per pixel, to the pixels where a measured material
// shows, and to no other: a cut-out quad (a per-fragment draw, like the sphere) in front of the sphere's left
// half keeps exactly the image it has with every lamp in the ball, while the sphere's right half changes.
TEST(BallTexture, NearLampsReachOnlyThePixelsWhereTheMeasuredMaterialShows) {
  context();
  const Brdf brdf{nullptr, testPaint()};
  SphereScene s = sphereScene(brdf, {});
  sdb::Light lamp;
  lamp.intensity = 20000.0f;
  s.scene.addNode({.name = "lamp", .parentFromLocal = glm::translate(mat4(1.0f), 3.0f * glm::normalize(vec3(0.3f, 0.5f, 1.0f))),
                   .light = s.scene.addLight(lamp).id});
  sdb::Material cut;
  cut.name = "cut-out";
  cut.diffuseColor = Rgb(0.5f);
  cut.alphaMode = sdb::AlphaMode::kMask;
  const sdb::MaterialId cutId = s.scene.addMaterial(cut).id;
  // x from −2 to 0, y from −2 to 2, at z = 1.5 facing the camera.
  s.scene.addNode({.name = "quad",
                   .parentFromLocal = glm::scale(glm::translate(mat4(1.0f), vec3(-1.0f, 0.0f, 1.5f)), vec3(1.0f, 4.0f, 1.0f)),
                   .meshes = {s.scene.addMesh(test::quadXY(cutId)).id}});
  s.rdb = rdb::buildRasterRdb(s.scene);
  s.rdb.ambient = {};
  constexpr uint32_t kPx = 96;
  auto render = [&](float nearLightRadii, int wantPasses) {
    Renderer renderer;
    BallSettings settings{128, 32, 4};
    settings.nearLightRadii = nearLightRadii;
    renderer.setBallSettings(settings);
    renderer.upload(s.rdb);
    renderer.render(frontView(), RenderMode::kSimple, kPx, kPx);
    renderer.render(frontView(), RenderMode::kSimple, kPx, kPx);  // records left by a frame would show here
    EXPECT_EQ(renderer.stats().nearLampPasses, wantPasses);
    return renderer.luminanceRgb();
  };
  const std::vector<float> perPixel = render(BallSettings{}.nearLightRadii, 2), inBall = render(0.0f, 0);
  size_t quadPixels = 0, quadDiffering = 0;
  RelativeRms sphereChange;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const float px = ((float(x) + 0.5f) / kPx * 2.0f - 1.0f) * 1.1f, py = (1.0f - (float(y) + 0.5f) / kPx * 2.0f) * 1.1f;
      const size_t i = 3 * (size_t(y) * kPx + x);
      if (px < -0.05f) {
        ++quadPixels;
        quadDiffering += perPixel[i] != inBall[i] || perPixel[i + 1] != inBall[i + 1] || perPixel[i + 2] != inBall[i + 2];
      } else if (px > 0.05f && px * px + py * py < 0.91f) {
        sphereChange.add(Rgb(perPixel[i], perPixel[i + 1], perPixel[i + 2]), Rgb(inBall[i], inBall[i + 1], inBall[i + 2]));
      }
    }
  }
  std::printf("near lamps: %zu of %zu pixels of the quad differ; the sphere's visible half changes by %.3f (RMS, relative)\n",
              quadDiffering, quadPixels, sphereChange.value());
  EXPECT_GT(quadPixels, 3000u);
  EXPECT_EQ(quadDiffering, 0u);
  EXPECT_GT(sphereChange.value(), 0.1);
}

// A ball is remade only when what it depends on changes; a scene without measured materials compiles no
// ball program and makes no ball.
TEST(BallTexture, ReusedWhileNothingChangesAndLeftOutWithoutMeasuredMaterials) {
  context();
  const SphereScene s = sphereScene({nullptr, testPaint()}, fiveLights());
  Renderer renderer;
  renderer.setBallSettings({32, 8, 4});
  renderer.upload(s.rdb);
  renderer.render(frontView(), RenderMode::kSimple, 16, 16);
  renderer.render(frontView(), RenderMode::kSimple, 16, 16);
  EXPECT_EQ(renderer.stats().ballsMade, 1);
  EXPECT_EQ(renderer.stats().ballsReused, 1);
  View moved = frontView();
  moved.worldFromCamera = glm::translate(mat4(1.0f), vec3(0.3f, 0.0f, 5.0f));  // translation only
  renderer.render(moved, RenderMode::kSimple, 16, 16);
  EXPECT_EQ(renderer.stats().ballsMade, 1);
  View turned = frontView();
  turned.worldFromCamera = glm::rotate(mat4(1.0f), 0.2f, vec3(0, 1, 0)) * frontView().worldFromCamera;
  renderer.render(turned, RenderMode::kSimple, 16, 16);
  EXPECT_EQ(renderer.stats().ballsMade, 2);
  const auto& programs = renderer.stats().programs;
  EXPECT_NE(std::find(programs.begin(), programs.end(), "ball"), programs.end());

  sdb::Scene plain;
  sdb::Material m;
  const sdb::MaterialId mat = plain.addMaterial(m).id;
  plain.addNode({.name = "sphere", .meshes = {plain.addMesh(test::uvSphere(vec3(0.0f), 1.0f, 8, 16, mat)).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(plain);
  EXPECT_FALSE(r.variants.measuredBrdf);
  Renderer other;
  other.upload(r);
  other.render(frontView(), RenderMode::kSimple, 16, 16);
  EXPECT_EQ(other.stats().ballsMade, 0);
  for (const std::string& p : other.stats().programs) {
    EXPECT_EQ(p.find("ball"), std::string::npos) << p;
    EXPECT_EQ(p.find("measured"), std::string::npos) << p;
  }
}

TEST(BallTexture, SilverMetallicSphereDependsOnTheBallSize) {
  size_t compared = 0;
  const double small = sphereError({nullptr, silverPaint()}, 256, frontView(), false, &compared);
  const double large = sphereError({nullptr, silverPaint()}, 1024, frontView(), false, &compared);
  std::printf("silver metallic sphere 160², orthographic: RMS relative error %.4f (ball 256²), %.4f (ball 1024²)\n",
              small, large);
  // Its coat's highlight (GGX α 0.01) is about a texel wide on a 256² ball: a larger ball resolves it.
  EXPECT_LT(large, small);
}

}  // namespace
}  // namespace fly::raster
