// Reflection fog in both engines (docs/materials-engine.md): a fogged mirror (uniform reflection r, fog colour
// c) under a sky of uniform radiance L and no sun reflects only the sky, which lies at infinity (t = 1), so it
// shows the fog alone: the luminance of a matte surface of reflectance r c lit by E = π L, i.e. r c L.
// GL engine: a 2 m × 1 m mirror pane (a planar reflector) in sunlight mode, the sky its image-based light,
// seen through an orthographic camera head-on and at 60°. Baker: the irradiance E_s of a sensor facing a
// 10 km floor of the same material (rdb::lowerMaterial), which it sees at the radiance E_s / π from every
// direction. The two agree within 1 % plus 4 of the baker's standard errors; the closed form r c L is printed
// beside them.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <vector>

#include "../raster/raster_test_scenes.h"
#include "raster/renderer.h"
#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "rdb/raster_rdb.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/camera.h"
#include "sdb/material.h"
#include "sdb/scene.h"

namespace fly {
namespace {

constexpr float kSkyCdM2 = 1000.0f;
constexpr uint32_t kPx = 8;

sdb::Material foggedMirror() {
  sdb::Material m;
  m.name = "fogged mirror";
  m.diffuseColor = Rgb(0.0f);
  m.reflectionColor = Rgb(0.8f);
  m.reflectionModel = sdb::ReflectionModel::kUniform;
  m.reflectionGlossiness = 0.0f;
  m.reflectionFogDistanceM = 5.0f;
  m.reflectionFogColor = Rgb(0.2f, 0.5f, 0.8f);
  return m;
}

// The mirror's luminance (cd/m², the mean of its pixels) seen at θ (degrees) from its normal.
Rgb engineLuminance(float thetaDeg) {
  sdb::Scene scene;
  const sdb::MaterialId id = scene.addMaterial(foggedMirror()).id;
  scene.addNode({.name = "mirror", .meshes = {scene.addMesh(raster::test::quadXY(id)).id}});
  rdb::RasterRdb r = rdb::buildRasterRdb(scene);
  EXPECT_EQ(r.planarReflectors.size(), 1u);
  EXPECT_TRUE(r.variants.reflectionFog);
  rdb::RasterSky sky;
  sky.width = 64;
  sky.height = 32;
  sky.radianceCdM2.assign(size_t(sky.width) * sky.height, Rgb(kSkyCdM2));
  r.sky = sky;
  r.variants.sky = true;
  raster::Renderer renderer;
  renderer.upload(r);
  const float theta = glm::radians(thetaDeg);
  raster::View view;
  view.worldFromCamera = sdb::lookAtTransform(3.0f * vec3(0.0f, std::sin(theta), std::cos(theta)), vec3(0.0f),
                                              vec3(0, 1, 0));
  view.orthographic = true;
  view.xmagM = view.ymagM = 0.04f;
  view.znearM = 0.1f;
  view.zfarM = 10.0f;
  renderer.render(view, raster::RenderMode::kSunlight, kPx, kPx);
  EXPECT_EQ(renderer.stats().reflectionPasses, 1);
  const std::vector<float> image = renderer.luminanceRgb();
  dvec3 sum(0.0);
  for (size_t p = 0; p < size_t(kPx) * kPx; ++p) sum += dvec3(image[3 * p], image[3 * p + 1], image[3 * p + 2]);
  return Rgb(sum / double(kPx * kPx));
}

TEST(ReflectionFog, EngineAndBakerAgreeOnAFoggedMirrorUnderTheSky) {
  raster::test::context();
  rdb::TraceRdb t;
  t.materials.push_back(rdb::lowerMaterial(foggedMirror(), 0));
  const float half = 5000.0f;
  t.positionsM = {{-half, 0, -half}, {-half, 0, half}, {half, 0, half}, {half, 0, -half}};
  t.normals.assign(4, vec3(0, 1, 0));
  t.indices = {0, 1, 2, 0, 2, 3};
  t.triangleMaterial = {0, 0};
  t.sky.resolution = 16;
  t.sky.radianceCdM2.assign(16 * 16, Rgb(kSkyCdM2));
  const raytracer::EmbreeScene scene(t);
  const raytracer::Integrator integrator(t, scene);
  raytracer::EstimateSettings settings;
  settings.maxSamples = 1024;
  settings.firstPassSamples = 64;
  settings.replicates = 64;
  const std::vector<vec3> points = {vec3(0.0f, 1.0f, 0.0f)};
  const std::vector<vec3> normals = {vec3(0.0f, -1.0f, 0.0f)};
  const raytracer::IrradianceEstimate e = raytracer::estimateIrradiance(integrator, points, normals, settings).points[0];
  const Rgb bakerCdM2 = e.meanLux / float(kPi);
  const Rgb bakerErrorCdM2 = e.stdErrorLux / float(kPi);
  const sdb::Material m = foggedMirror();
  const Rgb closedForm = m.reflectionColor * m.reflectionFogColor * kSkyCdM2;
  for (const float thetaDeg : {0.0f, 60.0f}) {
    const Rgb engine = engineLuminance(thetaDeg);
    std::printf("fogged mirror under the sky, θ %2.0f°: engine (%.2f %.2f %.2f), baker (%.2f %.2f %.2f) ± %.2f, "
                "r c L (%.2f %.2f %.2f) cd/m²\n",
                thetaDeg, engine.r, engine.g, engine.b, bakerCdM2.r, bakerCdM2.g, bakerCdM2.b,
                maxComponent(bakerErrorCdM2), closedForm.r, closedForm.g, closedForm.b);
    for (int c = 0; c < 3; ++c) {
      EXPECT_LE(std::abs(engine[c] - bakerCdM2[c]), 0.01f * bakerCdM2[c] + 4.0f * bakerErrorCdM2[c])
          << "θ " << thetaDeg << "° channel " << c;
      EXPECT_LE(bakerErrorCdM2[c], 0.01f * closedForm[c]) << "channel " << c;
    }
  }
}

}  // namespace
}  // namespace fly
