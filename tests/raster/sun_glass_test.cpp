// The sun through clear glass (raster/sun_glass.h): a horizontal pane over a floor, the sun at 40° elevation.
// With the ambient term off, the floor shows only the sun's direct term; where the sun reaches it through the
// pane, that term is T(θ) times the unshaded floor's (the same scene without the pane), T computed here from
// the material's inputs (rdb::RasterMaterial) by base/clear_pane.h, elsewhere it is unchanged, and a
// plate above the pane (between it and the sun) is unattenuated. The floor is drawn three ways: shaded per
// vertex and per fragment in simple mode, and in sunlight mode over a light map that keeps the sun's direct
// part apart (E − E_sunDirect = 0: the floor shows the real-time sun term alone; docs/mixed-lighting.md).
#include "raster/sun_glass.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "../support/helsinki_daylight.h"
#include "base/clear_pane.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/light_map_store.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

constexpr double kElevationRad = 40.0 * kPi / 180.0;
constexpr float kPaneHeightM = 1.0f;  // the pane: y = 1, x and z in [−1, 1]
constexpr float kPlateLo = 0.5f, kPlateHi = 0.8f, kPlateBottomM = 1.4f, kPlateTopM = 1.45f;  // x and z
const Rgb kTransmission(0.9f, 0.7f, 0.5f);

View lookAt(const vec3& eye, const vec3& target) { return test::lookAtView(eye, target, 100.0f); }

enum class Floor { kPerVertex, kPerFragment, kBakedSunDirect };

RenderMode modeOf(Floor f) {
  return f == Floor::kBakedSunDirect ? RenderMode::kSunlight : RenderMode::kSimple;
}

// A 10 m floor (COLOR_0 on it for kPerFragment: it is then shaded per fragment; a light map that is all sun
// for kBakedSunDirect), the pane when `withPane`, a small plate above the pane; the sun at kElevationRad
// towards +Z, no ambient light.
rdb::RasterRdb scene(bool withPane, Floor shading) {
  sdb::Scene s;
  sdb::Material paint;
  paint.diffuseColor = Rgb(0.5f);
  const sdb::MaterialId mat = s.addMaterial(paint).id;
  sdb::Mesh floor;
  floor.name = "floor";
  floor.positions = {{-5, 0, -5}, {5, 0, -5}, {5, 0, 5}, {-5, 0, 5}};
  floor.normals.assign(4, vec3(0, 1, 0));
  floor.indices = {0, 2, 1, 0, 3, 2};
  floor.material = mat;
  if (shading == Floor::kPerFragment) floor.colors.assign(4, vec4(1.0f));
  const sdb::MeshId floorMesh = s.addMesh(floor).id;
  const sdb::NodeId floorNode = s.addNode({.name = "floor", .meshes = {floorMesh}}).id;
  s.addNode({.name = "plate",
             .meshes = {s.addMesh(test::box(vec3(kPlateLo, kPlateBottomM, kPlateLo),
                                            vec3(kPlateHi, kPlateTopM, kPlateHi), mat))
                            .id}});
  if (withPane) {
    sdb::Material glass;
    glass.diffuseColor = Rgb(0.0f);
    glass.reflectionColor = Rgb(1.0f);
    glass.transmissionColor = kTransmission;
    glass.transmissionGlossiness = 0.0f;
    sdb::Mesh pane = test::quadXY(s.addMaterial(glass).id);  // 2 × 1 m: scaled to 2 × 2 m, turned to face +Y
    s.addNode({.name = "pane",
               .parentFromLocal = glm::translate(mat4(1.0f), vec3(0.0f, kPaneHeightM, 0.0f)) *
                                  glm::rotate(mat4(1.0f), float(-kPi / 2.0), vec3(1, 0, 0)) *
                                  glm::scale(mat4(1.0f), vec3(1.0f, 2.0f, 1.0f)),
               .meshes = {s.addMesh(pane).id}});
  }
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  rdb::LightMapStore store;
  if (shading == Floor::kBakedSunDirect) {
    // What a bake at another sun kept: E = E_sunDirect, so that only the real-time sun term shows.
    const Rgb bakedLux(40000.0f);
    store.sun = rdb::BakedSun{glm::normalize(vec3(0.2f, 0.9f, 0.3f)), Rgb(100000.0f)};
    store.meshes.push_back({floorNode.value,
                            floorMesh.value,
                            std::vector<Rgb>(4, bakedLux),
                            {},
                            {},
                            std::vector<Rgb>(4, bakedLux),
                            {}});
  }
  rdb::RasterRdb r = rdb::buildRasterRdb(s, shading == Floor::kBakedSunDirect ? &store : nullptr, {32, 16});
  EXPECT_EQ(r.variants.sunDirect, shading == Floor::kBakedSunDirect);
  EXPECT_TRUE(r.variants.sun);
  EXPECT_EQ(r.variants.glass, withPane);
  EXPECT_TRUE(r.lights.empty());
  r.sky->sunDirWorld = vec3(0.0f, float(std::sin(kElevationRad)), float(std::cos(kElevationRad)));
  r.ambient = {};
  return r;
}

std::vector<float> render(const rdb::RasterRdb& r, RenderMode mode, const View& view, uint32_t w, uint32_t h,
                          RendererStats* stats = nullptr) {
  Renderer renderer;
  renderer.upload(r);
  renderer.render(view, mode, w, h);
  if (stats) *stats = renderer.stats();
  return renderer.luminanceRgb();
}

// Where the pixel's ray from `view` meets the plane y = `planeY` (nullopt-like: w = 0 when it does not).
vec4 hitPlane(const View& view, uint32_t i, uint32_t j, uint32_t w, uint32_t h, float planeY) {
  const dvec3 eye(view.worldFromCamera[3]);
  const glm::dmat3 rot(view.worldFromCamera);
  const double tanY = std::tan(0.5 * double(view.yfovRad)), aspect = double(w) / double(h);
  const double x = (2.0 * (i + 0.5) / w - 1.0) * tanY * aspect, y = (1.0 - 2.0 * (j + 0.5) / h) * tanY;
  const dvec3 d = glm::normalize(rot * dvec3(x, y, -1.0));
  const double t = (double(planeY) - eye.y) / d.y;
  if (!(t > 0.0)) return vec4(0.0f);
  return vec4(vec3(eye + t * d), 1.0f);
}

bool inside(float x, float z, float lo, float hi, float margin) {
  return x > lo + margin && x < hi - margin && z > lo + margin && z < hi - margin;
}
bool near(float x, float z, float lo, float hi, float margin) {
  return x > lo - margin && x < hi + margin && z > lo - margin && z < hi + margin;
}

TEST(SunGlass, FloorUnderAPaneGetsTheSunTimesTAndNothingElseChanges) {
  context();
  const double cosTheta = std::sin(kElevationRad);  // the sun against the pane's normal (+Y)
  for (const Floor shading : {Floor::kPerVertex, Floor::kPerFragment, Floor::kBakedSunDirect}) {
    SCOPED_TRACE(shading == Floor::kPerVertex     ? "floor shaded per vertex"
                 : shading == Floor::kPerFragment ? "floor shaded per fragment"
                                                  : "floor light-mapped, sunlight mode");
    const RenderMode mode = modeOf(shading);
    const rdb::RasterRdb withPane = scene(true, shading), open = scene(false, shading);
    // T(θ) from the material's inputs: the pane of two Fresnel faces of ior 1.5 (F0 = 0.04).
    const rdb::RasterMaterial& glass = withPane.materials.back();
    ASSERT_GT(maxComponent(glass.transmission), 0.0f);
    const double f0 = std::pow((1.5 - 1.0) / (1.5 + 1.0), 2.0);
    ASSERT_NEAR(glass.fresnelF0, f0, 1e-6);
    const dvec3 expectedT =
        dvec3(ClearPane(glass.fresnelF0, glass.transmission, glass.reflection).at(float(cosTheta)));

    // The floor, seen from below the pane (no view ray crosses it).
    const uint32_t w = 160, h = 90;
    const View low = lookAt(vec3(0.0f, 0.9f, 1.2f), vec3(0.0f, 0.0f, -1.2f));
    RendererStats stats;
    const std::vector<float> lit = render(withPane, mode, low, w, h, &stats);
    const std::vector<float> unshaded = render(open, mode, low, w, h);
    EXPECT_EQ(stats.sunGlassUploads, 1);
    EXPECT_EQ(stats.sunGlassBuilds, 1);
    // The unshaded floor itself: albedo / π · E_sun · cos θ (no specular lobe, no ambient light).
    const rdb::RasterSky& sky = *open.sky;
    const double sunLux =
        double(luminance(sky.sunRadianceCdM2)) * 2.0 * kPi * (1.0 - std::cos(double(sky.sunHalfAngleRad)));
    const double floorCdM2 = 0.5 / kPi * sunLux * cosTheta;
    const float margin = 0.05f;  // m, beside the pane's and the plate's edges (texels: < 4 mm)
    size_t under = 0, outside = 0;
    for (uint32_t j = 0; j < h; ++j) {
      for (uint32_t i = 0; i < w; ++i) {
        const vec4 q = hitPlane(low, i, j, w, h, 0.0f);
        if (q.w == 0.0f || std::abs(q.x) > 4.9f || std::abs(q.z) > 4.9f) continue;
        // Where the sun's ray from q crosses the pane's plane and the plate.
        const auto along = [&](float y) {
          const float s = y / float(std::sin(kElevationRad));
          return vec2(q.x, q.z + s * float(std::cos(kElevationRad)));
        };
        const vec2 onPane = along(kPaneHeightM), onPlate = along(kPlateBottomM), onTop = along(kPlateTopM);
        if (near(onPlate.x, onPlate.y, kPlateLo, kPlateHi, margin) ||
            near(onTop.x, onTop.y, kPlateLo, kPlateHi, margin)) {
          continue;  // the plate's shadow
        }
        const size_t p = size_t(j) * w + i;
        const Rgb open3(unshaded[3 * p], unshaded[3 * p + 1], unshaded[3 * p + 2]);
        EXPECT_NEAR(luminance(open3), floorCdM2, 1e-3 * floorCdM2) << i << "," << j;
        const bool isUnder = inside(onPane.x, onPane.y, -1.0f, 1.0f, margin);
        if (!isUnder && near(onPane.x, onPane.y, -1.0f, 1.0f, margin)) continue;  // the patch's rim
        (isUnder ? under : outside) += 1;
        for (int c = 0; c < 3; ++c) {
          const double expected = double(unshaded[3 * p + c]) * (isUnder ? expectedT[c] : 1.0);
          ASSERT_NEAR(lit[3 * p + c], expected, 1e-3 * expected)
              << "pixel " << i << "," << j << " channel " << c << (isUnder ? " under" : " beside")
              << " the pane";
        }
      }
    }
    EXPECT_GT(under, 1000u);
    EXPECT_GT(outside, 1000u);

    // The plate's top, above the pane and between it and the sun: unattenuated.
    const View high = lookAt(vec3(0.65f, 3.0f, 1.2f), vec3(0.65f, kPlateTopM, 0.65f));
    const std::vector<float> top = render(withPane, mode, high, w, h),
                             topOpen = render(open, mode, high, w, h);
    size_t plate = 0;
    for (uint32_t j = 0; j < h; ++j) {
      for (uint32_t i = 0; i < w; ++i) {
        const vec4 q = hitPlane(high, i, j, w, h, kPlateTopM);
        if (q.w == 0.0f || !inside(q.x, q.z, kPlateLo, kPlateHi, 0.01f)) continue;
        const size_t p = size_t(j) * w + i;
        for (int c = 0; c < 3; ++c)
          ASSERT_NEAR(top[3 * p + c], topOpen[3 * p + c], 1e-3 * topOpen[3 * p + c]);
        ++plate;
      }
    }
    EXPECT_GT(plate, 200u);
    std::printf("floor pixels: %zu under the pane, %zu beside it; plate pixels: %zu\n", under, outside,
                plate);
  }
}

// Built once per sun direction; a scene without glass makes no map and compiles nothing for it.
TEST(SunGlass, BuiltOnlyForGlassAndWhenTheSunMoves) {
  context();
  rdb::RasterRdb r = scene(true, Floor::kPerVertex);
  const View low = lookAt(vec3(0.0f, 0.9f, 1.2f), vec3(0.0f, 0.0f, -1.2f));
  Renderer renderer;
  renderer.upload(r);
  renderer.render(low, RenderMode::kSimple, 32, 18);
  renderer.render(low, RenderMode::kSunlight, 32, 18);
  EXPECT_EQ(renderer.stats().sunGlassBuilds, 1);
  // The map is fitted to the pane's projection: 2 m along X (perpendicular to the sun), 2 m · sin 40° along
  // the other (the pane's Z seen from the sun), the larger plus 0.1 % over 1024 texels.
  const SunGlassCounts counts = renderer.sunGlassCounts();
  EXPECT_EQ(counts.glassTriangles, 2u);
  EXPECT_EQ(counts.texels, 1024u);
  EXPECT_NEAR(counts.texelSizeM, 2.0 * 1.001 / 1024.0, 1e-7);
  r.sky->sunDirWorld = glm::normalize(vec3(0.1f, 0.7f, 0.7f));
  renderer.render(low, RenderMode::kSimple, 32, 18);
  EXPECT_EQ(renderer.stats().sunGlassBuilds, 2);
  EXPECT_EQ(renderer.stats().sunGlassUploads, 1);
  renderer.setSunShadows({.transmittanceMapTexels = 256});
  renderer.render(low, RenderMode::kSimple, 32, 18);
  EXPECT_EQ(renderer.stats().sunGlassBuilds, 3);
  EXPECT_EQ(renderer.sunGlassCounts().texels, 256u);
  EXPECT_THROW(renderer.setSunShadows({.transmittanceMapTexels = 8}), std::invalid_argument);
  bool compiled = false;
  for (const std::string& p : renderer.stats().programs) compiled |= p == "sun-glass";
  EXPECT_TRUE(compiled);

  const rdb::RasterRdb open = scene(false, Floor::kPerFragment);
  Renderer plain;
  plain.upload(open);
  plain.render(low, RenderMode::kSimple, 32, 18);
  plain.render(low, RenderMode::kSunlight, 32, 18);
  EXPECT_EQ(plain.stats().sunGlassUploads, 0);
  EXPECT_EQ(plain.stats().sunGlassBuilds, 0);
  EXPECT_EQ(plain.sunGlassCounts().glassTriangles, 0u);
  EXPECT_GT(plain.stats().shadowBuilds, 0);
  for (const std::string& p : plain.stats().programs) {
    EXPECT_EQ(p.find("sun-glass"), std::string::npos) << p;
    EXPECT_EQ(p.find("sunglass"), std::string::npos) << p;
  }
}

}  // namespace
}  // namespace fly::raster
