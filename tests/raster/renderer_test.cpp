#include "raster/renderer.h"

#include <gtest/gtest.h>

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "base/color.h"
#include "base/log.h"
#include "base/tone_map.h"
#include "raster/gl_context.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "rdb/site_lowering.h"
#include "sunsky/sky.h"
#include "../support/helsinki_daylight.h"
#include "sdb/ies.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

TEST(GlContext, HeadlessIsOpenGl45CoreWithoutADisplay) {
  const GlInfo& info = context().info();
  EXPECT_TRUE(info.major > 4 || (info.major == 4 && info.minor >= 5)) << info.major << "." << info.minor;
  EXPECT_TRUE(info.platform == "egl-device" || info.platform == "egl-surfaceless") << info.platform;
  EXPECT_FALSE(info.renderer.empty());
}

TEST(GlContext, GlErrorsReachTheLogThroughKhrDebug) {
  context();
  std::vector<std::string> errors;
  const log::Sink previous = log::setSink([&](log::Level level, std::string_view m) {
    if (level == log::Level::kError) errors.emplace_back(m);
  });
  glBindBuffer(GL_ARRAY_BUFFER, 987654);  // not a buffer name: GL_INVALID_OPERATION
  log::setSink(previous);
  ASSERT_EQ(glGetError(), GLenum(GL_INVALID_OPERATION));
  ASSERT_FALSE(errors.empty());
  EXPECT_NE(errors.front().find("OpenGL"), std::string::npos) << errors.front();
}

// An orthographic camera at z = 5 looking down −Z (front view of quadXY) or at z = −5 looking down +Z (back).
View orthoView(bool fromBehind) {
  View v;
  v.orthographic = true;
  v.ymagM = 1.0f;  // x half extent = 1 · aspect
  v.znearM = 0.1f;
  v.zfarM = 10.0f;
  v.worldFromCamera = fromBehind
                          ? frameTransform(vec3(-1, 0, 0), vec3(0, 1, 0), vec3(0, 0, -1), vec3(0, 0, -5))
                          : frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, 5));
  return v;
}

// CPU expectation for quadXY seen through orthoView in a w × h image (aspect 2): Gouraud interpolation of the
// per-vertex luminances over the triangles (0,1,2), (0,2,3); 0 outside. Pixel centres never lie on the
// quad's border (it runs along pixel edges).
std::vector<float> expectedQuad(uint32_t w, uint32_t h, const std::vector<Rgb>& vertexLum, bool fromBehind) {
  std::vector<float> img(size_t(w) * h * 3, 0.0f);
  const vec2 p[4] = {{-1, -0.5f}, {1, -0.5f}, {1, 0.5f}, {-1, 0.5f}};
  const int tris[2][3] = {{0, 1, 2}, {0, 2, 3}};
  for (uint32_t j = 0; j < h; ++j) {
    for (uint32_t i = 0; i < w; ++i) {
      const float sx = -2.0f + 4.0f * (float(i) + 0.5f) / float(w);  // image x in metres, left to right
      const float y = 1.0f - 2.0f * (float(j) + 0.5f) / float(h);
      const vec2 q(fromBehind ? -sx : sx, y);
      for (const auto& t : tris) {
        const vec2 a = p[t[0]], b = p[t[1]], c = p[t[2]];
        const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
        const float wa = ((b.x - q.x) * (c.y - q.y) - (b.y - q.y) * (c.x - q.x)) / area;
        const float wb = ((c.x - q.x) * (a.y - q.y) - (c.y - q.y) * (a.x - q.x)) / area;
        const float wc = 1.0f - wa - wb;
        if (wa < -1e-6f || wb < -1e-6f || wc < -1e-6f) continue;
        const Rgb l =
            wa * vertexLum[size_t(t[0])] + wb * vertexLum[size_t(t[1])] + wc * vertexLum[size_t(t[2])];
        for (int k = 0; k < 3; ++k) img[(size_t(j) * w + i) * 3 + size_t(k)] = l[k];
        break;
      }
    }
  }
  return img;
}

void expectImageNear(const std::vector<float>& actual, const std::vector<float>& expected,
                     float relTolerance) {
  ASSERT_EQ(actual.size(), expected.size());
  size_t bad = 0;
  for (size_t i = 0; i < actual.size(); ++i) {
    const float tol = relTolerance * std::max(1.0f, std::abs(expected[i]));
    if (!(std::abs(actual[i] - expected[i]) <= tol)) {
      if (++bad <= 5)
        ADD_FAILURE() << "value " << i << " (pixel " << i / 3 << "): " << actual[i] << " vs " << expected[i];
    }
  }
  EXPECT_EQ(bad, 0u);
}

struct QuadScene {
  sdb::Scene scene;
  sdb::NodeId node;
  sdb::MeshId mesh;
  sdb::MaterialId material;
};

QuadScene quadScene(bool twoSided) {
  QuadScene q;
  sdb::Material m;
  m.name = "paint";
  m.diffuseColor = Rgb(0.5f, 0.6f, 0.7f);
  q.material = q.scene.addMaterial(m).id;
  sdb::Mesh mesh = test::quadXY(q.material);
  mesh.twoSided = twoSided;
  q.mesh = q.scene.addMesh(mesh).id;
  q.node = q.scene.addNode({.name = "quad", .meshes = {q.mesh}}).id;
  return q;
}

// Per-vertex irradiance, different in every vertex and channel, lux.
const std::vector<Rgb> kFrontLux = {{100, 200, 300}, {400, 250, 50}, {1000, 800, 600}, {30, 60, 90}};
const std::vector<Rgb> kBackLux = {{5, 10, 20}, {40, 30, 20}, {7, 8, 9}, {100, 1, 10}};

std::vector<Rgb> luminanceOf(const std::vector<Rgb>& lux, const Rgb& albedo) {
  std::vector<Rgb> l;
  for (const Rgb& e : lux) l.push_back(albedo * e / kPiF);
  return l;
}

// The one-sided quad with kFrontLux as its vertex light map.
rdb::RasterRdb lightMappedQuad() {
  const QuadScene q = quadScene(false);
  rdb::LightMapStore store;
  store.meshes.push_back({q.node.value, q.mesh.value, kFrontLux, {}});
  return rdb::buildRasterRdb(q.scene, &store);
}

TEST(Renderer, LightMapModeIsAlbedoTimesIrradianceOverPiInterpolated) {
  context();
  const rdb::RasterRdb r = lightMappedQuad();
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  const Rgb albedo(0.5f, 0.6f, 0.7f);
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, luminanceOf(kFrontLux, albedo), false),
                  1e-4f);
  // The back of a one-sided surface is culled: the background (black in light-map mode) shows.
  renderer.render(orthoView(true), RenderMode::kLightMap, 64, 32);
  expectImageNear(renderer.luminanceRgb(), std::vector<float>(64 * 32 * 3, 0.0f), 1e-6f);
  // Every mesh has a light map and none is two-sided: no Phong, no front/back choice is compiled.
  EXPECT_EQ(renderer.stats().programs, (std::vector<std::string>{"background", "scene+lightmap"}));
}

// Each light counted once: a Lambertian ground of albedo 0.5 (one-sided, open to the sky: no light that it
// reflects comes back) under a glTF directional light of 80 000 lx shows ρE sin(elevation)/π in simple mode,
// the Phong's term alone: progressive radiosity's ambient term is c = 0 here (RasterRdb::ambientClosure); an
// ambient term that took all reflected light to come back, as in a closed room, would show 2 × ρE/π.
TEST(Renderer, ALambertianGroundUnderAGltfDirectionalLightShowsRhoEOverPiInSimpleMode) {
  context();
  for (const float elevationDeg : {10.0f, 30.0f, 60.0f, 90.0f}) {
    sdb::Scene s;
    sdb::Material ground;
    ground.diffuseColor = Rgb(0.5f);
    s.addNode({.name = "ground", .meshes = {s.addMesh(test::quadXY(s.addMaterial(ground).id)).id}});
    sdb::Light sun;
    sun.type = sdb::LightType::kDirectional;
    sun.intensity = 80000.0f;
    const float el = elevationDeg * kPiF / 180.0f;
    // The light travels along the node's −Z: (−cos el, 0, −sin el), down onto the quad facing +Z.
    s.addNode({.name = "sun",
               .parentFromLocal = frameTransform(vec3(std::sin(el), 0, -std::cos(el)), vec3(0, 1, 0),
                                                 vec3(std::cos(el), 0, std::sin(el)), vec3(0, 0, 5)),
               .light = s.addLight(sun).id});
    const rdb::RasterRdb r = rdb::buildRasterRdb(s);
    EXPECT_EQ(r.ambientClosure, 0.0f);  // a lone plane: no ray from it meets another surface
    Renderer renderer;
    renderer.upload(r);
    renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
    const std::vector<float> img = renderer.luminanceRgb();
    const float expected = 0.5f * 80000.0f * std::sin(el) / kPiF;
    EXPECT_NEAR(img[(size_t(16) * 64 + 32) * 3 + 1], expected, 0.02f * expected) << elevationDeg << "°";
  }
}

// The same for a glTF point light and a spot light (its corners inside the inner cone) of 2 000 cd, 2 m from
// the ground's centre at 30° from its normal: E = I cos θ / d² at each vertex, shown as ρE/π between them.
TEST(Renderer, ALambertianGroundUnderAGltfPointOrSpotLightShowsRhoEOverPiInSimpleMode) {
  context();
  for (const sdb::LightType type : {sdb::LightType::kPoint, sdb::LightType::kSpot}) {
    sdb::Scene s;
    sdb::Material ground;
    ground.diffuseColor = Rgb(0.5f);
    s.addNode({.name = "ground", .meshes = {s.addMesh(test::quadXY(s.addMaterial(ground).id)).id}});
    sdb::Light lamp;
    lamp.type = type;
    lamp.intensity = 2000.0f;
    lamp.innerConeRad = 0.6f;
    lamp.outerConeRad = 0.7f;
    const float theta = 30.0f * kPiF / 180.0f, d = 2.0f;
    // At (d sin θ, 0, d cos θ), its −Z (the spot's axis) towards the ground's centre.
    const vec3 z(std::sin(theta), 0.0f, std::cos(theta));
    s.addNode({.name = "lamp",
               .parentFromLocal = frameTransform(vec3(z.z, 0, -z.x), vec3(0, 1, 0), z, d * z),
               .light = s.addLight(lamp).id});
    const rdb::RasterRdb r = rdb::buildRasterRdb(s);
    EXPECT_EQ(r.ambientClosure, 0.0f);
    Renderer renderer;
    renderer.upload(r);
    renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
    // Per vertex (Gouraud): ρ/π · E at each corner of the quad, interpolated over its two triangles.
    std::vector<Rgb> corners;
    for (const vec3& p : test::quadXY(sdb::MaterialId{}).positions) {
      const vec3 toLamp = d * z - p;
      corners.push_back(Rgb(0.5f / kPiF * 2000.0f * toLamp.z / glm::length(toLamp) / glm::dot(toLamp, toLamp)));
    }
    expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, corners, false), 1e-3f);
  }
}

// Emission given as a display colour (glTF emission without KHR_materials_emissive_strength) shows as that
// fraction of the exposure's white at any exposure: a quad of display colour (1, 0.5, 0.25) reads
// (1, 0.5, 0.25) · W for W = 1.2 · 2^EV100 at EV100 0 and 15, and black before a white is set; a physical
// emitter of 200 cd/m² beside it reads 200 cd/m² at both.
TEST(Renderer, DisplayEmissionShowsAtTheExposuresWhite) {
  context();
  sdb::Scene s;
  sdb::Material label;
  label.diffuseColor = Rgb(0.0f);
  label.emissionLuminance = Rgb(1.0f, 0.5f, 0.25f);
  label.emissionDisplay = true;
  sdb::Material lamp = label;
  lamp.emissionLuminance = Rgb(200.0f);
  lamp.emissionDisplay = false;
  auto place = [](float x) { return frameTransform(vec3(0.4f, 0, 0), vec3(0, 0.8f, 0), vec3(0, 0, 1), vec3(x, 0, 0)); };
  s.addNode({.name = "label", .parentFromLocal = place(-1.0f), .meshes = {s.addMesh(test::quadXY(s.addMaterial(label).id)).id}});
  s.addNode({.name = "lamp", .parentFromLocal = place(1.0f), .meshes = {s.addMesh(test::quadXY(s.addMaterial(lamp).id)).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  Renderer renderer;
  renderer.upload(r);
  EXPECT_TRUE(renderer.hasDisplayEmission());
  const size_t labelPx = (size_t(16) * 64 + 16) * 3, lampPx = (size_t(16) * 64 + 48) * 3;
  renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
  EXPECT_EQ(renderer.luminanceRgb()[labelPx], 0.0f);
  for (const double ev100 : {0.0, 15.0}) {
    const float white = 1.0f / exposureScale(ev100);
    renderer.setDisplayWhite(white);
    renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
    const std::vector<float> img = renderer.luminanceRgb();
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(img[labelPx + size_t(c)], label.emissionLuminance[c] * white, 1e-4f * white) << ev100;
      EXPECT_NEAR(img[lampPx + size_t(c)], 200.0f, 0.02f) << ev100;
    }
  }
  // Neither lights the scene: the simple mode's ambient counts the lamp alone (no other surface here: 0).
  EXPECT_EQ(r.ambient.upLux, Rgb(0.0f));
}

// Daylight counted once in simple and sunlight modes: a Lambertian ground (albedo 0.5, facing +Y) under the
// site's clear sky with the sun (Helsinki, 21 June, 15:00) and under the CIE overcast sky (type 1, no sun)
// shows ρE/π, with E the sky model's horizontal illuminance plus the sun's normal illuminance times the sine
// of its elevation (sunsky, computed apart from the GL engine's tables), within 2 %.
TEST(Renderer, ALambertianGroundUnderTheSkyShowsRhoEOverPiInSimpleAndSunlightModes) {
  context();
  for (const bool overcast : {false, true}) {
    sdb::Scene s;
    sdb::Material ground;
    ground.diffuseColor = Rgb(0.5f);
    sdb::Mesh mesh = test::quadXY(s.addMaterial(ground).id);
    for (vec3& p : mesh.positions) p = vec3(p.x, 0.0f, -p.y);  // laid down: x ∈ [−1, 1], z ∈ [−0.5, 0.5]
    mesh.normals.assign(4, vec3(0, 1, 0));
    s.addNode({.name = "ground", .meshes = {s.addMesh(mesh).id}});
    fly::test::setHelsinkiClearSky(s, "2026-06-21T15:00");
    if (overcast) {
      sdb::SkySettings sky;
      sky.model = sdb::SkyModel::kCie;
      sky.cieType = 1;
      sky.sun = false;
      s.setSky(sky);
    }
    const std::optional<rdb::SceneDaylight> d = rdb::lowerDaylight(s);
    ASSERT_TRUE(d && d->sky);
    double eLux = sunsky::horizontalIlluminanceLux(*d->sky);
    if (d->sun) eLux += double(luminance(d->sun->normalIlluminanceLux)) * d->sunDirWorld.y;
    const float expected = float(0.5 * eLux / kPi);
    const rdb::RasterRdb r = rdb::buildRasterRdb(s);
    Renderer renderer;
    renderer.upload(r);
    // From 5 m above, looking straight down at the ground's centre.
    View v;
    v.orthographic = true;
    v.ymagM = 0.25f;
    v.znearM = 0.1f;
    v.zfarM = 10.0f;
    v.worldFromCamera = frameTransform(vec3(1, 0, 0), vec3(0, 0, -1), vec3(0, 1, 0), vec3(0, 5, 0));
    for (const RenderMode mode : {RenderMode::kSimple, RenderMode::kSunlight}) {
      renderer.render(v, mode, 32, 16);
      const std::vector<float> img = renderer.luminanceRgb();
      const size_t centre = (size_t(8) * 32 + 16) * 3;
      const float l = luminance(Rgb(img[centre], img[centre + 1], img[centre + 2]));
      EXPECT_NEAR(l, expected, 0.02f * expected)
          << (overcast ? "overcast, " : "clear, ") << renderModeName(mode) << " mode; E = " << eLux << " lx";
    }
  }
}

// A light-textured surface whose diffuse share depends on the angle (a dielectric with a Fresnel reflection:
// rdb::RasterVariants::diffuseByAngle) takes that share per fragment: seen at a grazing angle, with a uniform
// texture, the image is mirror-symmetric about the view's plane of symmetry (y = 0), although the quad's
// diagonal puts the two mirrored points in different triangles. A share taken at each triangle's provoking
// vertex (the two upper corners, at different angles) would show the diagonal as a step of several per cent.
TEST(Renderer, ALightTexturesDiffuseShareIsTakenPerFragmentWithNoStepAlongTheDiagonal) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.name = "varnish";
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(1.0f);
  m.reflectionModel = sdb::ReflectionModel::kFresnel;
  m.ior = 1.5f;
  m.reflectionGlossiness = 0.5f;
  const sdb::MeshId mesh = s.addMesh(test::quadXY(s.addMaterial(m).id)).id;
  const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {mesh}}).id;
  rdb::MeshLightTexture texture{2, 2, std::vector<Rgb>(4, Rgb(1000.0f)), {}, {}};
  const vec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  for (uint32_t v : {0u, 1u, 2u, 0u, 2u, 3u}) texture.cornerUv.push_back(uv[v]);
  rdb::LightMapStore store;
  store.meshes.push_back({node.value, mesh.value, kFrontLux, {}, texture});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
  ASSERT_TRUE(r.variants.lightTexture);
  ASSERT_TRUE(r.variants.diffuseByAngle);
  Renderer renderer;
  renderer.upload(r);
  // From beside the quad's right edge, 0.25 m in front of its plane, looking at its left end: angles of
  // incidence from about 50° to 83°.
  renderer.render(test::lookAtView(vec3(1.5f, 0.0f, 0.25f), vec3(-1.0f, 0.0f, 0.0f), 10.0f), RenderMode::kLightMap,
                  64, 32);
  const std::vector<float> img = renderer.luminanceRgb();
  size_t compared = 0;
  float lo = std::numeric_limits<float>::infinity(), hi = 0.0f;
  for (uint32_t j = 0; j < 16; ++j) {
    for (uint32_t i = 0; i < 64; ++i) {
      const float a = img[(size_t(j) * 64 + i) * 3 + 1], b = img[(size_t(31 - j) * 64 + i) * 3 + 1];
      if (!(a > 0.0f) || !(b > 0.0f)) continue;  // off the quad
      ++compared;
      lo = std::min(lo, a);
      hi = std::max(hi, a);
      EXPECT_NEAR(a, b, 2e-3f * b) << "pixel " << i << " of rows " << j << " and " << 31 - j;
    }
  }
  EXPECT_GT(compared, 100u);
  EXPECT_GT(hi / lo, 1.1f);  // the share does vary over the image
}

// Sunlight mode over light maps that keep the sun's direct part apart (FLY §3): albedo · (E − E_sunDirect) /
// π plus the sun's Lambert term for the current sun. A matte quad facing +Z (south: north is −Z) under a
// clear sky with the sun placed at azimuth 180°; its light map holds E = E_other + E_sunDirect with
// E_sunDirect = E_n cos θ, what a bake without occluders gives at that sun. At the bake's sun sunlight mode
// shows what light-map mode shows; at another sun it differs by albedo/π · (E_n' cos θ' − E_n cos θ), the
// Lambert term's change. Both per vertex (one draw) and per texel (a light texture). The sky behind the quad
// is left out of the comparison.
TEST(Renderer, SunlightModeAddsTheRealTimeSunToTheLightMapWithoutItsDirectPart) {
  context();
  for (const bool texture : {false, true}) {
    QuadScene q = quadScene(false);
    sdb::Material matte;
    matte.diffuseColor = Rgb(0.5f, 0.6f, 0.7f);
    matte.reflectionColor = Rgb(0.0f);
    q.scene.setMaterial(q.material, matte);
    q.scene.setSky({.model = sdb::SkyModel::kClear, .sun = true});
    q.scene.setTime({.sunDirection = sdb::SunDirection{180.0, 30.0}});
    // The sun as the engine draws it: E_n on a surface facing it, towards sunDirWorld.
    auto sunOf = [](const rdb::RasterRdb& r, vec3& dir) {
      const rdb::RasterSky& sky = *r.sky;
      dir = sky.sunDirWorld;
      return sky.sunRadianceCdM2 * float(2.0 * kPi * (1.0 - std::cos(double(sky.sunHalfAngleRad))));
    };
    vec3 bakedDir;
    const Rgb bakedNormalLux = sunOf(rdb::buildRasterRdb(q.scene), bakedDir);
    ASSERT_GT(bakedDir.z, 0.5f);
    const Rgb sunDirect = bakedNormalLux * bakedDir.z;  // the quad's normal is +Z
    rdb::LightMapStore store;
    store.sun = rdb::BakedSun{bakedDir, bakedNormalLux};
    rdb::MeshLightMap map{q.node.value, q.mesh.value, {}, {}};
    for (const Rgb& other : kFrontLux) {
      map.frontLux.push_back(other + sunDirect);
      map.frontSunDirectLux.push_back(sunDirect);
    }
    if (texture) {
      // One texel per corner's quarter: 2 × 2 texels, E_other of the corners, over the quad's UV square.
      rdb::MeshLightTexture t;
      t.width = t.height = 2;
      for (const Rgb& other : {kFrontLux[3], kFrontLux[2], kFrontLux[0], kFrontLux[1]}) {
        t.frontLux.push_back(other + sunDirect);
        t.frontSunDirectLux.push_back(sunDirect);
      }
      t.cornerUv = {{0, 1}, {1, 1}, {1, 0}, {0, 1}, {1, 0}, {0, 0}};
      map.lightTexture = t;
    }
    store.meshes.push_back(map);
    rdb::RasterRdb r = rdb::buildRasterRdb(q.scene, &store);
    ASSERT_TRUE(r.variants.sunDirect);
    Renderer renderer;
    renderer.upload(r);
    renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
    const std::vector<float> lightMap = renderer.luminanceRgb();
    renderer.render(orthoView(false), RenderMode::kSunlight, 64, 32);
    const std::vector<float> atBake = renderer.luminanceRgb();
    // Another time: the sun at 60°, with the light map as it was.
    const rdb::RasterRdbChanges changes = rdb::updateRasterRdb(
        r, q.scene, q.scene.setTime({.sunDirection = sdb::SunDirection{180.0, 60.0}}), &store);
    EXPECT_FALSE(changes.geometry);  // the light maps stay; only the sky and sun are re-made
    const auto geometryUploads = renderer.stats().geometryUploads;
    renderer.update(r, changes);
    EXPECT_EQ(renderer.stats().geometryUploads, geometryUploads);  // nor are they uploaded again
    renderer.render(orthoView(false), RenderMode::kSunlight, 64, 32);
    const std::vector<float> later = renderer.luminanceRgb();
    vec3 laterDir;
    const Rgb laterNormalLux = sunOf(r, laterDir);
    const Rgb albedo = matte.diffuseColor;
    const Rgb change = albedo / kPiF * (laterNormalLux * laterDir.z - sunDirect);
    EXPECT_GT(std::abs(luminance(change)), 0.05f * luminance(albedo / kPiF * sunDirect));
    size_t compared = 0, bad = 0;
    for (size_t i = 0; i < lightMap.size(); ++i) {
      // The quad (x ∈ [−1, 1], y ∈ [−0.5, 0.5]) in orthoView's 4 × 2 m image; elsewhere the sky.
      const size_t px = i / 3 % 64, py = i / 3 / 64;
      if (std::abs(-2.0f + 4.0f * (float(px) + 0.5f) / 64.0f) > 1.0f ||
          std::abs(1.0f - 2.0f * (float(py) + 0.5f) / 32.0f) > 0.5f)
        continue;
      ++compared;
      const float tolerance = 1e-4f * lightMap[i];
      const float expectedLater = lightMap[i] + change[int(i % 3)];
      if (!(std::abs(atBake[i] - lightMap[i]) <= tolerance) ||
          !(std::abs(later[i] - expectedLater) <= tolerance)) {
        if (++bad <= 5)
          ADD_FAILURE() << (texture ? "light texture" : "vertex light map") << ", value " << i
                        << ": light map " << lightMap[i] << ", sunlight at the bake's sun " << atBake[i]
                        << ", at 60° " << later[i] << " (expected " << expectedLater << ")";
      }
    }
    EXPECT_EQ(compared, 64u * 32u * 3u / 4u);  // the quad covers a quarter of the view
    EXPECT_EQ(bad, 0u);
    const std::vector<std::string>& programs = renderer.stats().programs;
    EXPECT_TRUE(std::any_of(programs.begin(), programs.end(),
                            [](const std::string& p) { return p.find("+sundirect") != std::string::npos; }));
  }
}

// Clear glass: transmission (0.9, 0.8, 0.7), white Fresnel reflection at ior 1.5, no diffuse.
sdb::Material clearGlass() {
  sdb::Material glass;
  glass.name = "glass";
  glass.diffuseColor = Rgb(0.0f);
  glass.reflectionColor = Rgb(1.0f);
  glass.reflectionModel = sdb::ReflectionModel::kFresnel;
  glass.ior = 1.5f;
  glass.reflectionGlossiness = 0.0f;
  glass.transmissionColor = Rgb(0.9f, 0.8f, 0.7f);
  glass.transmissionGlossiness = 0.0f;
  return glass;
}

// A pane over the left half of quadXY, 1 m in front of it (x ∈ [−1, 0], y ∈ [−0.5, 0.5], z = 1), with
// uv0 = (x + 1, 0.5 − y), its front or its back towards the camera. `tilted`: turned about its edge x = 0 so
// that its normal lies 60° from +Z (its edge x = −1 at z = 1 + √3), projecting onto the same half.
sdb::Mesh leftPane(sdb::MaterialId material, bool backTowardsCamera, bool tilted = false) {
  sdb::Mesh pane;
  pane.name = "pane";
  const float farZ = tilted ? 1.0f + std::sqrt(3.0f) : 1.0f;
  pane.positions = {{-1.0f, -0.5f, farZ}, {0.0f, -0.5f, 1.0f}, {0.0f, 0.5f, 1.0f}, {-1.0f, 0.5f, farZ}};
  const vec3 normal = tilted ? vec3(0.5f * std::sqrt(3.0f), 0.0f, 0.5f) : vec3(0, 0, 1);
  pane.normals.assign(4, backTowardsCamera ? -normal : normal);
  for (const vec3& p : pane.positions) pane.uv0.push_back(vec2(p.x + 1.0f, 0.5f - p.y));
  pane.indices = backTowardsCamera ? std::vector<uint32_t>{0, 2, 1, 0, 3, 2} : std::vector<uint32_t>{0, 1, 2, 0, 2, 3};
  pane.material = material;
  return pane;
}

// Clear glass shows what lies behind it times its T(θ) (rdb/raster_rdb.h; base/clear_pane.h): the pane of
// clearGlass() over the left half of the light-mapped quad, 1 m in front of it, with its front and then its
// back towards the camera (either face passes light). Seen head-on (orthographic: cos θ = 1), T = t (1 − F0),
// F0 = 0.04; tilted so that its normal lies 60° from the view (cos θ = 0.5), T is
// sdb::Material::clearTransmittanceAt(0.5), the slab of two Fresnel faces, below the energy rule's one-face
// t (1 − F(θ)). Everything else is as without the pane.
TEST(Renderer, ClearGlassShowsWhatLiesBehindItTimesItsTransmittance) {
  context();
  const sdb::Material glass = clearGlass();
  for (const bool tilted : {false, true}) {
    for (const bool backTowardsCamera : {false, true}) {
      QuadScene q = quadScene(false);
      q.scene.addNode({.name = "window",
                       .meshes = {q.scene.addMesh(leftPane(q.scene.addMaterial(glass).id, backTowardsCamera, tilted))
                                      .id}});
      rdb::LightMapStore store;
      store.meshes.push_back({q.node.value, q.mesh.value, kFrontLux, {}});
      const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene, &store);
      ASSERT_TRUE(r.variants.glass);
      Renderer renderer;
      renderer.upload(r);
      renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
      std::vector<float> expected =
          expectedQuad(64, 32, luminanceOf(kFrontLux, Rgb(0.5f, 0.6f, 0.7f)), false);
      const float cosTheta = tilted ? 0.5f : 1.0f;
      const Rgb transmittance = glass.clearTransmittanceAt(cosTheta);
      if (tilted) {
        for (int k = 0; k < 3; ++k) {
          EXPECT_LT(transmittance[k], 0.97f * glass.effectiveAt(cosTheta).transmission[k]) << k;
        }
      } else {
        for (int k = 0; k < 3; ++k)
          EXPECT_NEAR(transmittance[k], glass.transmissionColor[k] * (1.0f - 0.04f), 1e-6f);
      }
      for (uint32_t j = 0; j < 32; ++j) {
        for (uint32_t i = 0; i < 32; ++i) {  // image x < 0: behind the pane
          for (int k = 0; k < 3; ++k) expected[(size_t(j) * 64 + i) * 3 + size_t(k)] *= transmittance[k];
        }
      }
      SCOPED_TRACE(tilted ? "pane at 60°" : "pane head-on");
      expectImageNear(renderer.luminanceRgb(), expected, 1e-4f);
      // The pane has no light map: the light-map program with the Phong fallback, and the glass pass.
      EXPECT_EQ(renderer.stats().programs,
                (std::vector<std::string>{"background", "scene+lightmap+phong+glass"}));
    }
  }
}

TEST(Renderer, TwoSidedLightMapsPickTheFaceTheCameraSees) {
  context();
  QuadScene q = quadScene(true);
  rdb::LightMapStore store;
  store.meshes.push_back({q.node.value, q.mesh.value, kFrontLux, kBackLux});
  const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene, &store);
  ASSERT_TRUE(r.variants.twoSided);
  Renderer renderer;
  renderer.upload(r);
  const Rgb albedo(0.5f, 0.6f, 0.7f);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, luminanceOf(kFrontLux, albedo), false),
                  1e-4f);
  renderer.render(orthoView(true), RenderMode::kLightMap, 64, 32);
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, luminanceOf(kBackLux, albedo), true), 1e-4f);
}

// GL's bilinear lookup with clamp-to-edge in a width × height texture (row 0 at v = 0) at `uv`.
Rgb bilinear(const std::vector<Rgb>& texels, int width, int height, const vec2& uv) {
  const float tx = uv.x * float(width) - 0.5f, ty = uv.y * float(height) - 0.5f;
  const int x0 = int(std::floor(tx)), y0 = int(std::floor(ty));
  const float fx = tx - float(x0), fy = ty - float(y0);
  const auto at = [&](int x, int y) {
    return texels[size_t(std::clamp(y, 0, height - 1) * width + std::clamp(x, 0, width - 1))];
  };
  return glm::mix(glm::mix(at(x0, y0), at(x0 + 1, y0), fx), glm::mix(at(x0, y0 + 1), at(x0 + 1, y0 + 1), fx),
                  fy);
}

// A light-textured quadXY as placed: world rectangle lo–hi in z = 0, UV u = (x − lo.x)/(hi.x − lo.x) left to
// right and v = (hi.y − y)/(hi.y − lo.y) (v = 0 along the top edge, the texture's row 0).
struct TexturedQuad {
  vec2 lo, hi;
  rdb::MeshLightTexture texture;
};

// CPU expectation of light-textured quads seen through orthoView in a w × h image (aspect 2): albedo ·
// bilinear(E) / π at each pixel centre's UV, the back texture from behind (black for a one-sided quad).
std::vector<float> expectedTexturedQuads(uint32_t w, uint32_t h, const std::vector<TexturedQuad>& quads,
                                         const Rgb& albedo, bool fromBehind) {
  std::vector<float> img(size_t(w) * h * 3, 0.0f);
  for (uint32_t j = 0; j < h; ++j) {
    for (uint32_t i = 0; i < w; ++i) {
      const float sx = -2.0f + 4.0f * (float(i) + 0.5f) / float(w);
      const vec2 p(fromBehind ? -sx : sx, 1.0f - 2.0f * (float(j) + 0.5f) / float(h));
      for (const TexturedQuad& q : quads) {
        if (p.x < q.lo.x || p.x > q.hi.x || p.y < q.lo.y || p.y > q.hi.y) continue;
        const vec2 uv((p.x - q.lo.x) / (q.hi.x - q.lo.x), (q.hi.y - p.y) / (q.hi.y - q.lo.y));
        const std::vector<Rgb>& texels = fromBehind ? q.texture.backLux : q.texture.frontLux;
        if (texels.empty()) continue;
        const Rgb l = albedo * bilinear(texels, int(q.texture.width), int(q.texture.height), uv) / kPiF;
        for (int k = 0; k < 3; ++k) img[(size_t(j) * w + i) * 3 + size_t(k)] = l[k];
      }
    }
  }
  return img;
}

// Light-map mode with light textures: a two-sided quadXY with a 4 × 4 checker of two irradiances on the
// front and a 4 × 4 gradient (every texel different) on the back, and two small one-sided quads (0.5 × 0.25
// m) with 2 × 2 and 3 × 1 textures, which share one layer of the array texture. The vertex light values
// (kFrontLux, kBackLux) must not show: the textures replace them.
TEST(Renderer, LightTexturesAreSampledBilinearlyPerFragment) {
  context();
  QuadScene q = quadScene(true);
  const sdb::MeshId small = q.scene.addMesh(test::quadXY(q.material)).id;
  const auto placeSmall = [&](const char* name, const vec2& centre) {
    mat4 m(0.25f);
    m[3] = vec4(centre, 0.0f, 1.0f);
    return q.scene.addNode({.name = name, .parentFromLocal = m, .meshes = {small}}).id;
  };
  const sdb::NodeId smallA = placeSmall("smallA", {1.6f, 0.8f});
  const sdb::NodeId smallB = placeSmall("smallB", {-1.6f, -0.8f});

  std::vector<vec2> cornerUv;
  const vec2 uv[4] = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  for (uint32_t v : {0u, 1u, 2u, 0u, 2u, 3u}) cornerUv.push_back(uv[v]);
  std::vector<TexturedQuad> quads(3);
  quads[0] = {{-1.0f, -0.5f}, {1.0f, 0.5f}, {4, 4, {}, {}, cornerUv}};
  const Rgb luxA(1000, 1200, 800), luxB(3000, 2500, 3500);
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      quads[0].texture.frontLux.push_back((i + j) % 2 ? luxB : luxA);
      quads[0].texture.backLux.push_back(Rgb(100.0f + 50.0f * float(i), 200.0f + 300.0f * float(j), 500.0f));
    }
  }
  quads[1] = {{1.35f, 0.675f}, {1.85f, 0.925f}, {2, 2, {}, {}, cornerUv}};
  quads[1].texture.frontLux = {{400, 0, 0}, {0, 400, 0}, {0, 0, 400}, {400, 400, 400}};
  quads[2] = {{-1.85f, -0.925f}, {-1.35f, -0.675f}, {3, 1, {}, {}, cornerUv}};
  quads[2].texture.frontLux = {{2000, 100, 100}, {100, 2000, 100}, {100, 100, 2000}};
  rdb::LightMapStore store;
  store.meshes.push_back({q.node.value, q.mesh.value, kFrontLux, kBackLux, quads[0].texture});
  store.meshes.push_back({smallA.value, small.value, kFrontLux, {}, quads[1].texture});
  store.meshes.push_back({smallB.value, small.value, kFrontLux, {}, quads[2].texture});
  const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene, &store);
  ASSERT_TRUE(r.variants.lightTexture);
  ASSERT_EQ(r.lightTextures.size(), 3u);

  Renderer renderer;
  renderer.upload(r);
  const Rgb albedo(0.5f, 0.6f, 0.7f);
  // GPUs weight bilinear taps with a few bits (8 on NVIDIA and llvmpipe): allow 1% of the checker's contrast.
  const float tolerance = 0.01f * albedo.g * (luxB.r - luxA.r) / kPiF;
  const auto expectNear = [&](const std::vector<float>& actual, const std::vector<float>& expected) {
    ASSERT_EQ(actual.size(), expected.size());
    size_t bad = 0, lit = 0;
    for (size_t i = 0; i < actual.size(); ++i) {
      lit += expected[i] > 0.0f;
      if (!(std::abs(actual[i] - expected[i]) <= tolerance) && ++bad <= 5)
        ADD_FAILURE() << "value " << i << " (pixel " << i / 3 << "): " << actual[i] << " vs " << expected[i];
    }
    EXPECT_EQ(bad, 0u);
    EXPECT_GT(lit, actual.size() / 8);  // the quads fill a good part of the image
  };
  renderer.render(orthoView(false), RenderMode::kLightMap, 128, 64);
  expectNear(renderer.luminanceRgb(), expectedTexturedQuads(128, 64, quads, albedo, false));
  renderer.render(orthoView(true), RenderMode::kLightMap, 128, 64);
  expectNear(renderer.luminanceRgb(), expectedTexturedQuads(128, 64, quads, albedo, true));
  EXPECT_EQ(renderer.stats().programs,
            (std::vector<std::string>{"background", "scene+lightmap+twosided+lighttexture"}));
}

// Simple mode, analytic: a directional light of E = 1000 lx falling straight on a matte quad of albedo ρ =
// 0.5 (grey). A lone quad reflects nothing onto another surface (closure c = 0), so the directional ambient
// level ρc/(1 − ρc) · Ē is 0 and L = ρE/π everywhere on the quad.
TEST(Renderer, SimpleModeDirectionalLightPlusAmbientOnAMatteQuad) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(0.0f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  s.addNode({.name = "quad", .meshes = {s.addMesh(test::quadXY(mat)).id}});
  sdb::Light sun;
  sun.type = sdb::LightType::kDirectional;
  sun.intensity = 1000.0f;
  // The light's node looks down its −Z; place it at +Z looking towards −Z (onto the quad's front).
  s.addNode({.name = "light", .light = s.addLight(sun).id});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_EQ(r.lights.size(), 1u);
  EXPECT_EQ(r.ambient.upLux.g, 0.0f);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
  const float l = 0.5f / kPiF * 1000.0f;
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, std::vector<Rgb>(4, Rgb(l)), false), 1e-4f);
}

// Simple mode with a goniometric light, analytic: a rotationally symmetric type C profile falling linearly from
// 1000 cd at nadir to 0 at zenith (I(γ) = 1000 · (1 − γ/180°), exact on the tabulated 5° grid), 2 m in front
// of the quad's centre and aimed at it. Its four vertices are alike, so L = ρE/π as above, with
// E = I(γ) cos γ / d², cos γ = 2/d.
TEST(Renderer, SimpleModeGoniometricLight) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  s.addNode({.name = "quad", .meshes = {s.addMesh(test::quadXY(mat)).id}});
  auto profile = std::make_shared<sdb::IesProfile>();
  profile->verticalDeg = {0.0, 90.0, 180.0};
  profile->horizontalDeg = {0.0};
  profile->candela = {{1000.0, 500.0, 0.0}};
  sdb::Light lamp;
  lamp.type = sdb::LightType::kGoniometric;
  lamp.ies = profile;
  lamp.iesPath = "linear.ies";
  s.addNode({.name = "lamp",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, 2)),
             .light = s.addLight(lamp).id});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_TRUE(r.variants.goniometric);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
  const double d = std::sqrt(1.0 + 0.25 + 4.0);
  const double gammaDeg = radToDeg(std::acos(2.0 / d));
  const double e = 1000.0 * (1.0 - gammaDeg / 180.0) * (2.0 / d) / (d * d);
  const float l = float(0.5 / kPi * e);
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, std::vector<Rgb>(4, Rgb(l)), false), 1e-4f);
  EXPECT_EQ(renderer.stats().programs, (std::vector<std::string>{"background", "scene+phong+gonio"}));
}

// An 8-bit texture of `channels` channels from its bytes, row-major from the top row.
sdb::TextureId addTexture(sdb::Scene& s, int w, int h, int channels, std::vector<uint8_t> bytes) {
  sdb::Texture t;
  t.name = "t";
  t.sourcePath = "<embedded>";
  t.width = w;
  t.height = h;
  t.channels = channels;
  t.pixels = std::move(bytes);
  return s.addTexture(std::move(t)).id;
}

// quadXY with uv0 = ((x + 1)/2, 0.5 − y): u from 0 to 1 left to right, v from 0 at the top to 1 at the bottom.
sdb::Mesh uvQuad(sdb::MaterialId material) {
  sdb::Mesh m = test::quadXY(material);
  for (const vec3& p : m.positions) m.uv0.push_back(vec2((p.x + 1.0f) * 0.5f, 0.5f - p.y));
  return m;
}

// The light-map mode of a textured surface: base colour factor × the texel (sRGB-decoded by the GPU) ×
// COLOR_0 × E / π, and its emission texel × the emission factor added; a 1 × 1 texture reads the same
// texel everywhere (every mip level is that texel).
TEST(Renderer, TexturedLightMapIsFactorTimesTexelTimesColourTimesIrradianceOverPi) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f, 0.6f, 0.7f);
  m.diffuseTexture.texture = addTexture(s, 1, 1, 3, {188, 120, 60});
  m.emissionLuminance = Rgb(20.0f);
  m.emissionTexture.texture = addTexture(s, 1, 1, 3, {255, 128, 0});
  const sdb::MaterialId mat = s.addMaterial(m).id;
  sdb::Mesh mesh = uvQuad(mat);
  mesh.colors.assign(4, vec4(0.8f, 1.0f, 0.5f, 1.0f));
  const sdb::MeshId meshId = s.addMesh(mesh).id;
  const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {meshId}}).id;
  rdb::LightMapStore store;
  store.meshes.push_back({node.value, meshId.value, kFrontLux, {}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  const Rgb albedo = Rgb(0.5f, 0.6f, 0.7f) * srgbToLinear(Rgb(188, 120, 60) / 255.0f) * Rgb(0.8f, 1.0f, 0.5f);
  const Rgb emission = 20.0f * srgbToLinear(Rgb(255, 128, 0) / 255.0f);
  std::vector<Rgb> vertexLum = luminanceOf(kFrontLux, albedo);
  for (Rgb& l : vertexLum) l += emission;
  // GPUs may decode 8-bit sRGB up to about half a code value off (llvmpipe: +0.3 % at 60/255); a missing
  // decode would be 2–5× off.
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, vertexLum, false), 1e-2f);
  EXPECT_EQ(renderer.stats().programs,
            (std::vector<std::string>{"background", "scene+lightmap+perfragment+textures+vertexcolor"}));
  EXPECT_EQ(renderer.stats().textureUploads, 2);
}

// Light-map mode shows an opaque uniform (metal) reflection as a rough reflector: (diffuse after the energy
// rule + reflection) · E / π, per vertex and per fragment (a white 1 × 1 texture); a pure metal (glTF
// metallic 1: no diffuse) is reflection · E / π, not black. A Fresnel (dielectric) reflection adds nothing.
TEST(Renderer, LightMapModeShowsAMetalAsARoughReflectorOfItsReflectance) {
  context();
  struct Case {
    Rgb diffuse, reflection;
    sdb::ReflectionModel model;
    bool textured;
  };
  const Case cases[] = {
      {Rgb(0.0f), Rgb(0.95f, 0.64f, 0.54f), sdb::ReflectionModel::kUniform, false},  // copper, factor-only
      {Rgb(0.0f), Rgb(0.95f, 0.64f, 0.54f), sdb::ReflectionModel::kUniform, true},
      {Rgb(0.5f, 0.4f, 0.3f), Rgb(0.6f, 0.5f, 0.2f), sdb::ReflectionModel::kUniform, false},
      {Rgb(0.5f, 0.4f, 0.3f), Rgb(1.0f), sdb::ReflectionModel::kFresnel, false},
  };
  for (const Case& c : cases) {
    sdb::Scene s;
    sdb::Material m;
    m.diffuseColor = c.diffuse;
    m.reflectionColor = c.reflection;
    m.reflectionModel = c.model;
    m.reflectionGlossiness = 0.2f;
    // The light-map term alone: a flat mirror-like metal would otherwise get a planar reflection
    // (docs/reflections.md), which shows its reflection by the mirrored image instead.
    m.engineReflection = sdb::EngineReflection::kNone;
    if (c.textured) m.diffuseTexture.texture = addTexture(s, 1, 1, 3, {255, 255, 255});
    const sdb::MaterialId mat = s.addMaterial(m).id;
    const sdb::MeshId meshId = s.addMesh(uvQuad(mat)).id;
    const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {meshId}}).id;
    rdb::LightMapStore store;
    store.meshes.push_back({node.value, meshId.value, kFrontLux, {}});
    const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
    Renderer renderer;
    renderer.upload(r);
    renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
    // The energy rule by hand: uniform reflection R leaves (1 − R) · diffuse; Fresnel F0 = 0.04 at ior 1.5.
    const Rgb rho = c.model == sdb::ReflectionModel::kUniform
                        ? (Rgb(1.0f) - c.reflection) * c.diffuse + c.reflection
                        : (1.0f - 0.04f) * c.diffuse;
    expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, luminanceOf(kFrontLux, rho), false), 1e-4f);
  }
}

// A glTF metal reflects its base colour texture (sdb::Material::reflectionTextureSrgb): in light-map mode its
// rough-reflector term is reflection × the decoded texel × E / π; without the tint it would be the factor
// alone, (0.9, 0.8, 0.7) · E / π, 1.9–8.3× brighter than this texel allows.
TEST(Renderer, AMetalsReflectionIsTintedByItsBaseColourTexture) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.0f);
  m.reflectionColor = Rgb(0.9f, 0.8f, 0.7f);
  m.reflectionModel = sdb::ReflectionModel::kUniform;
  m.reflectionGlossiness = 0.2f;
  m.engineReflection = sdb::EngineReflection::kNone;
  m.diffuseTexture.texture = addTexture(s, 1, 1, 3, {188, 120, 60});
  m.reflectionTexture = m.diffuseTexture;
  m.reflectionTextureSrgb = true;
  const sdb::MaterialId mat = s.addMaterial(m).id;
  const sdb::MeshId meshId = s.addMesh(uvQuad(mat)).id;
  const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {meshId}}).id;
  rdb::LightMapStore store;
  store.meshes.push_back({node.value, meshId.value, kFrontLux, {}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
  ASSERT_TRUE(r.materials.back().reflectionTinted);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  const Rgb rho = Rgb(0.9f, 0.8f, 0.7f) * srgbToLinear(Rgb(188, 120, 60) / 255.0f);
  // GPUs may decode 8-bit sRGB up to about half a code value off (as above).
  expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, luminanceOf(kFrontLux, rho), false), 1e-2f);
}

// glTF sampler wrap modes and filters: a 2 × 2 texture (red, green / blue, white from the top left) over the
// quad with u from −1 to 2 (left to right) and v from −0.5 to 1.5 (top to bottom), magnified with NEAREST: a
// pixel shows the texel that the wrap mode maps its UV into, computed here from the GL specification's
// definitions (OpenGL 4.5 §8.14.2: REPEAT takes the fractional part, MIRRORED_REPEAT mirrors every other
// copy, CLAMP_TO_EDGE clamps to the edge texels' centres). Unlit black ground, light map E = π lx: L = texel.
// The 2 × 1 m quad (test::quadXY) of material m, its UV running from −1 to 2 along x and from 2.5 to −0.5
// along y, under a light map of E = π lx (so L = the albedo).
struct UvQuad {
  rdb::RasterRdb rdb;
  sdb::MaterialId material;
  rdb::LightMapStore store;
};
UvQuad uvQuadUnderLightMap(sdb::Scene& s, const sdb::Material& m) {
  UvQuad q;
  q.material = s.addMaterial(m).id;
  sdb::Mesh mesh = test::quadXY(q.material);
  for (const vec3& p : mesh.positions)
    mesh.uv0.push_back(vec2(1.5f * (p.x + 1.0f) - 1.0f, 1.5f - 2.0f * (p.y + 0.5f)));
  const sdb::MeshId meshId = s.addMesh(mesh).id;
  const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {meshId}}).id;
  q.store.meshes.push_back({node.value, meshId.value, std::vector<Rgb>(4, Rgb(kPiF)), {}});
  q.rdb = rdb::buildRasterRdb(s, &q.store);
  return q;
}

TEST(Renderer, SamplerWrapModesAndNearestFilteringPickTheExpectedTexels) {
  context();
  const uint8_t texels[4][3] = {{255, 0, 0}, {0, 255, 0}, {0, 0, 255}, {255, 255, 255}};
  std::vector<uint8_t> bytes;
  for (const auto& t : texels) bytes.insert(bytes.end(), t, t + 3);
  // GL wrap of a coordinate c in texels of an image of size n, for NEAREST: the texel index.
  auto wrapIndex = [](float uv, sdb::WrapMode mode) {
    const float c = uv * 2.0f;  // texel space, n = 2
    switch (mode) {
      case sdb::WrapMode::kRepeat:
        return int(std::floor(c - 2.0f * std::floor(c / 2.0f)));
      case sdb::WrapMode::kMirroredRepeat: {
        const float m = c - 4.0f * std::floor(c / 4.0f);  // period 2n
        return int(std::floor(m < 2.0f ? m : 4.0f - m));
      }
      case sdb::WrapMode::kClampToEdge:
        break;
    }
    return std::clamp(int(std::floor(c)), 0, 1);
  };
  const sdb::WrapMode modes[] = {sdb::WrapMode::kRepeat, sdb::WrapMode::kMirroredRepeat,
                                 sdb::WrapMode::kClampToEdge};
  for (sdb::WrapMode ws : modes) {
    for (sdb::WrapMode wt : modes) {
      sdb::Scene s;
      sdb::Material m;
      m.diffuseColor = Rgb(1.0f);
      m.reflectionColor = Rgb(0.0f);
      m.diffuseTexture.texture = addTexture(s, 2, 2, 3, bytes);
      m.diffuseTexture.wrapS = ws;
      m.diffuseTexture.wrapT = wt;
      m.diffuseTexture.magFilter = sdb::MagFilter::kNearest;
      m.diffuseTexture.minFilter = sdb::MinFilter::kNearest;
      const rdb::RasterRdb r = uvQuadUnderLightMap(s, m).rdb;
      Renderer renderer;
      renderer.upload(r);
      constexpr uint32_t kW = 96, kH = 48;  // 24 pixels per metre: the quad is 48 × 24 pixels
      renderer.render(orthoView(false), RenderMode::kLightMap, kW, kH);
      const std::vector<float> img = renderer.luminanceRgb();
      size_t checked = 0;
      for (uint32_t j = 0; j < kH; ++j) {
        for (uint32_t i = 0; i < kW; ++i) {
          const float x = -2.0f + 4.0f * (float(i) + 0.5f) / float(kW),
                      y = 1.0f - 2.0f * (float(j) + 0.5f) / float(kH);
          if (std::abs(x) > 1.0f || std::abs(y) > 0.5f) continue;
          const float u = 1.5f * (x + 1.0f) - 1.0f, v = 1.5f - 2.0f * (y + 0.5f);
          // Skip pixels within 0.05 texel of a texel border, where rounding may pick either neighbour.
          const float cu = u * 2.0f, cv = v * 2.0f;
          if (std::abs(cu - std::round(cu)) < 0.05f || std::abs(cv - std::round(cv)) < 0.05f) continue;
          const int tx = wrapIndex(u, ws), ty = wrapIndex(v, wt);
          const uint8_t* t = texels[ty * 2 + tx];
          for (int k = 0; k < 3; ++k) {
            ASSERT_NEAR(img[(size_t(j) * kW + i) * 3 + size_t(k)], t[k] / 255.0f, 1e-3f)
                << "wrap " << int(ws) << "/" << int(wt) << " pixel " << i << "," << j << " uv " << u << ","
                << v;
          }
          ++checked;
        }
      }
      EXPECT_GT(checked, 48u * 24u * 3u / 4u);
      EXPECT_EQ(renderer.stats().samplerObjects, 1);
    }
  }
}

// A sampler edit is a block edit: the draw binds the edited sampler and renders what a fresh upload renders.
TEST(Renderer, SamplerEditRendersLikeAFreshUpload) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(1.0f);
  m.reflectionColor = Rgb(0.0f);
  m.diffuseTexture.texture = addTexture(s, 2, 2, 3, {255, 0, 0, 0, 255, 0, 0, 0, 255, 255, 255, 255});
  m.diffuseTexture.magFilter = sdb::MagFilter::kNearest;
  UvQuad q = uvQuadUnderLightMap(s, m);
  rdb::RasterRdb& r = q.rdb;
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 96, 48);
  const std::vector<float> repeat = renderer.luminanceRgb();
  m.diffuseTexture.wrapS = sdb::WrapMode::kClampToEdge;
  m.diffuseTexture.wrapT = sdb::WrapMode::kMirroredRepeat;
  const rdb::RasterRdbChanges ch = rdb::updateRasterRdb(r, s, s.setMaterial(q.material, m), &q.store);
  ASSERT_EQ(ch.materialBlocks, std::vector<uint32_t>{1});
  renderer.update(r, ch);
  renderer.render(orthoView(false), RenderMode::kLightMap, 96, 48);
  const std::vector<float> clamped = renderer.luminanceRgb();
  EXPECT_NE(repeat, clamped);
  EXPECT_EQ(renderer.stats().samplerObjects, 2);
  const rdb::RasterRdb fresh = rdb::buildRasterRdb(s, &q.store);
  Renderer other;
  other.upload(fresh);
  other.render(orthoView(false), RenderMode::kLightMap, 96, 48);
  EXPECT_EQ(clamped, other.luminanceRgb());
}

// A normal map bends the normal of the Phong terms: a 1000 lx directional light along the quad's normal and
// the ambient level (1000 lx, as in SimpleModeDirectionalLightPlusAmbientOnAMatteQuad) give L = ρ/π ·
// (1000 · n'_z + 1000), with n' the texel's normal (2 · texel − 1, normalised) in the tangent frame (tangent
// +X from u, bitangent +Y towards the image's top, normal +Z); with normalScale 0 the map is flat.
TEST(Renderer, NormalMapsBendTheNormalOfThePhongTerms) {
  context();
  for (float scale : {1.0f, 0.0f}) {
    sdb::Scene s;
    sdb::Material m;
    m.diffuseColor = Rgb(0.5f);
    m.bumpTexture.texture = addTexture(s, 1, 1, 3, {204, 128, 230});
    m.bumpScale = scale;
    const sdb::MaterialId mat = s.addMaterial(m).id;
    s.addNode({.name = "quad", .meshes = {s.addMesh(uvQuad(mat)).id}});
    sdb::Light sun;
    sun.type = sdb::LightType::kDirectional;
    sun.intensity = 1000.0f;
    s.addNode({.name = "light", .light = s.addLight(sun).id});
    const rdb::RasterRdb r = rdb::buildRasterRdb(s);
    ASSERT_TRUE(r.variants.normalMaps);
    Renderer renderer;
    renderer.upload(r);
    renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
    vec3 n = vec3(204, 128, 230) / 255.0f * 2.0f - 1.0f;
    n.x *= scale;
    n.y *= scale;
    n = glm::normalize(n);
    const float l = 0.5f / kPiF * (1000.0f * n.z + r.ambient.upLux.g);
    expectImageNear(renderer.luminanceRgb(), expectedQuad(64, 32, std::vector<Rgb>(4, Rgb(l)), false), 2e-4f);
  }
}

// Sunlight mode's real-time sun term on a light-mapped, normal-mapped surface (per fragment) bends with the
// normal map as the Phong terms do: L = ρ/π · (E − E_sunDirect) + ρ/π · E_n · max(0, n' · s), n' the texel's
// normal (as in NormalMapsBendTheNormalOfThePhongTerms), s the current sun's direction; E − E_sunDirect is
// interpolated over the quad. Every mesh is light-mapped, so no Phong program is compiled, yet the normal map
// is.
TEST(Renderer, SunlightModesRealTimeSunFollowsTheNormalMapOfALightMappedSurface) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(0.0f);
  m.bumpTexture.texture = addTexture(s, 1, 1, 3, {204, 128, 230});
  const sdb::MaterialId mat = s.addMaterial(m).id;
  const sdb::MeshId meshId = s.addMesh(uvQuad(mat)).id;
  const sdb::NodeId node = s.addNode({.name = "quad", .meshes = {meshId}}).id;
  s.setSky({.model = sdb::SkyModel::kClear, .sun = true});
  s.setTime({.sunDirection = sdb::SunDirection{120.0, 40.0}});  // east-south-east: the bend (towards +X) matters
  const rdb::RasterRdb unbaked = rdb::buildRasterRdb(s);
  const rdb::RasterSky& sky = *unbaked.sky;
  const Rgb normalLux = sky.sunRadianceCdM2 * float(2.0 * kPi * (1.0 - std::cos(double(sky.sunHalfAngleRad))));
  rdb::LightMapStore store;
  store.sun = rdb::BakedSun{sky.sunDirWorld, normalLux};
  rdb::MeshLightMap map{node.value, meshId.value, {}, {}};
  const Rgb sunDirect = normalLux * sky.sunDirWorld.z;  // what the bake held, on the unbent normal +Z
  for (const Rgb& other : kFrontLux) {
    map.frontLux.push_back(other + sunDirect);
    map.frontSunDirectLux.push_back(sunDirect);
  }
  store.meshes.push_back(map);
  const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
  ASSERT_TRUE(r.variants.sunDirect && r.variants.normalMaps);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSunlight, 64, 32);
  const vec3 bent = glm::normalize(vec3(204, 128, 230) / 255.0f * 2.0f - 1.0f);
  const float cosBent = std::max(0.0f, glm::dot(bent, sky.sunDirWorld));
  ASSERT_GT(std::abs(cosBent - sky.sunDirWorld.z), 0.05f);  // the bend matters
  std::vector<Rgb> expected;
  for (const Rgb& other : kFrontLux) expected.push_back(0.5f / kPiF * (other + normalLux * cosBent));
  const std::vector<float> want = expectedQuad(64, 32, expected, false);
  const std::vector<float> got = renderer.luminanceRgb();
  size_t compared = 0, bad = 0;
  for (size_t i = 0; i < want.size(); ++i) {
    if (want[i] <= 0.0f) continue;  // the sky around the quad
    ++compared;
    if (!(std::abs(got[i] - want[i]) <= 2e-4f * want[i]) && ++bad <= 5)
      ADD_FAILURE() << "value " << i << ": " << got[i] << " vs " << want[i];
  }
  EXPECT_EQ(compared, 64u * 32u * 3u / 4u);
  EXPECT_EQ(bad, 0u);
  for (const std::string& p : renderer.stats().programs) {
    if (p.find("perfragment") == std::string::npos) continue;
    EXPECT_NE(p.find("+sundirect"), std::string::npos) << p;
    EXPECT_NE(p.find("+normalmap"), std::string::npos) << p;
    EXPECT_EQ(p.find("+phong"), std::string::npos) << p;
  }
}

// An alpha cut-out: a 4 × 1 texture with alpha 0, 0, 1, 1 and cut-off 0.5 shows the quad where u ∈ [0.5, 1)
// (texel centres 0.625, 0.875: coverage 1) and nothing (the black background) where u ∈ (0.125, 0.375)
// (coverage 0); between them the bilinear alpha crosses the cut-off.
TEST(Renderer, AlphaMaskDiscardsBelowTheCutOff) {
  context();
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  m.diffuseTexture.texture = addTexture(s, 4, 1, 4, {255, 255, 255, 0, 255, 255, 255, 0, 255, 255, 255, 255,
                                                     255, 255, 255, 255});
  m.alphaMode = sdb::AlphaMode::kMask;
  m.alphaCutoff = 0.5f;
  m.emissionLuminance = Rgb(10.0f);
  const sdb::MaterialId mat = s.addMaterial(m).id;
  s.addNode({.name = "quad", .meshes = {s.addMesh(uvQuad(mat)).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_TRUE(r.variants.alphaMask);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
  const std::vector<float> img = renderer.luminanceRgb();
  for (uint32_t j = 9; j < 23; ++j) {  // rows inside the quad (y ∈ (−0.5, 0.5) is rows 8..23)
    for (uint32_t i = 0; i < 64; ++i) {
      const float u = ((-2.0f + 4.0f * (float(i) + 0.5f) / 64.0f) + 1.0f) * 0.5f;
      const float g = img[(size_t(j) * 64 + i) * 3 + 1];
      if (u > 0.13f && u < 0.37f) {
        EXPECT_EQ(g, 0.0f) << "pixel " << i << ", " << j;
      } else if (u > 0.5f && u < 1.0f) {
        // The emission, plus the simple mode's ambient term of the emitted flux (rdb/raster_rdb.h) on the
        // albedo 0.5: both halves of the quad are one vertical face (n_y = 0, no corners).
        const float ambient = 0.5f * (r.ambient.upLux.g + r.ambient.downLux.g);
        EXPECT_NEAR(g, 10.0f + 0.5f / kPiF * ambient, 1e-4f * (10.0f + ambient)) << "pixel " << i << ", " << j;
      }
    }
  }
  EXPECT_NE(std::find(renderer.stats().programs.begin(), renderer.stats().programs.end(),
                      "scene+phong+perfragment+textures+mask"),
            renderer.stats().programs.end());
}

// Glass with textures is shaded per fragment in the glass pass: the pane of ClearGlassShowsWhatLiesBehindIt…
// (no diffuse, white Fresnel reflection at ior 1.5, transmission (0.9, 0.8, 0.7), seen head-on: F = 0.04) over
// the left half of the light-mapped quad, with a 4 × 1 transmission texture (red 1, 1, 0, 0) and a 4 × 1 base
// colour texture whose alpha (1, 0, 1, 1) cuts it out (MASK, cut-off 0.5), both read nearest: its first
// quarter shows the quad times T, its second the quad unchanged (cut out), the rest nothing (t = 0 and no
// diffuse: an opaque black pane).
TEST(Renderer, TexturedGlassTransmitsByItsTextureAndCutsOutByItsAlpha) {
  context();
  QuadScene q = quadScene(false);
  sdb::Material glass = clearGlass();
  glass.transmissionTexture.texture = addTexture(q.scene, 4, 1, 1, {255, 255, 0, 0});
  glass.diffuseTexture.texture =
      addTexture(q.scene, 4, 1, 4, {255, 255, 255, 255, 255, 255, 255, 0, 255, 255, 255, 255, 255, 255, 255, 255});
  for (sdb::TextureRef* t : {&glass.transmissionTexture, &glass.diffuseTexture}) {
    t->magFilter = sdb::MagFilter::kNearest;
    t->minFilter = sdb::MinFilter::kNearest;
  }
  glass.alphaMode = sdb::AlphaMode::kMask;
  glass.alphaCutoff = 0.5f;
  q.scene.addNode({.name = "window", .meshes = {q.scene.addMesh(leftPane(q.scene.addMaterial(glass).id, false)).id}});
  rdb::LightMapStore store;
  store.meshes.push_back({q.node.value, q.mesh.value, kFrontLux, {}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene, &store);
  ASSERT_TRUE(r.variants.glass);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  std::vector<float> expected = expectedQuad(64, 32, luminanceOf(kFrontLux, Rgb(0.5f, 0.6f, 0.7f)), false);
  const Rgb transmittance = Rgb(0.9f, 0.8f, 0.7f) * (1.0f - 0.04f);
  for (uint32_t j = 8; j < 24; ++j) {  // the pane's rows (y ∈ (−0.5, 0.5)); its columns 16–31 (x ∈ (−1, 0))
    for (uint32_t i = 16; i < 32; ++i) {
      for (int k = 0; k < 3; ++k) {
        float& e = expected[(size_t(j) * 64 + i) * 3 + size_t(k)];
        if (i < 20) e *= transmittance[k];  // u < 0.25: clear
        else if (i >= 24) e = 0.0f;         // u > 0.5: opaque, black
      }
    }
  }
  expectImageNear(renderer.luminanceRgb(), expected, 1e-4f);
  const std::vector<std::string>& programs = renderer.stats().programs;
  EXPECT_NE(std::find(programs.begin(), programs.end(), "scene+lightmap+phong+glass+perfragment+textures+mask+diffusebyangle"),
            programs.end())
      << ::testing::PrintToString(programs);
}

// Metalness per texel (light-map mode, seen head-on): a light-mapped quad of diffuse colour d, white Fresnel
// reflection at ior 1.5 (R0' = 0.04) and a 2 × 1 metalness texture (0, 1; nearest) shows its left half as
// the dielectric, (1 − R0') d · E / π, and its right half as a uniform reflector of colour d, which the
// light-map mode shows as a rough one: (0 + d) · E / π. Over the quad's left half, a glass pane (diffuse c,
// transmission t, the same reflection) with a 4 × 1 metalness texture (0, 0, 1, 1): its glass texels pass the
// quad times T = t (1 − R0'), its metal texels are opaque (transmission × (1 − 1) = 0) and, in this mode,
// black (a glass's reflection is not the light-map mode's to show).
TEST(Renderer, MetalnessTextureMixesAMetalOfTheBaseColourPerTexel) {
  context();
  sdb::Scene s;
  const Rgb d(0.5f, 0.6f, 0.7f);
  sdb::Material paint;
  paint.diffuseColor = d;
  paint.reflectionColor = Rgb(1.0f);
  paint.reflectionModel = sdb::ReflectionModel::kFresnel;
  paint.ior = 1.5f;
  paint.reflectionGlossiness = 0.5f;
  paint.metalnessTexture.texture = addTexture(s, 2, 1, 1, {0, 255});
  sdb::Material glass;
  glass.diffuseColor = Rgb(0.9f, 0.8f, 0.7f);
  glass.reflectionColor = Rgb(1.0f);
  glass.reflectionModel = sdb::ReflectionModel::kFresnel;
  glass.ior = 1.5f;
  glass.reflectionGlossiness = 0.0f;
  glass.transmissionColor = Rgb(0.9f, 0.8f, 0.7f);
  glass.transmissionGlossiness = 0.0f;
  glass.metalnessTexture.texture = addTexture(s, 4, 1, 1, {0, 0, 255, 255});
  for (sdb::TextureRef* t : {&paint.metalnessTexture, &glass.metalnessTexture}) {
    t->magFilter = sdb::MagFilter::kNearest;
    t->minFilter = sdb::MinFilter::kNearest;
  }
  const sdb::MeshId quad = s.addMesh(uvQuad(s.addMaterial(paint).id)).id;
  const sdb::NodeId quadNode = s.addNode({.name = "quad", .meshes = {quad}}).id;
  sdb::Mesh pane;
  pane.name = "pane";
  pane.positions = {{-1.0f, -0.5f, 1.0f}, {0.0f, -0.5f, 1.0f}, {0.0f, 0.5f, 1.0f}, {-1.0f, 0.5f, 1.0f}};
  pane.normals.assign(4, vec3(0, 0, 1));
  for (const vec3& p : pane.positions) pane.uv0.push_back(vec2(p.x + 1.0f, 0.5f - p.y));
  pane.indices = {0, 1, 2, 0, 2, 3};
  pane.material = s.addMaterial(glass).id;
  const sdb::MeshId paneId = s.addMesh(pane).id;
  const sdb::NodeId paneNode = s.addNode({.name = "window", .meshes = {paneId}}).id;
  rdb::LightMapStore store;
  store.meshes.push_back({quadNode.value, quad.value, kFrontLux, {}});
  store.meshes.push_back({paneNode.value, paneId.value, std::vector<Rgb>(4, Rgb(0.0f)), {}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s, &store);
  ASSERT_TRUE(r.variants.glass && r.variants.metalnessTextures);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  const float r0 = 0.04f;
  const std::vector<float> dielectric = expectedQuad(64, 32, luminanceOf(kFrontLux, (1.0f - r0) * d), false);
  const std::vector<float> metal = expectedQuad(64, 32, luminanceOf(kFrontLux, d), false);
  const Rgb transmittance = Rgb(0.9f, 0.8f, 0.7f) * (1.0f - r0);
  std::vector<float> expected(dielectric.size(), 0.0f);
  for (uint32_t j = 0; j < 32; ++j) {
    for (uint32_t i = 0; i < 64; ++i) {
      for (int k = 0; k < 3; ++k) {
        const size_t at = (size_t(j) * 64 + i) * 3 + size_t(k);
        expected[at] = i < 32 ? dielectric[at] : metal[at];  // the quad: x ∈ (−1, 0) is u < 0.5
        if (j >= 8 && j < 24 && i >= 16 && i < 32) {        // the pane
          expected[at] = i < 24 ? dielectric[at] * transmittance[k] : 0.0f;
        }
      }
    }
  }
  expectImageNear(renderer.luminanceRgb(), expected, 1e-4f);
  const std::vector<std::string>& programs = renderer.stats().programs;
  EXPECT_TRUE(std::any_of(programs.begin(), programs.end(), [](const std::string& p) {
    return p.find("+glass") != std::string::npos && p.find("+metalnesstexture") != std::string::npos;
  })) << ::testing::PrintToString(programs);
}

// Blended surfaces are drawn back to front over what lies behind them: a wall of luminance L_b (emission, no
// lights) behind two blended quads listed front first, A (1 m in front, emission (100, 0, 0), opacity 0.25)
// and B (0.5 m in front, emission (0, 100, 0), opacity 0.5), show 0.25 A + 0.75 (0.5 B + 0.5 L_b) where all
// three overlap — the order sorted by depth, not the meshes' order.
TEST(Renderer, BlendedSurfacesAreDrawnBackToFrontOverTheRest) {
  context();
  sdb::Scene s;
  auto emitter = [&](const Rgb& cdM2, float opacity, bool blend) {
    sdb::Material m;
    m.diffuseColor = Rgb(0.0f);
    m.emissionLuminance = cdM2;
    m.opacity = opacity;
    m.alphaMode = blend ? sdb::AlphaMode::kBlend : sdb::AlphaMode::kOpaque;
    return s.addMaterial(m).id;
  };
  const Rgb wall(10, 20, 30), a(100, 0, 0), b(0, 100, 0);
  auto place = [](float z) { return frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, z)); };
  s.addNode({.name = "A", .parentFromLocal = place(1.0f), .meshes = {s.addMesh(test::quadXY(emitter(a, 0.25f, true))).id}});
  s.addNode({.name = "B", .parentFromLocal = place(0.5f), .meshes = {s.addMesh(test::quadXY(emitter(b, 0.5f, true))).id}});
  s.addNode({.name = "wall", .meshes = {s.addMesh(test::quadXY(emitter(wall, 1.0f, false))).id}});
  const rdb::RasterRdb r = rdb::buildRasterRdb(s);
  ASSERT_TRUE(r.variants.alphaBlend);
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSimple, 64, 32);
  const Rgb expected = 0.25f * a + 0.75f * (0.5f * b + 0.5f * wall);
  const std::vector<float> img = renderer.luminanceRgb();
  const size_t centre = (size_t(16) * 64 + 32) * 3;
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(img[centre + size_t(c)], expected[c], 1e-4f * 100.0f);
  // From behind, every quad is one-sided and culled: the background (black in simple mode) shows.
  renderer.render(orthoView(true), RenderMode::kSimple, 64, 32);
  const std::vector<float> back = renderer.luminanceRgb();
  for (int c = 0; c < 3; ++c) EXPECT_EQ(back[centre + size_t(c)], 0.0f);
}

// The back of a one-sided surface is culled, as glTF's doubleSided: false says, for the per-vertex and the
// per-fragment draws (simple mode: the scene has no daylight): a one-sided wall (emission L_w, facing +Z) with a two-sided panel
// 0.5 m in front of it (emission L_p on both faces). From the front the panel hides the wall; from behind
// the wall's back is culled and the panel's back shows L_p. The same with the wall's material textured
// (drawn per fragment), and with the wall two-sided its back hides the panel.
TEST(Renderer, TheBackOfAOneSidedSurfaceIsCulledAndWhatLiesBehindShows) {
  context();
  const Rgb wallCdM2(10, 20, 30), panelCdM2(0, 100, 0);
  for (const bool perFragment : {false, true}) {
    for (const bool wallTwoSided : {false, true}) {
      sdb::Scene s;
      sdb::Material wall;
      wall.diffuseColor = Rgb(0.0f);
      wall.emissionLuminance = wallCdM2;
      wall.doubleSided = wallTwoSided;
      if (perFragment) wall.alphaMode = sdb::AlphaMode::kMask;  // a cut-out, wholly covered: drawn per fragment
      sdb::Material panel = wall;
      panel.emissionLuminance = panelCdM2;
      panel.doubleSided = true;
      const sdb::MaterialId wallId = s.addMaterial(wall).id, panelId = s.addMaterial(panel).id;
      sdb::Mesh wallMesh = test::quadXY(wallId), panelMesh = test::quadXY(panelId);
      wallMesh.twoSided = wallTwoSided;
      panelMesh.twoSided = true;
      s.addNode({.name = "wall", .meshes = {s.addMesh(wallMesh).id}});
      s.addNode({.name = "panel",
                 .parentFromLocal = frameTransform(vec3(0.5f, 0, 0), vec3(0, 0.5f, 0), vec3(0, 0, 1), vec3(0, 0, 0.5f)),
                 .meshes = {s.addMesh(panelMesh).id}});
      const rdb::RasterRdb r = rdb::buildRasterRdb(s);
      Renderer renderer;
      renderer.upload(r);
      // Pixel columns 32 (x = 0.03 m: the panel) and 20 (x = −0.72 m: the wall beside it) of row 16.
      const size_t centre = (size_t(16) * 64 + 32) * 3, beside = (size_t(16) * 64 + 20) * 3;
      {
        const RenderMode mode = RenderMode::kSimple;
        renderer.render(orthoView(false), mode, 64, 32);
        const std::vector<float> front = renderer.luminanceRgb();
        renderer.render(orthoView(true), mode, 64, 32);
        const std::vector<float> back = renderer.luminanceRgb();
        for (int c = 0; c < 3; ++c) {
          const std::string what = std::string(perFragment ? "per fragment" : "per vertex") +
                                   (wallTwoSided ? ", two-sided wall" : ", one-sided wall");
          EXPECT_NEAR(front[centre + size_t(c)], panelCdM2[c], 1e-3f * 100.0f) << what;
          EXPECT_NEAR(front[beside + size_t(c)], wallCdM2[c], 1e-3f * 100.0f) << what;
          EXPECT_NEAR(back[centre + size_t(c)], wallTwoSided ? wallCdM2[c] : panelCdM2[c], 1e-3f * 100.0f) << what;
        }
      }
    }
  }
}

TEST(Renderer, ExposureOrOperatorChangesReRunOnlyTheToneMapPass) {
  context();
  const rdb::RasterRdb r = lightMappedQuad();
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  const std::vector<float> lum = renderer.luminanceRgb();
  const std::vector<ToneMapSettings> settings = {{ToneOperator::kLinear, 4.0},
                                                 {ToneOperator::kLinear, 6.0},
                                                 {ToneOperator::kReinhard, 4.0, 2.0f},
                                                 {ToneOperator::kFilmic, 5.0}};
  std::vector<std::vector<uint8_t>> images;
  for (const ToneMapSettings& t : settings) {
    renderer.toneMap(t);
    images.push_back(renderer.srgb8());
    // The GPU pass computes what the CPU functions compute, to 8-bit rounding.
    int worst = 0;
    for (size_t i = 0; i < lum.size(); i += 3) {
      const Rgb display = fly::toneMap(Rgb(lum[i], lum[i + 1], lum[i + 2]), t);
      for (int c = 0; c < 3; ++c)
        worst = std::max(worst, std::abs(int(images.back()[i + size_t(c)]) - int(encodeSrgb8(display[c]))));
    }
    EXPECT_LE(worst, 1) << "operator " << int(t.op) << " EV100 " << t.ev100;
  }
  EXPECT_EQ(renderer.stats().scenePasses, 1);
  EXPECT_EQ(renderer.stats().toneMapPasses, 4);
  EXPECT_EQ(renderer.stats().geometryUploads, 1);
  EXPECT_NE(images[0], images[1]);
  EXPECT_NE(images[0], images[2]);
  EXPECT_NE(images[0], images[3]);
}

TEST(Renderer, CompilesOnlyTheVariantsTheSceneNeeds) {
  context();
  QuadScene q = quadScene(false);
  const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene);
  EXPECT_FALSE(r.variants.sky);
  EXPECT_FALSE(r.variants.lightMap);
  EXPECT_EQ(supportedModes(r), std::vector<RenderMode>{RenderMode::kSimple});
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kSimple, 32, 16);
  EXPECT_THROW(renderer.render(orthoView(false), RenderMode::kSunlight, 32, 16), std::invalid_argument);
  EXPECT_THROW(renderer.render(orthoView(false), RenderMode::kLightMap, 32, 16), std::invalid_argument);
  renderer.toneMap({ToneOperator::kReinhard, 0.0});
  EXPECT_EQ(renderer.stats().programs, (std::vector<std::string>{"background", "scene+phong", "tonemap"}));
}

TEST(Renderer, RejectsBadImageSizes) {
  context();
  QuadScene q = quadScene(false);
  const rdb::RasterRdb r = rdb::buildRasterRdb(q.scene);
  Renderer renderer;
  renderer.upload(r);
  EXPECT_THROW(renderer.render(orthoView(false), RenderMode::kSimple, 0, 16), std::invalid_argument);
  EXPECT_THROW(renderer.render(orthoView(false), RenderMode::kSimple, 16, 20000), std::invalid_argument);
}

}  // namespace
}  // namespace fly::raster

namespace fly::raster {
namespace {

// The window twin of the headless path: CTest runs this under xvfb-run (tests/CMakeLists.txt,
// raster.glfw_window); without an X display it has nothing to open.
TEST(GlfwWindow, OpensA45CoreContextAndRendersLikeHeadless) {
  if (!std::getenv("DISPLAY"))
    GTEST_SKIP() << "no X display; CTest's raster.glfw_window runs this under xvfb-run";
  GlfwWindowContext window(64, 32, "fly test");
  EXPECT_EQ(window.info().platform, "glfw");
  EXPECT_TRUE(window.info().major > 4 || (window.info().major == 4 && window.info().minor >= 5));
  const rdb::RasterRdb r = lightMappedQuad();
  Renderer renderer;
  renderer.upload(r);
  renderer.render(orthoView(false), RenderMode::kLightMap, 64, 32);
  expectImageNear(renderer.luminanceRgb(),
                  expectedQuad(64, 32, luminanceOf(kFrontLux, Rgb(0.5f, 0.6f, 0.7f)), false), 1e-4f);
  window.swapBuffers();
  window.pollEvents();
}

}  // namespace
}  // namespace fly::raster
