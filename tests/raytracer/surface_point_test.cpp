// Texture lookups against hand-computed texel values: wrap modes, bilinear weights, sRGB decoding,
// KHR_texture_transform, channel layouts; coverage, shading normals, anisotropy textures and the tangent
// frame at points.
#include "raytracer/surface_point.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "raytracer/bsdf.h"
#include "rdb/trace_rdb_build.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::raytracer {
namespace {

using rdb::TraceWrap;

TEST(SurfacePoint, WrapModesFollowOpenGL) {
  // Width 4: texels 0 1 2 3.
  const int64_t in[] = {-5, -1, 0, 3, 4, 5, 7, 8, 9};
  const uint32_t repeat[] = {3, 3, 0, 3, 0, 1, 3, 0, 1};
  const uint32_t clamp[] = {0, 0, 0, 3, 3, 3, 3, 3, 3};
  const uint32_t mirror[] = {3, 0, 0, 3, 3, 2, 0, 0, 1};
  for (size_t k = 0; k < std::size(in); ++k) {
    EXPECT_EQ(wrapTexel(in[k], 4, TraceWrap::kRepeat), repeat[k]) << in[k];
    EXPECT_EQ(wrapTexel(in[k], 4, TraceWrap::kClampToEdge), clamp[k]) << in[k];
    EXPECT_EQ(wrapTexel(in[k], 4, TraceWrap::kMirroredRepeat), mirror[k]) << in[k];
  }
}

// A 4 × 2 grey texture, linear: row 0 = 0, 40, 80, 120; row 1 = 200, 210, 220, 230.
rdb::TraceRdb greyTexture() {
  rdb::TraceRdbBuilder b;
  b.texture(4, 2, 1, {0, 40, 80, 120, 200, 210, 220, 230});
  return b.rdb;
}

float lookup(const rdb::TraceRdb& rdb, const vec2& uv, TraceWrap s, TraceWrap t = TraceWrap::kRepeat) {
  rdb::TraceTextureSlot slot;
  slot.texture = 0;
  slot.wrapS = s;
  slot.wrapT = t;
  return sampleTexture(rdb, slot, uv, false).r * 255.0f;
}

TEST(SurfacePoint, BilinearLookupsUnderEachWrapMode) {
  const rdb::TraceRdb rdb = greyTexture();
  // Texel centres: u = (i + ½)/4, v = (j + ½)/2.
  EXPECT_NEAR(lookup(rdb, {0.375f, 0.25f}, TraceWrap::kRepeat), 40.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {0.625f, 0.75f}, TraceWrap::kRepeat), 220.0f, 1e-3f);
  // Half-way between texels 1 and 2 of row 0, a quarter of the way down to row 1.
  EXPECT_NEAR(lookup(rdb, {0.5f, 0.375f}, TraceWrap::kRepeat), 0.75f * 60.0f + 0.25f * 215.0f, 1e-3f);
  // u = 1.125 is texel 0's centre one period on (repeat), beyond the right edge (clamp: texel 3), and in the
  // mirrored copy (texel 3).
  EXPECT_NEAR(lookup(rdb, {1.125f, 0.25f}, TraceWrap::kRepeat), 0.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {1.125f, 0.25f}, TraceWrap::kClampToEdge), 120.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {1.125f, 0.25f}, TraceWrap::kMirroredRepeat), 120.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {1.375f, 0.25f}, TraceWrap::kMirroredRepeat), 80.0f, 1e-3f);
  // u = 0: half-way between texel 0 and texel 3 (repeat), texel 0 (clamp, mirror).
  EXPECT_NEAR(lookup(rdb, {0.0f, 0.25f}, TraceWrap::kRepeat), 60.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {0.0f, 0.25f}, TraceWrap::kClampToEdge), 0.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {0.0f, 0.25f}, TraceWrap::kMirroredRepeat), 0.0f, 1e-3f);
  // v = −0.25: texel row 1 under repeat, row 0 under clamp, row 0 mirrored.
  EXPECT_NEAR(lookup(rdb, {0.125f, -0.25f}, TraceWrap::kRepeat, TraceWrap::kRepeat), 200.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {0.125f, -0.25f}, TraceWrap::kRepeat, TraceWrap::kClampToEdge), 0.0f, 1e-3f);
  EXPECT_NEAR(lookup(rdb, {0.125f, -0.25f}, TraceWrap::kRepeat, TraceWrap::kMirroredRepeat), 0.0f, 1e-3f);
  // Far away and non-finite coordinates stay finite.
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_TRUE(std::isfinite(lookup(rdb, {1e30f, -1e30f}, TraceWrap::kRepeat)));
  EXPECT_NEAR(lookup(rdb, {nan, 0.25f}, TraceWrap::kClampToEdge, TraceWrap::kClampToEdge), 0.0f, 1e-3f);
}

// magFilter NEAREST: the texel that contains the point, whichever side of a texel centre it lies.
TEST(SurfacePoint, NearestLookupsReadTheTexelThePointFallsIn) {
  const rdb::TraceRdb rdb = greyTexture();
  auto nearest = [&](const vec2& uv, TraceWrap s) {
    rdb::TraceTextureSlot slot;
    slot.texture = 0;
    slot.wrapS = s;
    slot.nearest = true;
    return sampleTexture(rdb, slot, uv, false).r * 255.0f;
  };
  // Texel 1 of row 0 covers u ∈ [0.25, 0.5), v ∈ [0, 0.5): bilinear there blends with its neighbours.
  EXPECT_NEAR(nearest({0.26f, 0.01f}, TraceWrap::kRepeat), 40.0f, 1e-3f);
  EXPECT_NEAR(nearest({0.49f, 0.49f}, TraceWrap::kRepeat), 40.0f, 1e-3f);
  EXPECT_NEAR(nearest({0.5f, 0.5f}, TraceWrap::kRepeat), 220.0f, 1e-3f);  // the lower-left corner of texel (2, 1)
  EXPECT_NE(lookup(rdb, {0.49f, 0.49f}, TraceWrap::kRepeat), 40.0f);
  // Outside [0, 1]: u = −0.1 is texel 3 repeated, texel 0 clamped, texel 0 mirrored; u = 1.3 texel 1, 3, 2.
  EXPECT_NEAR(nearest({-0.1f, 0.25f}, TraceWrap::kRepeat), 120.0f, 1e-3f);
  EXPECT_NEAR(nearest({-0.1f, 0.25f}, TraceWrap::kClampToEdge), 0.0f, 1e-3f);
  EXPECT_NEAR(nearest({-0.1f, 0.25f}, TraceWrap::kMirroredRepeat), 0.0f, 1e-3f);
  EXPECT_NEAR(nearest({1.3f, 0.25f}, TraceWrap::kRepeat), 40.0f, 1e-3f);
  EXPECT_NEAR(nearest({1.3f, 0.25f}, TraceWrap::kClampToEdge), 120.0f, 1e-3f);
  EXPECT_NEAR(nearest({1.3f, 0.25f}, TraceWrap::kMirroredRepeat), 80.0f, 1e-3f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NEAR(nearest({nan, 0.25f}, TraceWrap::kClampToEdge), 0.0f, 1e-3f);
  EXPECT_TRUE(std::isfinite(nearest({1e30f, -1e30f}, TraceWrap::kMirroredRepeat)));
}

TEST(SurfacePoint, TextureTransformAndSrgbAndChannels) {
  rdb::TraceRdbBuilder b;
  // 4 × 4 RGBA: texel (i, j) = (i · 60, j · 60, 10, 255 − 50 i).
  std::vector<uint8_t> texels;
  for (int j = 0; j < 4; ++j) {
    for (int i = 0; i < 4; ++i) {
      texels.insert(texels.end(), {uint8_t(i * 60), uint8_t(j * 60), 10, uint8_t(255 - 50 * i)});
    }
  }
  b.texture(4, 4, 4, texels);
  rdb::TraceTextureSlot slot;
  slot.texture = 0;
  // KHR_texture_transform, offset (0, 1), rotation π/2, scale ½: u' = v/2, v' = 1 − u/2 (rdb/trace_rdb.h).
  slot.uvFromU = vec2(0.0f, -0.5f);
  slot.uvFromV = vec2(0.5f, 0.0f);
  slot.uvOffset = vec2(0.0f, 1.0f);
  // (u, v) = (0.75, 0.25) → (0.125, 0.625): texel (0, 2).
  const vec4 linear = sampleTexture(b.rdb, slot, vec2(0.75f, 0.25f), false);
  EXPECT_NEAR(linear.r, 0.0f, 1e-6f);
  EXPECT_NEAR(linear.g, 120.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(linear.a, 1.0f, 1e-6f);
  // sRGB decodes the colour, not alpha; at (u, v) = (0.25, 0.75) → (0.375, 0.875): texel (1, 3).
  const vec4 srgb = sampleTexture(b.rdb, slot, vec2(0.25f, 0.75f), true);
  EXPECT_NEAR(srgb.r, srgbToLinear(60.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(srgb.g, srgbToLinear(180.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(srgb.b, srgbToLinear(10.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(srgb.a, 205.0f / 255.0f, 1e-6f);
  // sRGB is decoded per texel before filtering: half-way between texels 0 and 1 of a row.
  rdb::TraceTextureSlot plain;
  plain.texture = 0;
  const vec4 between = sampleTexture(b.rdb, plain, vec2(0.25f, 0.125f), true);
  EXPECT_NEAR(between.r, 0.5f * srgbToLinear(60.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(between.a, (255.0f - 25.0f) / 255.0f, 1e-6f);
}

// A reflection texture multiplies the reflection colour, decoded as sRGB where the material says so (a glTF
// metal's base colour texture) and read as linear values otherwise; the energy rule then leaves the diffuse
// what the reflection does not take.
TEST(SurfacePoint, ReflectionTextureLinearOrSrgb) {
  rdb::TraceRdbBuilder b;
  b.texture(1, 1, 4, {128, 64, 255, 255});
  const uint32_t mat = b.material(Rgb(0.5f));
  rdb::TraceMaterial& m = b.rdb.materials[mat];
  m.reflection = Rgb(0.8f);
  m.fresnel = false;  // a glTF metal's uniform reflection
  m.reflectionTexture.texture = 0;
  b.ground(1.0f, 1, mat);
  const TrianglePoint at{0, vec2(0.2f, 0.3f)};
  const PointMaterial linear = materialAt(b.rdb, m, at);
  EXPECT_NEAR(linear.material.reflection.r, 0.8f * 128.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(linear.material.reflection.g, 0.8f * 64.0f / 255.0f, 1e-6f);
  EXPECT_NEAR(linear.material.reflection.b, 0.8f, 1e-6f);
  m.reflectionTextureSrgb = true;
  const PointMaterial srgb = materialAt(b.rdb, m, at);
  EXPECT_NEAR(srgb.material.reflection.r, 0.8f * srgbToLinear(128.0f / 255.0f), 1e-6f);  // 0.8 × 0.2158
  EXPECT_NEAR(srgb.material.reflection.g, 0.8f * srgbToLinear(64.0f / 255.0f), 1e-6f);
  EXPECT_NEAR(srgb.material.reflection.b, 0.8f, 1e-6f);
  EXPECT_GT(srgb.material.diffuse.r, linear.material.diffuse.r);  // less reflected, more left to diffuse
}

// Metalness per point: a 2 × 1 metalness texture (0, 1; nearest) on a mirror of white Fresnel reflection at
// ior 1.5 (R0' = 0.04, R90' = 1) with base colour c mixes, by k = factor × texel, a uniform reflector of colour
// c: R(θ) = R0 + (R90 − R0)(1 − cos θ)⁵ with R0 = (1 − k) 0.04 + k c, R90 = (1 − k) + k c, and the diffuse
// colour (1 − k) c. The Bsdf's albedo towards θ is R(θ) + (1 − R(θ)) (1 − k) c, its mirror reflects R(θ), and
// its diffuse lobe is f = (1 − k) c (1 − R(θi)) (1 − R(θo)) / ((1 − R̄) π), R̄ = R0 + (R90 − R0)/21; at
// normal incidence and at 60°, on the dielectric texel and the metal one, for factors 1 and 0.5.
TEST(SurfacePoint, MetalnessTextureMixesAUniformReflectorOfTheBaseColour) {
  const Rgb c(0.2f, 0.5f, 0.9f);
  rdb::TraceRdbBuilder b;
  b.texture(2, 1, 1, {0, 255});
  const uint32_t mat = b.material(c);
  rdb::TraceMaterial& m = b.rdb.materials[mat];
  m.reflection = Rgb(1.0f);
  m.fresnel = true;
  m.ior = 1.5f;
  m.reflectionGlossiness = 0.0f;
  m.metalnessTexture.texture = 0;
  m.metalnessTexture.nearest = true;
  b.ground(1.0f, 1, mat);
  int checked[2] = {0, 0};
  for (const float factor : {1.0f, 0.5f}) {
    m.metalness = factor;
    m.diffuse = normalIncidenceDiffuse(m);  // what lowerMaterial keeps; materialAt recomputes it per point
    for (const vec2 bary : {vec2(0.1f, 0.2f), vec2(0.2f, 0.7f), vec2(0.7f, 0.1f), vec2(0.45f, 0.45f)}) {
      const TrianglePoint at{0, bary};
      const vec2 uv = interpolateUv(b.rdb, 0, at);
      if (std::abs(uv.x - 0.5f) < 0.05f) continue;
      const float k = uv.x < 0.5f ? 0.0f : factor;
      ++checked[uv.x < 0.5f ? 0 : 1];
      const PointMaterial pm = materialAt(b.rdb, m, at);
      EXPECT_NEAR(pm.material.metalness, k, 1e-6f);
      const Rgb r0 = (1.0f - k) * 0.04f + k * c;
      const Rgb r90 = Rgb(1.0f - k) + k * c;
      for (int ch = 0; ch < 3; ++ch) {
        EXPECT_NEAR(pm.material.diffuse[ch], (1.0f - r0[ch]) * (1.0f - k) * c[ch], 1e-6f);
      }
      const Bsdf bsdf(pm.material, true);
      ASSERT_FALSE(bsdf.isLambertian());
      for (const float cosTheta : {1.0f, 0.5f}) {
        const float x = 1.0f - cosTheta;
        const Rgb r = r0 + (r90 - r0) * (x * x * x * x * x);
        const Rgb albedo = r + (Rgb(1.0f) - r) * (1.0f - k) * c;
        const Rgb got = bsdf.albedo(cosTheta);
        for (int ch = 0; ch < 3; ++ch) {
          EXPECT_NEAR(got[ch], albedo[ch], 1e-5f) << "k " << k << ", cos " << cosTheta;
        }
        const vec3 wo(std::sqrt(1.0f - cosTheta * cosTheta), 0.0f, cosTheta);
        Bsdf::Sample s;
        ASSERT_TRUE(bsdf.sample(wo, 0x1.fffffep-1f, vec2(0.5f), s));
        ASSERT_EQ(s.lobe, Bsdf::Lobe::kMirror);
        for (int ch = 0; ch < 3; ++ch) EXPECT_NEAR(s.weight[ch] * s.pdf, r[ch], 1e-5f);
      }
      // The diffuse lobe between normal incidence and 60°.
      const Rgb rBar = r0 + (r90 - r0) / 21.0f;
      const Rgb r60 = r0 + (r90 - r0) * 0.03125f;
      const Rgb f = bsdf.eval(vec3(0, 0, 1), glm::normalize(vec3(std::sqrt(3.0f), 0.0f, 1.0f)));
      for (int ch = 0; ch < 3; ++ch) {
        const float want =
            (1.0f - k) * c[ch] * (1.0f - r0[ch]) * (1.0f - r60[ch]) / ((1.0f - rBar[ch]) * kPiF);
        EXPECT_NEAR(f[ch], want, 1e-6f);
      }
    }
  }
  EXPECT_GT(checked[0], 0);
  EXPECT_GT(checked[1], 0);
}

TEST(SurfacePoint, CoverageAndShadingNormal) {
  rdb::TraceRdbBuilder b;
  b.texture(1, 1, 2, {255, 128});  // grey + alpha
  const uint32_t mat = b.material(Rgb(0.5f));
  rdb::TraceMaterial& m = b.rdb.materials[mat];
  m.diffuseTexture.texture = 0;
  m.opacity = 0.5f;
  b.ground(1.0f, 1, mat);
  const TrianglePoint at{0, vec2(0.2f, 0.3f)};
  EXPECT_NEAR(coverageAt(b.rdb, m, at), 0.5f * 128.0f / 255.0f, 1e-6f);
  b.rdb.colors.assign(b.rdb.positionsM.size(), vec4(1.0f, 1.0f, 1.0f, 0.5f));
  EXPECT_NEAR(coverageAt(b.rdb, m, at), 0.25f * 128.0f / 255.0f, 1e-6f);
  const PointMaterial pm = materialAt(b.rdb, m, at);
  EXPECT_NEAR(pm.coverage, 0.25f * 128.0f / 255.0f, 1e-6f);
  for (int c = 0; c < 3; ++c) EXPECT_NEAR(pm.material.diffuse[c], 0.5f, 1e-6f);

  // Interpolated vertex normals; one pointing below the surface gives way to the geometric normal.
  b.rdb.normals[0] = glm::normalize(vec3(1, 1, 0));
  const vec3 n = shadingNormalAt(b.rdb, m, {0, vec2(0.0f)}, vec3(0, 1, 0));
  EXPECT_NEAR(glm::dot(n, glm::normalize(vec3(1, 1, 0))), 1.0f, 1e-6f);
  b.rdb.normals[0] = vec3(0, -1, 0);
  EXPECT_EQ(shadingNormalAt(b.rdb, m, {0, vec2(0.0f)}, vec3(0, 1, 0)), vec3(0, 1, 0));
}

// The anisotropy texture replaces U and V per point (red, green; linear), the rotation texture the rotation
// (red × 2π); the point's material has no texture slots left. The frame of an anisotropic material follows
// the tangents (here ∂p/∂u = +z, so T = +z and B = N × T = +x), the same on both faces.
TEST(SurfacePoint, AnisotropyTexturesAndTangentFrame) {
  rdb::TraceRdbBuilder b;
  const uint32_t uvTexture = b.texture(2, 1, 3, {255, 0, 0, 51, 204, 0});  // (U, V) = (1, 0) | (0.2, 0.8)
  const uint32_t rotationTexture = b.texture(1, 1, 1, {64});
  const uint32_t mat = b.material(Rgb(0.0f));
  rdb::TraceMaterial& m = b.rdb.materials[mat];
  m.reflection = Rgb(1.0f);
  m.reflectionGlossiness = 0.35f;
  m.anisotropyU = 0.6f;
  m.anisotropyV = 0.1f;
  m.anisotropyRotationRad = 0.3f;
  m.anisotropyTexture.texture = uvTexture;
  m.anisotropyTexture.nearest = true;
  b.ground(1.0f, 1, mat);  // uv0: u along +z, v along +x
  // Triangle 0's corners have uv (0, 0), (1, 0), (1, 1): barycentrics (b1, b2) give u = b1 + b2.
  const TrianglePoint left{0, vec2(0.1f, 0.1f)}, right{0, vec2(0.6f, 0.1f)};
  const PointMaterial l = materialAt(b.rdb, m, left);
  const PointMaterial r = materialAt(b.rdb, m, right);
  EXPECT_FLOAT_EQ(l.material.anisotropyU, 1.0f);
  EXPECT_FLOAT_EQ(l.material.anisotropyV, 0.0f);
  EXPECT_FLOAT_EQ(r.material.anisotropyU, 0.2f);
  EXPECT_FLOAT_EQ(r.material.anisotropyV, 0.8f);
  EXPECT_FLOAT_EQ(l.material.anisotropyRotationRad, 0.3f);  // no rotation texture: the constant
  EXPECT_FALSE(l.material.hasTextures());
  m.anisotropyRotationTexture.texture = rotationTexture;
  EXPECT_NEAR(materialAt(b.rdb, m, right).material.anisotropyRotationRad, 2.0f * kPiF * 64.0f / 255.0f,
              1e-6f);
  // The points' Bsdfs differ as their texels say: at the left point the lobe is ten times wider along U than
  // along V, at the right one narrower.
  const vec3 wo(0.0f, 0.0f, 1.0f), alongU(std::sin(0.2f), 0.0f, std::cos(0.2f)),
      alongV(0.0f, std::sin(0.2f), std::cos(0.2f));
  rdb::TraceMaterial unrotated = l.material;
  unrotated.anisotropyRotationRad = 0.0f;
  const Bsdf bu(unrotated, true);
  EXPECT_GT(bu.eval(wo, alongU).g, 10.0f * bu.eval(wo, alongV).g);
  rdb::TraceMaterial unrotatedRight = r.material;
  unrotatedRight.anisotropyRotationRad = 0.0f;
  const Bsdf bur(unrotatedRight, true);
  EXPECT_LT(bur.eval(wo, alongU).g, bur.eval(wo, alongV).g);

  // The tangent is +u = +z; the bitangent points to the image's up, −v = −x (glTF's), on either face.
  b.rdb.tangents = rdb::generateTangents(b.rdb.positionsM, b.rdb.normals, b.rdb.uv0, b.rdb.indices);
  const vec3 up(0, 1, 0);
  const Onb front = shadingFrameAt(b.rdb, m, left, up, true);
  EXPECT_NEAR(glm::distance(front.tangent, vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(front.bitangent, vec3(-1, 0, 0)), 0.0f, 1e-6f);
  const Onb back = shadingFrameAt(b.rdb, m, left, -up, false);
  EXPECT_NEAR(glm::distance(back.tangent, vec3(0, 0, 1)), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::distance(back.bitangent, vec3(-1, 0, 0)), 0.0f, 1e-6f);
  EXPECT_EQ(back.normal, -up);
  // A tilted shading normal: the tangent made perpendicular to it, the frame orthonormal.
  const vec3 tilted = glm::normalize(vec3(0.0f, 1.0f, 0.5f));
  const Onb t = shadingFrameAt(b.rdb, m, left, tilted, true);
  EXPECT_NEAR(glm::dot(t.tangent, tilted), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::length(t.tangent), 1.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(t.bitangent, t.tangent), 0.0f, 1e-6f);
  EXPECT_NEAR(glm::dot(t.bitangent, vec3(-1, 0, 0)), 1.0f, 1e-6f);
  EXPECT_GT(t.tangent.z, 0.8f);
  // Isotropic materials get the plain basis around the normal.
  const rdb::TraceMaterial isotropic;
  const Onb plain = shadingFrameAt(b.rdb, isotropic, left, up, true);
  const Onb expected = onb(up);
  EXPECT_EQ(plain.tangent, expected.tangent);
  EXPECT_EQ(plain.bitangent, expected.bitangent);
}

}  // namespace
}  // namespace fly::raytracer
