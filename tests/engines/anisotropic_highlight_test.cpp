// The shape of an anisotropic highlight in the GL engine's image. A 4 m × 4 m plate (normal +Z, no UVs: its
// tangent is n × x̂ = +Y, rdb::RasterRdb::tangents) under a point lamp 1 m above its centre, seen straight down
// through an orthographic camera (256 px over 2 m, simple mode, no ambient term). Where the half vector leans
// by tan θh ≈ r / 2 m from the normal, the GGX lobe falls to half its peak at tan θh ≈ 0.64 α, so the
// highlight's half-maximum width along each axis of the plate is proportional to the lobe's α on that axis:
// the brushed-metal preset (U 0.6, V 0.1: α_t / α_b = 1 / (1 − 0.9 · 0.5) = 1.82, base/ggx.h) shows a highlight
// 1.82 times as wide along the tangent (+Y) as across it (X), to first order in the slope. The exact widths
// come from the closed form of tests/engines/anisotropic_ggx_reference.h over the same pixel centres, with
// the lamp's 1 / d² and cos θi: the image's widths must match them within 2 % (a pixel of 7.8 mm is 3–6 % of
// a half-width; the crossings are interpolated between pixels), and turning the anisotropy by 90° swaps them.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <vector>

#include "../raster/raster_test_scenes.h"
#include "anisotropic_ggx_reference.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "sdb/light.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"

namespace fly {
namespace {

constexpr uint32_t kPx = 256;
constexpr float kHalfExtentM = 1.0f;  // the view spans [−1, 1] m on both axes
constexpr float kLampHeightM = 1.0f;
constexpr float kLampCd = 1000.0f;

// The world coordinate (m) of pixel column or row i's centre.
double pixelCentreM(uint32_t i) { return -kHalfExtentM + (double(i) + 0.5) * 2.0 * kHalfExtentM / kPx; }

// The full width (pixels) at half maximum of `profile` about its largest value, each side's crossing
// interpolated linearly between the pixels that straddle it; NaN where it never falls to half.
double halfMaximumWidthPx(const std::vector<double>& profile) {
  size_t peak = 0;
  for (size_t i = 1; i < profile.size(); ++i)
    if (profile[i] > profile[peak]) peak = i;
  const double half = 0.5 * profile[peak];
  double lo = std::nan(""), hi = std::nan("");
  for (size_t i = peak; i + 1 < profile.size(); ++i) {
    if (profile[i + 1] <= half) {
      hi = double(i) + (profile[i] - half) / (profile[i] - profile[i + 1]);
      break;
    }
  }
  for (size_t i = peak; i > 0; --i) {
    if (profile[i - 1] <= half) {
      lo = double(i) - (profile[i] - half) / (profile[i] - profile[i - 1]);
      break;
    }
  }
  return hi - lo;
}

struct Widths {
  double alongXPx = 0.0;  // the row through the centre: world X (the lobe's b axis unturned)
  double alongYPx = 0.0;  // the column through the centre: world Y (the tangent)
};

// The plate of material m, rendered; the widths of its highlight through the image's centre (luminance).
// With `anisotropyTexel` ≥ 0 the plate has UVs and its anisotropy comes from a flat texture of U = V = that
// texel (an isotropic lobe, shaded per fragment as anisotropic materials are).
Widths renderedWidths(raster::Renderer& renderer, sdb::Material m, int anisotropyTexel = -1) {
  sdb::Scene scene;
  sdb::Mesh plate = raster::test::quadXY({});
  for (vec3& p : plate.positions) p = vec3(2.0f * p.x, 4.0f * p.y, 0.0f);  // 4 m × 4 m
  if (anisotropyTexel >= 0) {
    sdb::Texture t;
    t.name = "anisotropy";
    t.sourcePath = "<generated>";
    t.width = t.height = 2;
    t.channels = 3;
    for (int k = 0; k < 4; ++k) t.pixels.insert(t.pixels.end(), {uint8_t(anisotropyTexel), uint8_t(anisotropyTexel), 0});
    m.anisotropyTexture.texture = scene.addTexture(std::move(t)).id;
    plate.uv0 = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
  }
  const sdb::MaterialId id = scene.addMaterial(m).id;
  plate.material = id;
  scene.addNode({.name = "plate", .meshes = {scene.addMesh(plate).id}});
  sdb::Light lamp;
  lamp.type = sdb::LightType::kPoint;
  lamp.intensity = kLampCd;
  scene.addNode({.name = "lamp",
                 .parentFromLocal = glm::translate(mat4(1.0f), vec3(0.0f, 0.0f, kLampHeightM)),
                 .light = scene.addLight(lamp).id});
  rdb::RasterRdb r = rdb::buildRasterRdb(scene);
  r.ambient = {};
  EXPECT_EQ(r.variants.anisotropy, m.isAnisotropic());
  renderer.upload(r);
  raster::View view;
  view.worldFromCamera = sdb::lookAtTransform(vec3(0.0f, 0.0f, 3.0f), vec3(0.0f), vec3(0, 1, 0));
  view.orthographic = true;
  view.xmagM = view.ymagM = kHalfExtentM;
  view.znearM = 0.1f;
  view.zfarM = 10.0f;
  renderer.render(view, raster::RenderMode::kSimple, kPx, kPx);
  const std::vector<float> image = renderer.luminanceRgb();
  auto luminance = [&](uint32_t x, uint32_t y) {
    const float* p = &image[3 * (size_t(y) * kPx + x)];
    return 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2];
  };
  // The centre lies between pixels kPx/2 − 1 and kPx/2: average the two rows (columns) that straddle it.
  std::vector<double> row(kPx), column(kPx);
  for (uint32_t i = 0; i < kPx; ++i) {
    row[i] = 0.5 * (luminance(i, kPx / 2 - 1) + luminance(i, kPx / 2));
    column[i] = 0.5 * (luminance(kPx / 2 - 1, i) + luminance(kPx / 2, i));
  }
  return {halfMaximumWidthPx(row), halfMaximumWidthPx(column)};
}

// The same widths by the closed form: L = f(ωo, ωi) cos θi · I / d² at the pixel centres beside the centre
// line (the mean of the two, as renderedWidths reads them).
Widths referenceWidths(const sdb::Material& m) {
  const dvec2 alphas = test::anisotropicAlphas(m, m.anisotropyU, m.anisotropyV);
  const test::AnisotropicFrame frame = test::anisotropicFrame(dvec3(0, 0, 1), dvec3(0, 1, 0), m.anisotropyRotationRad);
  const dvec3 lamp(0.0, 0.0, kLampHeightM);
  auto radiance = [&](double x, double y) {
    const dvec3 toLamp = lamp - dvec3(x, y, 0.0);
    const double d2 = glm::dot(toLamp, toLamp);
    const dvec3 l = test::anisotropicBrdfCos(m, alphas, frame, dvec3(0, 0, 1), toLamp / std::sqrt(d2)) * (kLampCd / d2);
    return 0.2126 * l.r + 0.7152 * l.g + 0.0722 * l.b;
  };
  const double nearCentre = pixelCentreM(kPx / 2);  // ± half a pixel
  std::vector<double> row(kPx), column(kPx);
  for (uint32_t i = 0; i < kPx; ++i) {
    const double c = pixelCentreM(i);
    row[i] = 0.5 * (radiance(c, nearCentre) + radiance(c, -nearCentre));
    column[i] = 0.5 * (radiance(nearCentre, c) + radiance(-nearCentre, c));
  }
  return {halfMaximumWidthPx(row), halfMaximumWidthPx(column)};
}

void expectWidths(const char* what, const Widths& image, const Widths& reference) {
  std::printf("%-34s width along X %.2f px (closed form %.2f), along Y %.2f px (%.2f), Y/X %.3f (%.3f)\n", what,
              image.alongXPx, reference.alongXPx, image.alongYPx, reference.alongYPx, image.alongYPx / image.alongXPx,
              reference.alongYPx / reference.alongXPx);
  EXPECT_NEAR(image.alongXPx, reference.alongXPx, 0.02 * reference.alongXPx) << what;
  EXPECT_NEAR(image.alongYPx, reference.alongYPx, 0.02 * reference.alongYPx) << what;
}

TEST(AnisotropicHighlight, WiderAlongTheWideAxisByTheLobesRatio) {
  raster::test::context();
  raster::Renderer renderer;
  const sdb::Material brushed = sdb::findMaterialPreset("brushed-metal")->material;
  const dvec2 alphas = test::anisotropicAlphas(brushed, brushed.anisotropyU, brushed.anisotropyV);
  ASSERT_NEAR(alphas.x / alphas.y, 1.0 / 0.55, 1e-5);  // Burley's aspect² = 1 − 0.9 |0.6 − 0.1|

  const Widths reference = referenceWidths(brushed);
  // The closed form's own ratio lies near the first-order α_t / α_b.
  EXPECT_NEAR(reference.alongYPx / reference.alongXPx, alphas.x / alphas.y, 0.1);
  const Widths image = renderedWidths(renderer, brushed);
  expectWidths("brushed-metal", image, reference);
  EXPECT_GT(image.alongYPx / image.alongXPx, 1.7);

  // Turned by 90° about the normal, the wide axis is X.
  sdb::Material turned = brushed;
  turned.anisotropyRotationRad = glm::radians(90.0f);
  const Widths turnedReference = referenceWidths(turned);
  const Widths turnedImage = renderedWidths(renderer, turned);
  expectWidths("brushed-metal turned 90°", turnedImage, turnedReference);
  EXPECT_NEAR(turnedImage.alongXPx, image.alongYPx, 0.02 * image.alongYPx);
  EXPECT_NEAR(turnedImage.alongYPx, image.alongXPx, 0.02 * image.alongXPx);

  // U = V (from a texture of 0.5 / 0.5 in place of the values): a round highlight of the preset's α.
  sdb::Material round = brushed;
  round.anisotropyU = round.anisotropyV = 128.0f / 255.0f;
  const Widths roundImage = renderedWidths(renderer, brushed, 128);
  expectWidths("brushed-metal, U = V by a texture", roundImage, referenceWidths(round));
  EXPECT_NEAR(roundImage.alongYPx / roundImage.alongXPx, 1.0, 0.02);
}

// Extreme lobes stay finite: glossiness 0 (a delta lobe: the isotropic narrowest lobe), 0.03 and 1 (α_t
// beyond 1), U − V = ±1 (the widest aspect, 10), under the lamp in simple mode and under a uniform sky of
// 1000 cd/m² (the image-based light's four reads) in sunlight mode, seen from above and at grazing angles: no
// pixel is NaN, infinite or negative, and the plate reflects something in sunlight mode.
TEST(AnisotropicHighlight, ExtremeLobesStayFinite) {
  raster::test::context();
  raster::Renderer renderer;
  for (const float glossiness : {0.0f, 0.03f, 1.0f}) {
    for (const float u : {0.0f, 1.0f}) {
      sdb::Material m = sdb::findMaterialPreset("brushed-metal")->material;
      m.reflectionGlossiness = glossiness;
      m.anisotropyU = u;
      m.anisotropyV = 1.0f - u;
      m.anisotropyRotationRad = 1.0f;
      sdb::Scene scene;
      sdb::Mesh plate = raster::test::quadXY(scene.addMaterial(m).id);
      scene.addNode({.name = "plate", .meshes = {scene.addMesh(plate).id}});
      sdb::Light lamp;
      lamp.intensity = kLampCd;
      scene.addNode({.name = "lamp",
                     .parentFromLocal = glm::translate(mat4(1.0f), vec3(0.2f, 0.1f, kLampHeightM)),
                     .light = scene.addLight(lamp).id});
      rdb::RasterRdb r = rdb::buildRasterRdb(scene);
      ASSERT_TRUE(r.variants.anisotropy);
      rdb::RasterSky sky;
      sky.width = 64;
      sky.height = 32;
      sky.radianceCdM2.assign(size_t(sky.width) * sky.height, Rgb(1000.0f));
      r.sky = sky;
      r.variants.sky = true;
      renderer.upload(r);
      for (const float thetaDeg : {0.0f, 89.0f}) {
        const float theta = glm::radians(thetaDeg);
        raster::View view;
        view.worldFromCamera =
            sdb::lookAtTransform(3.0f * vec3(0.0f, std::sin(theta), std::cos(theta)), vec3(0.0f),
                                 thetaDeg > 45.0f ? vec3(0, 0, 1) : vec3(0, 1, 0));
        view.orthographic = true;
        view.xmagM = view.ymagM = 0.5f;
        view.znearM = 0.1f;
        view.zfarM = 10.0f;
        for (const raster::RenderMode mode : {raster::RenderMode::kSimple, raster::RenderMode::kSunlight}) {
          renderer.render(view, mode, 32, 32);
          const std::vector<float> image = renderer.luminanceRgb();
          double sum = 0.0;
          for (const float v : image) {
            ASSERT_TRUE(std::isfinite(v) && v >= 0.0f)
                << "glossiness " << glossiness << " U " << u << " θ " << thetaDeg << " mode " << int(mode);
            sum += v;
          }
          if (mode == raster::RenderMode::kSunlight) {
            EXPECT_GT(sum, 0.0) << "glossiness " << glossiness;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace fly
