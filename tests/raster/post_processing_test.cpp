// Simple mode's screen-space ambient occlusion (raster/ambient_occlusion.h) and the bloom before tone mapping
// (raster/bloom.h): their values against closed forms, and that either, when off, leaves the image and the
// compiled programs exactly as without it.
//
// The bloom golden lives in tests/data/golden/raster-bloom-sunlight-160x90.png; regenerate it (after a
// deliberate change, looking at the new image) with FLY_UPDATE_GOLDEN=1 tests/fly_raster_tests
// --gtest_filter='PostProcessing.BloomGolden*'.
#include <epoxy/gl.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "../support/helsinki_daylight.h"
#include "base/image_io.h"
#include "base/tone_map.h"
#include "raster/bloom.h"
#include "raster/gl_program.h"
#include "raster/renderer.h"
#include "raster_test_scenes.h"
#include "rdb/raster_rdb.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using test::context;

bool hasProgram(const Renderer& r, const std::string& prefix) {
  for (const std::string& p : r.stats().programs) {
    if (p.rfind(prefix, 0) == 0 || p.find("+" + prefix) != std::string::npos) return true;
  }
  return false;
}

// A matte floor (y = 0, x ∈ [0, 6], z ∈ [−3, 3]) and, where `wall`, a matte wall on x = 0 (y ∈ [0, 3]) facing
// +X: a 90° inner corner along the Z axis. They are lit by the ambient term alone: the scene's only light is
// an emissive panel overhead, 10 m up and facing down (above the view, so it is in no depth buffer), which the
// Phong terms do not shade with but the ambient level counts for the part of its light that lands on the floor
// (rdb/raster_rdb.h, DirectionalAmbient). So each pixel's luminance is its ambient term, and the image with
// occlusion over the one without is the AO itself.
rdb::RasterRdb cornerScene(bool wall) {
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.5f);
  m.reflectionColor = Rgb(0.0f);
  const sdb::MaterialId matte = s.addMaterial(m).id;
  m.emissionLuminance = Rgb(1000.0f);
  const sdb::MaterialId panel = s.addMaterial(m).id;
  sdb::Mesh floor = test::quadXY(matte);  // 2 × 1 m in XY facing +Z: laid down facing +Y, scaled by the frame
  floor.positions = {{0, 0, 3}, {6, 0, 3}, {6, 0, -3}, {0, 0, -3}};
  floor.normals.assign(4, vec3(0, 1, 0));
  s.addNode({.name = "floor", .meshes = {s.addMesh(floor).id}});
  if (wall) {
    sdb::Mesh w = test::quadXY(matte);
    w.positions = {{0, 0, 3}, {0, 0, -3}, {0, 3, -3}, {0, 3, 3}};
    w.normals.assign(4, vec3(1, 0, 0));
    s.addNode({.name = "wall", .meshes = {s.addMesh(w).id}});
  }
  sdb::Mesh p = test::quadXY(panel);
  p.positions = {{-4, 10, -7}, {10, 10, -7}, {10, 10, 7}, {-4, 10, 7}};
  p.normals.assign(4, vec3(0, -1, 0));
  s.addNode({.name = "panel", .meshes = {s.addMesh(p).id}});
  return rdb::buildRasterRdb(s);
}

constexpr uint32_t kAoW = 384, kAoH = 384;
constexpr float kRadiusM = 1.0f;

// The view of the corner: from (3, 2, 0) towards the origin, which lies on the corner's edge line at the
// image's centre.
View cornerView() {
  return test::lookAtView(vec3(3.0f, 2.0f, 0.0f), vec3(0.0f), 100.0f);
}

// Per pixel: the luminance with occlusion over that without (the green channel), and the world point the
// pixel's centre sees on the floor plane y = 0 (rows from the top).
struct AoImage {
  std::vector<float> ratio;
  std::vector<vec3> floorPointM;
};

AoImage aoImage(const rdb::RasterRdb& r, const View& view) {
  Renderer plain, occluded;
  plain.upload(r);
  occluded.upload(r);
  occluded.setAmbientOcclusion({true, kRadiusM});
  plain.render(view, RenderMode::kSimple, kAoW, kAoH);
  occluded.render(view, RenderMode::kSimple, kAoW, kAoH);
  const std::vector<float> a = plain.luminanceRgb(), b = occluded.luminanceRgb();
  AoImage img;
  const float tanY = std::tan(0.5f * view.yfovRad);
  for (uint32_t y = 0; y < kAoH; ++y) {
    for (uint32_t x = 0; x < kAoW; ++x) {
      const size_t i = (size_t(y) * kAoW + x) * 3 + 1;
      img.ratio.push_back(a[i] > 0.0f ? b[i] / a[i] : -1.0f);
      const vec3 dirCamera((2.0f * (x + 0.5f) / kAoW - 1.0f) * tanY, (1.0f - 2.0f * (y + 0.5f) / kAoH) * tanY,
                           -1.0f);
      const vec3 dir = mat3(view.worldFromCamera) * dirCamera;
      const vec3 eye(view.worldFromCamera[3]);
      img.floorPointM.push_back(dir.y < 0.0f ? eye + dir * (-eye.y / dir.y) : vec3(1e9f));
    }
  }
  return img;
}

// On a failed check, the AO image as an 8-bit PNG in the working directory (grey = AO, 1 white; the
// background red; pixels below `flagBelow` blue), to see where the estimate goes wrong.
void writeAoImageOnFailure(const AoImage& img, const std::string& name, float flagBelow) {
  if (!::testing::Test::HasFailure()) return;
  std::vector<uint8_t> px(size_t(kAoW) * kAoH * 3);
  for (size_t i = 0; i < img.ratio.size(); ++i) {
    const float r = img.ratio[i];
    const uint8_t g = uint8_t(std::clamp(r, 0.0f, 1.0f) * 255.0f + 0.5f);
    px[i * 3 + 0] = r < 0.0f ? 255 : (r < flagBelow ? 0 : g);
    px[i * 3 + 1] = r < 0.0f ? 0 : (r < flagBelow ? 0 : g);
    px[i * 3 + 2] = r < 0.0f ? 0 : (r < flagBelow ? 255 : g);
  }
  const std::filesystem::path out = std::filesystem::absolute("ao-" + name + ".png");
  writePng(out, int(kAoW), int(kAoH), 3, px.data());
  ADD_FAILURE() << "the AO image is in " << out;
}

// An open floor, nothing within the radius: every floor point sees its whole hemisphere, AO = 1 (the
// estimate's points all lie above the plane; the bilinear depth read makes a plane exact, up to R16F's 2⁻¹¹).
TEST(PostProcessing, AmbientOcclusionOfAnOpenFloorIsOne) {
  context();
  const AoImage img = aoImage(cornerScene(false), cornerView());
  int floorPixels = 0;
  float lowest = 2.0f;
  for (size_t i = 0; i < img.ratio.size(); ++i) {
    if (img.ratio[i] < 0.0f) continue;  // background
    ++floorPixels;
    lowest = std::min(lowest, img.ratio[i]);
  }
  EXPECT_GT(floorPixels, int(kAoW * kAoH / 3));
  EXPECT_GT(lowest, 0.995f);
  writeAoImageOnFailure(img, "open-floor", 0.995f);
}

// A 90° inner corner: for a point on the edge line the wall fills half of the hemisphere by symmetry, and the
// estimator, cosine-weighted, reads 1/2 (the 16 turns of its pattern, averaged by the blur, put half of each
// direction's turns into the wall). A floor point at distance h from the wall loses about (2/π) E[1/t] h / R
// ≈ 1.6 h / R of that (the disc-projected directions that reach the wall; t ∈ [0.1, 1] the sample's
// distance over R), and the blur averages over |h| ≤ 2.5 pixels ≈ 4 cm here (R = 1 m, pixels of 1.6 cm at the
// corner), so the four pixels about the image's centre read 0.5 + 1.6 · 2 cm ≈ 0.53: 0.5 within 0.05.
// Floor points farther than 1.1 R from the wall are open: 1.
TEST(PostProcessing, AmbientOcclusionInAnInnerCornerIsOneHalf) {
  context();
  const AoImage img = aoImage(cornerScene(true), cornerView());
  for (uint32_t y : {kAoH / 2 - 1, kAoH / 2}) {
    for (uint32_t x : {kAoW / 2 - 1, kAoW / 2}) {
      EXPECT_NEAR(img.ratio[size_t(y) * kAoW + x], 0.5f, 0.05f) << "pixel " << x << ", " << y;
    }
  }
  int open = 0;
  for (size_t i = 0; i < img.ratio.size(); ++i) {
    const vec3 p = img.floorPointM[i];
    if (img.ratio[i] < 0.0f || p.x < 1.1f * kRadiusM || p.x > 5.5f || std::abs(p.z) > 2.5f) continue;
    ++open;
    EXPECT_GT(img.ratio[i], 0.995f) << "floor point " << p.x << ", " << p.z;
  }
  EXPECT_GT(open, 1000);
  writeAoImageOnFailure(img, "inner-corner", 0.995f);
}

// Off (the default), or on in a mode other than simple: the same image to the bit, and no pass compiled.
TEST(PostProcessing, AmbientOcclusionOffChangesNothing) {
  context();
  const rdb::RasterRdb r = cornerScene(true);
  Renderer a, b;
  a.upload(r);
  b.upload(r);
  b.setAmbientOcclusion({false, 2.0f});
  a.render(cornerView(), RenderMode::kSimple, 64, 64);
  b.render(cornerView(), RenderMode::kSimple, 64, 64);
  EXPECT_EQ(a.luminanceRgb(), b.luminanceRgb());
  EXPECT_EQ(a.stats().programs, b.stats().programs);
  EXPECT_FALSE(hasProgram(b, "ssao"));
  b.setAmbientOcclusion({true, 2.0f});
  b.render(cornerView(), RenderMode::kSimple, 64, 64);
  EXPECT_TRUE(hasProgram(b, "ssao"));
  EXPECT_NE(a.luminanceRgb(), b.luminanceRgb());
  EXPECT_THROW(b.setAmbientOcclusion({true, 0.0f}), std::invalid_argument);
  EXPECT_THROW(b.setAmbientOcclusion({true, std::nanf("")}), std::invalid_argument);
}

// kLuminanceEncoding on the CPU for a grey value that is a power of two (or 0), exact: 2^k has e = k + 1 and
// mantissa 2^18.
std::array<uint32_t, 2> encodeGreyPowerOfTwo(int k) {
  const uint32_t q = 1u << 18;
  const uint32_t e = uint32_t(k + 1 + 64);
  return {q | (q << 19), (q >> 13) | (q << 6) | (e << 25)};
}

float decodeGreen(uint32_t x, uint32_t y) {
  const uint32_t q = (x >> 19) | ((y & 0x3fu) << 13);
  return std::ldexp(float(q), int(y >> 25) - 64 - 19);
}

// One pixel of 2^20 cd/m² on black, threshold 1 cd/m² (exposure scale 1), strength k = 0.1: the bright part
// is B = 2^20 − 1, and the glare moves k B into the kernel about the pixel: the pixel keeps L − k B plus the
// kernel's own centre weight, and the kernel's sum over the image (the pixel's gain included) is k B within
// 1 % (the image's energy, Σ L, is kept: the kernel stays inside the 256² image). The kernel is wide: most of
// it lies outside the 3 × 3 pixels about the source; and it is centred: mirror pixels 3, 10 and 30 pixels
// away agree within 10 %.
TEST(PostProcessing, BloomSpreadsTheStatedFractionOfABrightPixel) {
  context();
  constexpr uint32_t w = 256, h = 256, cx = 128, cy = 128;
  std::vector<uint32_t> words(size_t(w) * h * 2, 0u);
  const std::array<uint32_t, 2> bright = encodeGreyPowerOfTwo(20);
  words[(size_t(cy) * w + cx) * 2] = bright[0];
  words[(size_t(cy) * w + cx) * 2 + 1] = bright[1];
  GLuint input = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &input);
  glTextureStorage2D(input, 1, GL_RG32UI, w, h);
  glTextureSubImage2D(input, 0, 0, 0, w, h, GL_RG_INTEGER, GL_UNSIGNED_INT, words.data());
  std::vector<std::string> compiled;
  Bloom bloom([&](const std::string& name, const std::string& defines,
                  std::initializer_list<std::pair<unsigned, const char*>> stages) {
    compiled.push_back(name);
    return linkGlProgram(name, defines, stages);
  });
  const float k = 0.1f, sourceCdM2 = 1048576.0f;
  const unsigned out = bloom.apply(input, w, h, 1.0f, {k, 1.0f});
  std::vector<uint32_t> result(words.size());
  glGetTextureImage(out, 0, GL_RG_INTEGER, GL_UNSIGNED_INT, GLsizei(result.size() * 4), result.data());
  glDeleteTextures(1, &input);
  auto at = [&](uint32_t x, uint32_t y) {
    return double(decodeGreen(result[(size_t(y) * w + x) * 2], result[(size_t(y) * w + x) * 2 + 1]));
  };
  const double brightPart = sourceCdM2 - 1.0;
  double total = 0.0, near = 0.0;
  for (uint32_t y = 0; y < h; ++y) {
    for (uint32_t x = 0; x < w; ++x) {
      total += at(x, y);
      if (std::abs(int(x) - int(cx)) <= 1 && std::abs(int(y) - int(cy)) <= 1 && !(x == cx && y == cy))
        near += at(x, y);
    }
  }
  const double keptAtSource = sourceCdM2 - k * brightPart;
  const double kernelSum = total - keptAtSource;
  EXPECT_NEAR(kernelSum / (k * brightPart), 1.0, 0.01);
  EXPECT_NEAR(total / sourceCdM2, 1.0, 0.001);
  const double centreGain = at(cx, cy) - keptAtSource;
  EXPECT_GT(centreGain, 0.0);
  EXPECT_LT(centreGain + near, 0.5 * kernelSum);
  for (int d : {3, 10, 30}) {
    EXPECT_NEAR(at(cx - d, cy), at(cx + d, cy), 0.1 * at(cx + d, cy)) << d;
    EXPECT_NEAR(at(cx, cy - d), at(cx, cy + d), 0.1 * at(cx, cy + d)) << d;
  }
  EXPECT_EQ(compiled, (std::vector<std::string>{"bloom-first", "bloom-down", "bloom-up", "bloom"}));
}

// A ground, a box and the low evening sun of Helsinki in view (the camera looks towards it, 2° below).
rdb::RasterRdb sunsetScene(View& view) {
  sdb::Scene s;
  sdb::Material m;
  m.diffuseColor = Rgb(0.3f, 0.35f, 0.25f);
  const sdb::MaterialId ground = s.addMaterial(m).id;
  m.diffuseColor = Rgb(0.8f, 0.3f, 0.2f);
  m.reflectionColor = Rgb(1.0f);
  m.reflectionGlossiness = 0.6f;
  const sdb::MaterialId paint = s.addMaterial(m).id;
  sdb::Mesh g = test::quadXY(ground);
  g.positions = {{-20, 0, 20}, {20, 0, 20}, {20, 0, -20}, {-20, 0, -20}};
  g.normals.assign(4, vec3(0, 1, 0));
  s.addNode({.name = "ground", .meshes = {s.addMesh(g).id}});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T21:30");
  rdb::RasterRdb probe = rdb::buildRasterRdb(s);
  const vec3 sun = probe.sky->sunDirWorld;
  const vec3 flat = glm::normalize(vec3(sun.x, 0.0f, sun.z));
  s.addNode({.name = "box",
             .meshes = {s.addMesh(test::box(vec3(-0.5f, 0, -0.5f) + 4.0f * flat,
                                            vec3(0.5f, 1, 0.5f) + 4.0f * flat + vec3(0.8f, 0, 0), paint))
                            .id}});
  const vec3 eye(0.0f, 1.5f, 0.0f);
  const float below = std::tan(2.0f * 3.14159265f / 180.0f);
  view = test::lookAtView(eye, eye + glm::normalize(sun - vec3(0.0f, below, 0.0f)), 1e30f);
  view.yfovRad = 0.3f;  // 17°: the sun's disc (0.53°) some 5 pixels wide
  return rdb::buildRasterRdb(s);
}

// The sun in view with bloom 0.05 against its golden (linear operator, compared as golden_test.cpp's goldens:
// at most 3 levels off on 99.5 % of the values, none more than 48); bloom off leaves the sRGB image to the
// bit, and the luminance image is never changed by it.
TEST(PostProcessing, BloomGoldenOfTheSunInView) {
  context();
  View view;
  const rdb::RasterRdb r = sunsetScene(view);
  ASSERT_TRUE(r.variants.sun);
  constexpr uint32_t w = 160, h = 90;
  const double ev100 = 14.0;
  Renderer plain, glare;
  plain.upload(r);
  glare.upload(r);
  plain.render(view, RenderMode::kSunlight, w, h);
  glare.render(view, RenderMode::kSunlight, w, h);
  plain.toneMap({ToneOperator::kLinear, ev100});
  glare.setBloom({0.0f, 1.0f});
  glare.toneMap({ToneOperator::kLinear, ev100});
  EXPECT_EQ(plain.srgb8(), glare.srgb8());
  EXPECT_FALSE(hasProgram(glare, "bloom"));
  glare.setBloom({0.05f, 1.0f});
  glare.toneMap({ToneOperator::kLinear, ev100});
  EXPECT_TRUE(hasProgram(glare, "bloom"));
  EXPECT_EQ(plain.luminanceRgb(), glare.luminanceRgb());
  const std::vector<uint8_t> px = glare.srgb8();
  EXPECT_NE(px, plain.srgb8());
  const std::filesystem::path golden =
      std::filesystem::path(FLY_TEST_DATA_DIR) / "golden" / "raster-bloom-sunlight-160x90.png";
  if (std::getenv("FLY_UPDATE_GOLDEN")) {
    writePng(golden, int(w), int(h), 3, px.data());
    GTEST_SKIP() << "wrote " << golden;
  }
  ASSERT_TRUE(std::filesystem::exists(golden)) << golden << " is missing; see the top of this file";
  const ImageU8 g = readPng(golden);
  ASSERT_EQ(g.width, int(w));
  ASSERT_EQ(g.height, int(h));
  size_t off = 0;
  int worst = 0;
  for (size_t i = 0; i < px.size(); ++i) {
    const int d = std::abs(int(px[i]) - int(g.pixels[i]));
    worst = std::max(worst, d);
    off += d > 3;
  }
  if (!(off * 1000 <= px.size() * 5 && worst <= 48)) {
    writePng(std::filesystem::absolute("golden-actual-raster-bloom-sunlight-160x90.png"), int(w), int(h), 3,
             px.data());
    ADD_FAILURE() << off << " of " << px.size() << " values differ by more than 3, worst " << worst;
  }
  EXPECT_THROW(glare.setBloom({1.5f, 1.0f}), std::invalid_argument);
  EXPECT_THROW(glare.setBloom({0.1f, 0.0f}), std::invalid_argument);
}

}  // namespace
}  // namespace fly::raster
