// The GL engine's glossiness texture (rdb::RasterMaterial::glossinessTexture): a plate of glossiness 1 whose
// texture's red halves are 51/255 = 0.2 (left) and 204/255 = 0.8 (right) shows on each half, pixel for pixel,
// what a plate of that glossiness without the texture shows (α = (glossiness · red)² = 0.04 and 0.64): under
// two lamps in simple mode (the lamps' GGX lobes) and under a striped sky in sunlight mode (the image-based
// light's prefiltered level and split sum). The untextured references get a white base colour texture so
// that they too are shaded per fragment (a white texel decodes to exactly 1). Both evaluate the same terms in
// single precision from α = 0.2² and from α = 1 · (unorm8 0.2)², so they agree to 10⁻³ relative (they come
// out equal on llvmpipe); the halves differ by far more: under the lamps the narrow half's brightest pixel
// (848 cd/m²) is about 10 times the wide half's (GGX's peak D = 1 / (π α²) is 256 times as high; the diffuse
// part and the pixel grid take most of that).
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/light.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

constexpr uint32_t kWidthPx = 256, kHeightPx = 128;
constexpr float kLampCd = 100.0f;

// A linear 8-bit texture of one channel (grey: red = green = blue), row-major from the top row.
sdb::TextureId greyTexture(sdb::Scene& s, const char* name, int w, std::vector<uint8_t> texels) {
  sdb::Texture t;
  t.name = name;
  t.sourcePath = "<generated>";
  t.width = w;
  t.height = 1;
  t.channels = 1;
  t.pixels = std::move(texels);
  return s.addTexture(std::move(t)).id;
}

// The plate: quadXY (x ∈ [−1, 1] m, y ∈ [−0.5, 0.5] m, normal +Z) with u = (x + 1) / 2 left to right, of a
// shiny plastic of `glossiness`; with `glossinessTexels` its glossiness texture (a row of those red texels,
// nearest without mipmaps: the halves meet between two pixel columns), else a white base colour texture. Two
// 100 cd lamps 0.5 m above the halves' centres; a sky of azimuthal stripes (1000 and 10000 cd/m², 8 columns
// each).
rdb::RasterRdb plateScene(float glossiness, const std::vector<uint8_t>& glossinessTexels) {
  sdb::Scene s;
  sdb::Material m = sdb::findMaterialPreset("shiny-plastic")->material;
  m.reflectionGlossiness = glossiness;
  if (!glossinessTexels.empty()) {
    m.reflectionGlossinessTexture.texture =
        greyTexture(s, "glossiness", int(glossinessTexels.size()), glossinessTexels);
    m.reflectionGlossinessTexture.magFilter = sdb::MagFilter::kNearest;
    m.reflectionGlossinessTexture.minFilter = sdb::MinFilter::kNearest;
  } else {
    m.diffuseTexture.texture = greyTexture(s, "white", 1, {255});
  }
  sdb::Mesh plate = test::quadXY(s.addMaterial(m).id);
  for (const vec3& p : plate.positions) plate.uv0.push_back(vec2((p.x + 1.0f) * 0.5f, 0.5f - p.y));
  s.addNode({.name = "plate", .meshes = {s.addMesh(plate).id}});
  for (const float x : {-0.5f, 0.5f}) {
    sdb::Light lamp;
    lamp.type = sdb::LightType::kPoint;
    lamp.intensity = kLampCd;
    s.addNode({.name = "lamp",
               .parentFromLocal = glm::translate(mat4(1.0f), vec3(x, 0.0f, 0.5f)),
               .light = s.addLight(lamp).id});
  }
  rdb::RasterRdb r = rdb::buildRasterRdb(s);
  rdb::RasterSky sky;
  sky.width = 64;
  sky.height = 32;
  for (uint32_t j = 0; j < sky.height; ++j)
    for (uint32_t i = 0; i < sky.width; ++i)
      sky.radianceCdM2.push_back(Rgb((i / 8) % 2 == 0 ? 10000.0f : 1000.0f));
  r.sky = sky;
  r.variants.sky = true;
  return r;
}

// The plate seen straight down its normal through an orthographic camera that frames it exactly.
View plateView() {
  View v;
  v.worldFromCamera = sdb::lookAtTransform(vec3(0.0f, 0.0f, 3.0f), vec3(0.0f), vec3(0, 1, 0));
  v.orthographic = true;
  v.xmagM = 1.0f;
  v.ymagM = 0.5f;
  v.znearM = 0.1f;
  v.zfarM = 10.0f;
  return v;
}

struct Rendered {
  std::vector<double> luminance;  // cd/m², kWidthPx × kHeightPx from the top row
  std::vector<std::string> programs;
};

Rendered render(const rdb::RasterRdb& r, RenderMode mode) {
  Renderer renderer;
  renderer.upload(r);
  renderer.render(plateView(), mode, kWidthPx, kHeightPx);
  const std::vector<float> rgb = renderer.luminanceRgb();
  Rendered out;
  for (size_t p = 0; p < size_t(kWidthPx) * kHeightPx; ++p)
    out.luminance.push_back(0.2126 * rgb[3 * p] + 0.7152 * rgb[3 * p + 1] + 0.0722 * rgb[3 * p + 2]);
  out.programs = renderer.stats().programs;
  return out;
}

bool compiles(const Rendered& r, const std::string& tag) {
  return std::any_of(r.programs.begin(), r.programs.end(),
                     [&](const std::string& p) { return p.find(tag) != std::string::npos; });
}

TEST(GlossinessTexture, EachHalfShowsTheHighlightOfItsGlossiness) {
  context();
  const rdb::RasterRdb textured = plateScene(1.0f, {51, 204});
  ASSERT_TRUE(textured.variants.glossinessTextures);
  ASSERT_TRUE(textured.shadedPerFragment(textured.meshes[0]));
  ASSERT_EQ(textured.textures.size(), 1u);
  EXPECT_FALSE(textured.textures[0].srgb);  // linear data
  const rdb::RasterRdb narrow = plateScene(0.2f, {}), wide = plateScene(0.8f, {});
  ASSERT_FALSE(narrow.variants.glossinessTextures);
  for (const RenderMode mode : {RenderMode::kSimple, RenderMode::kSunlight}) {
    const Rendered t = render(textured, mode), n = render(narrow, mode), w = render(wide, mode);
    EXPECT_TRUE(compiles(t, "+glossinesstexture")) << int(mode);
    EXPECT_FALSE(compiles(n, "+glossinesstexture"))
        << int(mode);  // a scene without one compiles no extra code
    size_t bad = 0;
    double peak[2] = {0.0, 0.0};
    for (uint32_t y = 0; y < kHeightPx; ++y) {
      for (uint32_t x = 0; x < kWidthPx; ++x) {
        const size_t p = size_t(y) * kWidthPx + x;
        const int half = x < kWidthPx / 2 ? 0 : 1;
        const double expected = half == 0 ? n.luminance[p] : w.luminance[p];
        peak[half] = std::max(peak[half], t.luminance[p]);
        if (!(std::abs(t.luminance[p] - expected) <= 1e-3 * expected + 1e-4) && ++bad <= 5) {
          ADD_FAILURE() << "mode " << int(mode) << " pixel (" << x << ", " << y << "): " << t.luminance[p]
                        << " cd/m², the untextured glossiness " << (half == 0 ? 0.2 : 0.8) << " gives "
                        << expected;
        }
      }
    }
    EXPECT_EQ(bad, 0u) << "mode " << int(mode);
    std::printf("mode %d: peak luminance %.1f cd/m² on the glossiness 0.2 half, %.1f on the 0.8 half\n",
                int(mode), peak[0], peak[1]);
    if (mode == RenderMode::kSimple) EXPECT_GT(peak[0], 5.0 * peak[1]);  // the halves' lobes differ
  }
}

// Texels of 0 (α = 0: the narrowest lobe the engine draws, 10⁻³) and 1 on an anisotropic plate and on a plain
// one stay finite and non-negative in both modes.
TEST(GlossinessTexture, ExtremeTexelsStayFinite) {
  context();
  for (const bool anisotropic : {false, true}) {
    rdb::RasterRdb r = plateScene(1.0f, {0, 255});
    if (anisotropic) {
      sdb::Scene s;
      sdb::Material m = sdb::findMaterialPreset("brushed-metal")->material;
      m.reflectionGlossiness = 1.0f;
      m.reflectionGlossinessTexture.texture = greyTexture(s, "glossiness", 2, {0, 255});
      sdb::Mesh plate = test::quadXY(s.addMaterial(m).id);
      for (const vec3& p : plate.positions) plate.uv0.push_back(vec2((p.x + 1.0f) * 0.5f, 0.5f - p.y));
      s.addNode({.name = "plate", .meshes = {s.addMesh(plate).id}});
      sdb::Light lamp;
      lamp.intensity = kLampCd;
      s.addNode({.name = "lamp",
                 .parentFromLocal = glm::translate(mat4(1.0f), vec3(0.1f, 0.0f, 0.5f)),
                 .light = s.addLight(lamp).id});
      const std::optional<rdb::RasterSky> sky = r.sky;
      r = rdb::buildRasterRdb(s);
      ASSERT_TRUE(r.variants.anisotropy && r.variants.glossinessTextures);
      r.sky = sky;
      r.variants.sky = true;
    }
    for (const RenderMode mode : {RenderMode::kSimple, RenderMode::kSunlight}) {
      const Rendered t = render(r, mode);
      for (const double l : t.luminance)
        ASSERT_TRUE(std::isfinite(l) && l >= 0.0) << int(mode) << " " << anisotropic;
    }
  }
}

}  // namespace
}  // namespace fly::raster
