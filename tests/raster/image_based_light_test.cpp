// Sunlight mode's image-based light (raster/renderer.h, setImageBasedLight): spheres without light maps under
// an environment given as the sky image, against closed forms (a uniform environment, two hemispheres) and
// the split sum by an independent quadrature (split_sum_reference.h), per pixel of a CPU ray cast of the
// sphere.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <optional>
#include <vector>

#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/material.h"
#include "sdb/scene.h"
#include "split_sum_reference.h"

namespace fly::raster {
namespace {

using test::context;

constexpr float kRadiusM = 1.0f;
constexpr uint32_t kPx = 96;
const vec3 kEye(0.0f, 0.6f, 3.5f);

// A sphere of `material` at the origin with the environment `radiance(direction)` as its sky (64 × 32 pixels,
// no sun).
rdb::RasterRdb sphereUnder(const sdb::Material& material, const std::function<Rgb(const vec3&)>& radiance) {
  sdb::Scene scene;
  const sdb::MaterialId id = scene.addMaterial(material).id;
  scene.addNode({.name = "sphere", .meshes = {scene.addMesh(test::uvSphere(vec3(0.0f), kRadiusM, 48, 96, id)).id}});
  rdb::RasterRdb r = rdb::buildRasterRdb(scene);
  rdb::RasterSky sky;
  sky.width = 64;
  sky.height = 32;
  for (uint32_t y = 0; y < sky.height; ++y) {
    for (uint32_t x = 0; x < sky.width; ++x) {
      const double phi = (x + 0.5) / sky.width * 2.0 * kPi, theta = (y + 0.5) / sky.height * kPi;
      sky.radianceCdM2.push_back(radiance(vec3(float(std::sin(theta) * std::cos(phi)), float(std::cos(theta)),
                                               float(std::sin(theta) * std::sin(phi)))));
    }
  }
  r.sky = sky;
  r.variants.sky = true;
  return r;
}

// The sphere's unit normal where the ray of pixel (x, y) (rows from the top) first meets it, when it meets it
// at least 2 % of the radius inside the silhouette (the mesh's facets stay inside the analytic sphere).
std::optional<vec3> sphereNormal(const View& view, uint32_t x, uint32_t y) {
  const float t = std::tan(0.5f * view.yfovRad);
  const vec3 dCamera((2.0f * (float(x) + 0.5f) / kPx - 1.0f) * t, (1.0f - 2.0f * (float(y) + 0.5f) / kPx) * t, -1.0f);
  const vec3 d = glm::normalize(mat3(view.worldFromCamera) * dCamera);
  const vec3 o(view.worldFromCamera[3]);
  const float b = glm::dot(o, d), c = glm::dot(o, o) - kRadiusM * kRadiusM;
  const float disc = b * b - c;
  // The ray's closest approach to the centre, sqrt(c + r² − disc)… inside 0.98 r.
  if (disc <= 0.0f || glm::dot(o, o) - b * b > 0.98f * 0.98f * kRadiusM * kRadiusM) return std::nullopt;
  return glm::normalize(o + (-b - std::sqrt(disc)) * d);
}

struct Comparison {
  double worst = 0.0;  // relative, the worst channel
  int pixels = 0;
};

// Renders `r` in sunlight mode and compares every pixel on the sphere with want(n, toEye).
Comparison compare(const rdb::RasterRdb& r, const std::function<Rgb(const vec3&, const vec3&)>& want,
                   Renderer* renderer = nullptr) {
  context();
  Renderer own;
  Renderer& rr = renderer ? *renderer : own;
  rr.upload(r);
  const View view = test::lookAtView(kEye, vec3(0.0f), 100.0f);
  rr.render(view, RenderMode::kSunlight, kPx, kPx);
  const std::vector<float> image = rr.luminanceRgb();
  Comparison c;
  for (uint32_t y = 0; y < kPx; ++y) {
    for (uint32_t x = 0; x < kPx; ++x) {
      const std::optional<vec3> n = sphereNormal(view, x, y);
      if (!n) continue;
      const vec3 p = kRadiusM * *n;
      const Rgb expected = want(*n, glm::normalize(kEye - p));
      for (int ch = 0; ch < 3; ++ch) {
        const float got = image[3 * (size_t(y) * kPx + x) + size_t(ch)];
        c.worst = std::max(c.worst, std::abs(double(got) / expected[ch] - 1.0));
      }
      ++c.pixels;
    }
  }
  return c;
}

sdb::Material lambertian(float albedo) {
  sdb::Material m;
  m.name = "white";
  m.diffuseColor = Rgb(albedo);
  m.reflectionColor = Rgb(0.0f);
  return m;
}

// A white diffuse sphere without a light map under a uniform environment of L: E = π L on every normal, so
// it shows albedo · E / π = albedo · L.
TEST(ImageBasedLight, DiffuseSphereUnderAUniformEnvironment) {
  const Rgb l(1000.0f, 800.0f, 600.0f);
  constexpr float kAlbedo = 0.9f;
  const rdb::RasterRdb r = sphereUnder(lambertian(kAlbedo), [&](const vec3&) { return l; });
  const Comparison c = compare(r, [&](const vec3&, const vec3&) { return kAlbedo * l; });
  std::printf("diffuse sphere, uniform environment: worst relative error %.2e at %d pixels (albedo · L)\n", c.worst,
              c.pixels);
  EXPECT_GT(c.pixels, 2000);
  EXPECT_LT(c.worst, 2e-3);
}

// Two hemispheres split at the horizon: E(n) = π (L_up (1 + n_y) + L_down (1 − n_y)) / 2 (the view factors of
// a tilted plane), interpolated per vertex over the facets.
TEST(ImageBasedLight, DiffuseSphereUnderTwoHemispheres) {
  const float up = 4000.0f, down = 1000.0f;
  constexpr float kAlbedo = 0.5f;
  const rdb::RasterRdb r = sphereUnder(lambertian(kAlbedo), [&](const vec3& d) { return Rgb(d.y > 0.0f ? up : down); });
  const Comparison c = compare(r, [&](const vec3& n, const vec3&) {
    return Rgb(kAlbedo * (up * (1.0f + n.y) + down * (1.0f - n.y)) / 2.0f);
  });
  std::printf("diffuse sphere, two hemispheres %.0f / %.0f cd/m²: worst relative error %.4f at %d pixels\n", up, down,
              c.worst, c.pixels);
  EXPECT_GT(c.pixels, 2000);
  EXPECT_LT(c.worst, 0.012);
}

// Glossy spheres under a uniform environment of L: L_pre = L at every level, so each pixel shows
// L · (D(θo) + F0 A + F90 B)(cos θo, α) (Karis's split sum; D(θo) the SDB's energy rule's diffuse share at
// the angle the pixel is seen, sdb::Material::effectiveAt) — against the quadrature of fly's GGX at the
// analytic normal. A dielectric (Fresnel, ior 1.5: F0 = 0.04 · reflection colour, F90 = the reflection colour) over a
// diffuse base, and a metal (uniform reflection: F0 = F90 = its colour).
TEST(ImageBasedLight, GlossySpheresAgainstTheSplitSumByQuadrature) {
  const Rgb l(2000.0f);
  struct Case {
    const char* name;
    sdb::ReflectionModel model;
    float glossiness, diffuse;
    Rgb reflection;
  };
  for (const Case& k : {Case{"dielectric", sdb::ReflectionModel::kFresnel, 0.5f, 0.3f, Rgb(1.0f)},
                        Case{"metal", sdb::ReflectionModel::kUniform, 0.3f, 0.0f, Rgb(0.9f, 0.7f, 0.4f)}}) {
    sdb::Material m;
    m.name = k.name;
    m.diffuseColor = Rgb(k.diffuse);
    m.reflectionColor = k.reflection;
    m.reflectionModel = k.model;
    m.reflectionGlossiness = k.glossiness;
    const float alpha = k.glossiness * k.glossiness;
    const rdb::RasterRdb r = sphereUnder(m, [&](const vec3&) { return l; });
    const rdb::RasterMaterial& block = r.materials.back();
    // (A, B) by quadrature at 129 values of cos θo, linear between them (the split sum is smooth in cos θo;
    // the pixels' cos θo is ≥ 0.2 inside the silhouette).
    constexpr int kNodes = 128;
    std::vector<vec2> nodes;
    for (int i = 0; i <= kNodes; ++i)
      nodes.push_back(test::splitSumByQuadrature(std::max(float(i) / kNodes, 1e-3f), alpha, 1024, 256));
    const Comparison c = compare(r, [&](const vec3& n, const vec3& toEye) {
      const float x = std::clamp(glm::dot(n, toEye), 0.0f, 1.0f) * kNodes;
      const int i = std::min(int(x), kNodes - 1);
      const vec2 ab = glm::mix(nodes[size_t(i)], nodes[size_t(i) + 1], x - float(i));
      return l * (m.effectiveAt(glm::dot(n, toEye)).diffuse + block.specular * ab.x + block.environmentF90 * ab.y);
    });
    std::printf("%s sphere (α = %.2f), uniform environment: worst relative error %.4f at %d pixels against the "
                "split sum by quadrature\n", k.name, alpha, c.worst, c.pixels);
    EXPECT_GT(c.pixels, 2000);
    EXPECT_LT(c.worst, 0.03) << k.name;
  }
}

// Specular occlusion of light-mapped surfaces (docs/environment-light.md): the environment's specular part
// times clamp(Y(E_baked) / Y(E_env(n)), 0, 1), E_baked the light map's irradiance without the sun's direct part.
// A polished light-mapped floor (a Fresnel dielectric, ior 1.5, α = 0.09, over a 0.4 diffuse base) facing +Y
// under a uniform environment of L (E_env = π L on every normal) whose light map holds E_baked = f · π L: f = 0
// is a floor in a closed room (no light reaches it: it must show no environment specular), f = 1 one under the
// open sky (the whole specular part), 0.5 half of it, 3 (lamps and interreflections brighter than the sky) the
// whole, clamped. Seen orthographically at 60° from the normal (cos θo = 0.5 at every pixel), the image minus
// the image with the image-based light off (albedo · E / π alone: the dielectric has no stand-in reflection)
// must be min(f, 1) · L (F0 A + F90 B), (A, B) by quadrature. Every path: per vertex, a light texture (per
// texel), a per-fragment surface (COLOR_0), and a light map that keeps the sun's direct part apart (E_baked =
// E − E_sunDirect: the sun patch's light is not the sky's).
TEST(ImageBasedLight, LightMappedSurfacesReflectTheEnvironmentTheirLightMapSees) {
  context();
  const Rgb l(2000.0f, 1800.0f, 1500.0f);
  sdb::Material floorMaterial;
  floorMaterial.name = "polished floor";
  floorMaterial.diffuseColor = Rgb(0.4f);
  floorMaterial.reflectionColor = Rgb(1.0f);
  floorMaterial.reflectionModel = sdb::ReflectionModel::kFresnel;
  floorMaterial.ior = 1.5f;
  floorMaterial.reflectionGlossiness = 0.3f;
  const float alpha = 0.09f;
  const vec3 toEye(0.0f, 0.5f, std::sqrt(0.75f));
  View view;
  view.orthographic = true;
  view.worldFromCamera = sdb::lookAtTransform(5.0f * toEye, vec3(0.0f), vec3(0, 1, 0));
  view.znearM = 0.1f;
  view.zfarM = 20.0f;
  constexpr uint32_t kSize = 32;
  const vec2 ab = test::splitSumByQuadrature(0.5f, alpha, 1024, 256);

  enum class Path { kVertex, kLightTexture, kFragment, kSunDirect };
  for (const Path path : {Path::kVertex, Path::kLightTexture, Path::kFragment, Path::kSunDirect}) {
    const char* name = path == Path::kVertex         ? "per vertex"
                       : path == Path::kLightTexture ? "light texture"
                       : path == Path::kFragment     ? "per fragment"
                                                     : "sun kept apart";
    for (const float f : {0.0f, 0.5f, 1.0f, 3.0f}) {
      sdb::Scene scene;
      const sdb::MaterialId id = scene.addMaterial(floorMaterial).id;
      sdb::Mesh floor;
      floor.name = "floor";
      floor.positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
      floor.normals.assign(4, vec3(0, 1, 0));
      floor.indices = {0, 2, 1, 0, 3, 2};  // counter-clockwise seen from +Y
      floor.material = id;
      if (path == Path::kFragment) floor.colors.assign(4, vec4(1.0f));
      const sdb::MeshId mesh = scene.addMesh(floor).id;
      const sdb::NodeId node = scene.addNode({.name = "floor", .meshes = {mesh}}).id;
      Rgb sunDirect(0.0f);
      if (path == Path::kSunDirect) {
        scene.setSky({.model = sdb::SkyModel::kClear, .sun = true});
        scene.setTime({.sunDirection = sdb::SunDirection{180.0, 30.0}});
        const rdb::RasterSky& sky = *rdb::buildRasterRdb(scene).sky;
        sunDirect = sky.sunRadianceCdM2 * float(2.0 * kPi * (1.0 - std::cos(double(sky.sunHalfAngleRad)))) *
                    sky.sunDirWorld.y;
      }
      const Rgb baked = f * float(kPi) * l;
      rdb::LightMapStore store;
      rdb::MeshLightMap map{node.value, mesh.value, std::vector<Rgb>(4, baked + sunDirect), {}};
      if (path == Path::kSunDirect) {
        store.sun = rdb::BakedSun{vec3(0, 1, 0), sunDirect};
        map.frontSunDirectLux.assign(4, sunDirect);
      }
      if (path == Path::kLightTexture) {
        rdb::MeshLightTexture t;
        t.width = t.height = 2;
        t.frontLux.assign(4, baked);
        t.cornerUv = {{0, 0}, {1, 1}, {1, 0}, {0, 0}, {0, 1}, {1, 1}};
        map.lightTexture = t;
      }
      store.meshes.push_back(map);
      rdb::RasterRdb r = rdb::buildRasterRdb(scene, &store);
      ASSERT_EQ(r.variants.lightTexture, path == Path::kLightTexture);
      ASSERT_EQ(r.variants.sunDirect, path == Path::kSunDirect);
      ASSERT_EQ(r.variants.vertexColors, path == Path::kFragment);
      if (!r.sky) r.sky = rdb::RasterSky{};
      r.sky->width = 64;
      r.sky->height = 32;
      r.sky->radianceCdM2.assign(64 * 32, l);
      r.variants.sky = true;
      const rdb::RasterMaterial& block = r.materials.back();
      const Rgb unoccluded = l * (block.specular * ab.x + block.environmentF90 * ab.y);
      const Rgb expected = std::min(f, 1.0f) * unoccluded;

      // The sky's light times the light map's specular occlusion: the renderer without the room probe.
      Renderer on, off;
      on.setRoomProbe(false);
      off.setImageBasedLight(false);
      on.upload(r);
      off.upload(r);
      on.render(view, RenderMode::kSunlight, kSize, kSize);
      off.render(view, RenderMode::kSunlight, kSize, kSize);
      const std::vector<float> withIbl = on.luminanceRgb(), without = off.luminanceRgb();
      double worst = 0.0;
      for (size_t i = 0; i < withIbl.size(); ++i) {
        const int ch = int(i % 3);
        worst = std::max(worst, std::abs(double(withIbl[i] - without[i]) - expected[ch]) / unoccluded[ch]);
      }
      std::printf(
          "%s, E_baked = %.1f π L: environment specular %.4f of the unoccluded (want %.1f), worst error "
          "%.4f of it\n",
          name, f, (withIbl[1] - without[1]) / unoccluded[1], std::min(f, 1.0f), worst);
      EXPECT_LT(worst, 0.02) << name << ", f = " << f;
    }
  }
}

// The maps are built at the first sunlight frame and rebuilt only when the sky changes; simple mode and a
// renderer with the image-based light off compile no "ibl" program.
TEST(ImageBasedLight, RebuiltOnlyWhenTheSkyChanges) {
  context();
  const rdb::RasterRdb r = sphereUnder(lambertian(0.5f), [](const vec3&) { return Rgb(100.0f); });
  const View view = test::lookAtView(kEye, vec3(0.0f), 100.0f);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(view, RenderMode::kSimple, 16, 16);
  EXPECT_EQ(renderer.stats().environmentBuilds, 0);
  renderer.render(view, RenderMode::kSunlight, 16, 16);
  renderer.render(view, RenderMode::kSunlight, 16, 16);
  EXPECT_EQ(renderer.stats().environmentBuilds, 1);
  renderer.update(r, {.sky = true});
  renderer.render(view, RenderMode::kSunlight, 16, 16);
  EXPECT_EQ(renderer.stats().environmentBuilds, 2);
  const auto& programs = renderer.stats().programs;
  EXPECT_TRUE(std::any_of(programs.begin(), programs.end(),
                          [](const std::string& p) { return p.find("+ibl") != std::string::npos; }));

  Renderer off;
  off.setImageBasedLight(false);
  off.upload(r);
  off.render(view, RenderMode::kSunlight, 16, 16);
  EXPECT_EQ(off.stats().environmentBuilds, 0);
  for (const std::string& p : off.stats().programs) EXPECT_EQ(p.find("+ibl"), std::string::npos) << p;
}

}  // namespace
}  // namespace fly::raster
