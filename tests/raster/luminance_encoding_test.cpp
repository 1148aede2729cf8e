// The float image's encoding (raster/shaders/scene_glsl.h, kLuminanceEncoding: RGB with a shared exponent in
// an RG32UI target), through the whole engine: written by the scene and background passes, decoded by
// Renderer::luminanceRgb and by the tone-map pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "base/tone_map.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

// Two black, non-reflecting quads (quadXY scaled by 1/2: 1 × 0.5 m) centred at x = −1 and x = +1 in z = 0,
// emitting `left` and `right` (cd/m²), seen head-on by an orthographic camera (4 × 2 m in 64 × 32 pixels:
// the quads' edges run along pixel edges). Simple mode with no lights: L = the emission, exactly.
struct TwoEmitters {
  rdb::RasterRdb rdb;
  std::vector<float> expected;  // RGB per pixel, rows from the top
};

TwoEmitters twoEmitters(const Rgb& left, const Rgb& right) {
  sdb::Scene s;
  TwoEmitters t;
  t.expected.assign(64 * 32 * 3, 0.0f);
  for (const auto& [emission, centreX] : {std::pair{left, -1.0f}, std::pair{right, 1.0f}}) {
    sdb::Material m;
    m.diffuseColor = Rgb(0.0f);
    m.reflectionColor = Rgb(0.0f);
    m.emissionLuminance = emission;
    mat4 placement(0.5f);
    placement[3] = vec4(centreX, 0.0f, 0.0f, 1.0f);
    s.addNode({.name = "emitter",
               .parentFromLocal = placement,
               .meshes = {s.addMesh(test::quadXY(s.addMaterial(m).id)).id}});
    // Pixels 16 wide per metre: x ∈ [centreX − 0.5, centreX + 0.5], y ∈ [−0.25, 0.25].
    const int x0 = int(std::lround((centreX - 0.5f + 2.0f) * 16.0f));
    for (int j = 12; j < 20; ++j) {
      for (int i = x0; i < x0 + 16; ++i) {
        for (int c = 0; c < 3; ++c) t.expected[(size_t(j) * 64 + size_t(i)) * 3 + size_t(c)] = emission[c];
      }
    }
  }
  t.rdb = rdb::buildRasterRdb(s);
  return t;
}

View headOn() {
  View v;
  v.orthographic = true;
  v.ymagM = 1.0f;
  v.znearM = 0.1f;
  v.zfarM = 10.0f;
  v.worldFromCamera = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 0, 5));
  return v;
}

// Uploads the two emitters into `renderer` and renders them head-on in simple mode (64 × 32 pixels).
void renderHeadOn(Renderer& renderer, const TwoEmitters& t) {
  renderer.upload(t.rdb);
  renderer.render(headOn(), RenderMode::kSimple, 64, 32);
}

// Each channel within 2⁻¹⁹ of the pixel's largest (the encoding's rounding) plus a few float ulps (the
// rasteriser's interpolation of a constant); channels that are 0 stay exactly 0.
void expectEncodedNear(const std::vector<float>& actual, const std::vector<float>& expected) {
  ASSERT_EQ(actual.size(), expected.size());
  size_t bad = 0;
  for (size_t p = 0; p < expected.size(); p += 3) {
    const float largest = std::max({expected[p], expected[p + 1], expected[p + 2]});
    for (size_t c = p; c < p + 3; ++c) {
      const float tol = expected[c] == 0.0f ? 0.0f : 2.5e-6f * largest;
      if (!(std::abs(actual[c] - expected[c]) <= tol) && ++bad <= 5)
        ADD_FAILURE() << "value " << c << " (pixel " << p / 3 << "): " << actual[c] << " vs " << expected[c];
    }
  }
  EXPECT_EQ(bad, 0u);
}

// The sun's disc (~1.6·10⁹ cd/m², beyond half floats' 65 504) and a dim surface (~10⁻⁷ cd/m², below half
// floats' normal range) in one image, every channel different, one of them 0.
TEST(LuminanceEncoding, KeepsTheSunAndDimSurfacesToTheEncodingsAccuracy) {
  context();
  TwoEmitters t = twoEmitters(Rgb(1.6e9f, 1.3e9f, 0.0f), Rgb(3.1e-7f, 5.3e-7f, 1.7e-7f));
  Renderer renderer;
  renderHeadOn(renderer, t);
  expectEncodedNear(renderer.luminanceRgb(), t.expected);
}

// A channel far below the pixel's largest keeps an absolute error of at most 2⁻¹⁹ of the largest: here
// (1000, 1, 0.001) cd/m² gives ≤ 1.9·10⁻³ cd/m² on each.
TEST(LuminanceEncoding, SmallChannelsBesideALargeOneKeepTheLargeOnesAbsoluteAccuracy) {
  context();
  TwoEmitters t = twoEmitters(Rgb(1000.0f, 1.0f, 0.001f), Rgb(0.25f, 0.5f, 0.75f));
  Renderer renderer;
  renderHeadOn(renderer, t);
  expectEncodedNear(renderer.luminanceRgb(), t.expected);
}

// The tone-map pass decodes on the GPU what luminanceRgb decodes on the CPU: linear operator at an exposure
// that puts the bright quad at display value 0.8 gives the same sRGB bytes as the CPU tone map of the
// decoded image (to 1 code).
TEST(LuminanceEncoding, ToneMapPassDecodesLikeTheReadBack) {
  context();
  TwoEmitters t = twoEmitters(Rgb(1.6e9f, 1.3e9f, 0.0f), Rgb(0.9e9f, 1.2e9f, 0.4e9f));
  Renderer renderer;
  renderHeadOn(renderer, t);
  const std::vector<float> lum = renderer.luminanceRgb();
  // exposureScale(ev100) = 1 / (1.2 · 2^ev100): 1.6·10⁹ · scale = 0.8.
  const ToneMapSettings tone{ToneOperator::kLinear, std::log2(1.6e9 / (0.8 * 1.2))};
  renderer.toneMap(tone);
  const std::vector<uint8_t> srgb = renderer.srgb8();
  ASSERT_EQ(srgb.size(), lum.size());
  int worst = 0, lit = 0;
  for (size_t i = 0; i < lum.size(); i += 3) {
    const Rgb display = fly::toneMap(Rgb(lum[i], lum[i + 1], lum[i + 2]), tone);
    for (size_t c = 0; c < 3; ++c) {
      const int code = int(encodeSrgb8(display[int(c)]));
      lit += code > 0;
      worst = std::max(worst, std::abs(int(srgb[i + c]) - code));
    }
  }
  EXPECT_LE(worst, 1);
  EXPECT_GT(lit, 2 * 16 * 8 * 2);  // both quads show
}

}  // namespace
}  // namespace fly::raster
