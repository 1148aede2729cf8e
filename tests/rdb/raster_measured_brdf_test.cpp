// Measured BRDFs lowered for the GL engine (rdb/raster_measured_brdf.h): the plain data the ball textures
// evaluate, the albedo table against independent quadratures, and how the RasterRdb carries and updates them.
#include "rdb/raster_measured_brdf.h"

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "rdb/raster_rdb.h"
#include "sdb/material.h"
#include "sdb/scene.h"
#include "test_meshes.h"

namespace fly::rdb {
namespace {

sdb::CarPaintBrdf paint() {
  sdb::CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.35f, 0.05f, 0.04f);
  p.lobes[0] = {Rgb(0.4f, 0.3f, 0.2f), 0.25f};
  p.lobes[1] = {Rgb(0.05f, 0.05f, 0.1f), 0.6f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.1f;
  return p;
}

// ρ(θo) by the midpoint rule on a cosine-weighted grid of directions (sin θi = √u, φ = 2πv): a quadrature
// independent of the half-vector one under test, fine enough for a coat of GGX α 0.1.
Rgb cosineGridAlbedo(const sdb::CarPaintBrdf& p, float cosThetaOut) {
  const vec3 wo(std::sqrt(1.0f - cosThetaOut * cosThetaOut), 0.0f, cosThetaOut);
  constexpr int kN = 600, kM = 2400;
  dvec3 sum(0.0);
  for (int a = 0; a < kN; ++a) {
    const double u = (a + 0.5) / kN, s = std::sqrt(u), c = std::sqrt(1.0 - u);
    for (int b = 0; b < kM; ++b) {
      const double phi = 2.0 * kPi * (b + 0.5) / kM;
      sum += dvec3(p.evalPerSr(vec3(float(s * std::cos(phi)), float(s * std::sin(phi)), float(c)), wo));
    }
  }
  return Rgb(sum * (kPi / (double(kN) * kM)));
}

TEST(RasterMeasuredBrdf, CarPaintParametersAndAlbedo) {
  sdb::Material m;
  m.carPaint = paint();
  const RasterMeasuredBrdf r = lowerMeasuredBrdf(m, 7);
  EXPECT_EQ(r.kind, RasterBrdfKind::kCarPaint);
  EXPECT_TRUE(r.tableRgba.empty());
  EXPECT_EQ(r.sdbMaterialId, 7u);
  EXPECT_EQ(r.carPaint.baseAlbedo, m.carPaint->baseAlbedo);
  EXPECT_EQ(r.carPaint.lobeF0[0], m.carPaint->lobes[0].f0);
  EXPECT_EQ(r.carPaint.lobeAlpha[1], m.carPaint->lobes[1].alpha);
  EXPECT_EQ(r.carPaint.coatAlpha, 0.1f);
  EXPECT_NEAR(r.carPaint.internalDiffuseReflectance, 0.596f, 0.001f);  // η = 1.5 (sdb/car_paint_brdf.h)
  ASSERT_EQ(r.albedo.size(), kRasterAlbedoSteps);
  for (uint32_t k : {0u, 8u, 20u, 31u}) {
    const float cosThetaOut = (float(k) + 0.5f) / float(kRasterAlbedoSteps);
    const Rgb want = cosineGridAlbedo(*m.carPaint, cosThetaOut);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(r.albedo[k][c], want[c], 0.01f * want[c] + 1e-4f) << "k " << k << " channel " << c;
      EXPECT_LE(r.albedo[k][c], 1.0f);
    }
  }
}

// A Lambertian table (ρ/π everywhere measured): ρ(θo) = ρ at every angle.
TEST(RasterMeasuredBrdf, TableSamplesValidityAndLambertianAlbedo) {
  const Rgb rho(0.2f, 0.5f, 0.8f);
  std::vector<Rgb> samples(sdb::MeasuredBrdf::kSamples, rho / kPiF);
  sdb::Material m;
  m.measuredBrdf = std::make_shared<const sdb::MeasuredBrdf>(std::move(samples));
  const RasterMeasuredBrdf r = lowerMeasuredBrdf(m, 3);
  EXPECT_EQ(r.kind, RasterBrdfKind::kTable);
  ASSERT_EQ(r.tableRgba.size(), 4 * sdb::MeasuredBrdf::kSamples);
  const std::vector<uint8_t>& valid = sdb::MeasuredBrdf::validSamples();
  size_t measured = 0;
  for (size_t s = 0; s < sdb::MeasuredBrdf::kSamples; ++s) {
    ASSERT_EQ(r.tableRgba[4 * s + 3], valid[s] ? 1.0f : 0.0f) << s;
    measured += valid[s];
  }
  EXPECT_GT(measured, sdb::MeasuredBrdf::kSamples / 2);
  EXPECT_LT(measured, sdb::MeasuredBrdf::kSamples);
  EXPECT_EQ(r.tableRgba[4 * 1234 + 1], rho.g / kPiF);
  for (uint32_t k = 0; k < kRasterAlbedoSteps; ++k) {
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(r.albedo[k][c], rho[c], 0.005f * rho[c]) << "k " << k;
  }
}

// A sphere of a measured material and a quad of a plain one: the block points at its BRDF, the BRDF knows its
// objects' bounds, the mesh is drawn per fragment, the variant is on; edits and assignments equal a rebuild.
TEST(RasterMeasuredBrdf, CarriedByTheRasterRdbAndUpdatedAsARebuild) {
  sdb::Scene s;
  sdb::Material plain;
  plain.name = "plain";
  const sdb::MaterialId plainId = s.addMaterial(plain).id;
  sdb::Material car;
  car.name = "car";
  car.carPaint = paint();
  const sdb::MaterialId carId = s.addMaterial(car).id;
  const sdb::MeshId quadMesh = s.addMesh(test::quadXZ(plainId)).id;
  s.addNode({.name = "quad", .meshes = {quadMesh}});
  sdb::Mesh box = test::quadXZ(carId);
  s.addNode({.name = "car", .parentFromLocal = glm::translate(mat4(1.0f), vec3(3.0f, 1.0f, 0.0f)),
             .meshes = {s.addMesh(box).id}});
  RasterRdb r = buildRasterRdb(s);
  ASSERT_EQ(r.measuredBrdfs.size(), 1u);
  EXPECT_TRUE(r.variants.measuredBrdf);
  const RasterMesh& carMesh = r.meshes.at(1);
  const RasterMaterial& block = r.materials.at(carMesh.material);
  EXPECT_EQ(block.measured, 0u);
  EXPECT_EQ(block.diffuse, glm::clamp(r.measuredBrdfs[0].albedo.back(), Rgb(0.0f), Rgb(1.0f)));
  EXPECT_TRUE(r.shadedPerFragment(carMesh));
  EXPECT_FALSE(r.shadedPerFragment(r.meshes.at(0)));
  EXPECT_EQ(r.materials.at(r.meshes.at(0).material).measured, RasterTextureRef::kNone);
  Bounds3 b;
  for (uint32_t v = carMesh.firstVertex; v < carMesh.firstVertex + carMesh.vertexCount; ++v) b.extend(r.positionsM[v]);
  EXPECT_EQ(r.measuredBrdfs[0].centreM, 0.5f * (b.min + b.max));
  EXPECT_NEAR(r.measuredBrdfs[0].radiusM, 0.5f * glm::length(b.size()), 1e-6f);

  // The paint edited: its BRDF and block re-made, as a rebuild.
  car.carPaint->coatAlpha = 0.3f;
  RasterRdbChanges ch = updateRasterRdb(r, s, s.setMaterial(carId, car));
  EXPECT_TRUE(ch.materials || ch.geometry);
  EXPECT_EQ(r.measuredBrdfs.at(0).carPaint.coatAlpha, 0.3f);
  EXPECT_TRUE(r == buildRasterRdb(s));
  // The plain quad given the paint: one BRDF, its bounds now both meshes'.
  ch = updateRasterRdb(r, s, s.setMeshMaterial(quadMesh, carId));
  EXPECT_TRUE(ch.materials || ch.geometry);
  EXPECT_TRUE(r == buildRasterRdb(s));
  EXPECT_EQ(r.measuredBrdfs.size(), 1u);
  // The paint made plain: no BRDF, no variant.
  car.carPaint.reset();
  updateRasterRdb(r, s, s.setMaterial(carId, car));
  EXPECT_TRUE(r.measuredBrdfs.empty());
  EXPECT_FALSE(r.variants.measuredBrdf);
  EXPECT_TRUE(r == buildRasterRdb(s));
}

}  // namespace
}  // namespace fly::rdb
