// Textured materials, alpha coverage, shading normals, emission textures and anisotropic reflection in the
// integrator, against exact answers: every estimate within 4 of its reported standard errors of the exact
// value, with a standard error small enough for the comparison to mean something.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "raytracer/embree_scene.h"
#include "raytracer/integrator.h"
#include "raytracer/sampler.h"
#include "rdb/trace_rdb_build.h"
#include "rdb/trace_rdb_builder.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"

namespace fly::raytracer {
namespace {

struct Sensors {
  std::vector<vec3> points;
  std::vector<vec3> normals;
  std::vector<Rgb> exact;
  void add(const vec3& p, const vec3& n, const Rgb& e) {
    points.push_back(p);
    normals.push_back(glm::normalize(n));
    exact.push_back(e);
  }
};

constexpr uint32_t kReplicates = 64;  // a 4σ bound from 64 replicates fails by chance on ~1 point in 10⁴

EstimateResult run(const rdb::TraceRdb& rdb, const Sensors& s, uint32_t samples, uint32_t threads = 0) {
  const EmbreeScene scene(rdb);
  const Integrator integrator(rdb, scene);
  EstimateSettings settings;
  settings.firstPassSamples = kReplicates;
  settings.maxSamples = samples;
  settings.threads = threads;
  settings.replicates = kReplicates;
  return estimateIrradiance(integrator, s.points, s.normals, settings);
}

// |mean − exact| < 4σ + 10⁻⁴ exact per channel, and σ ≤ maxRelStdError · exact (+ 10⁻³ lux where exact is 0).
void expectAgrees(const char* what, const EstimateResult& r, const Sensors& s, float maxRelStdError) {
  for (size_t i = 0; i < s.points.size(); ++i) {
    const IrradianceEstimate& e = r.points[i];
    std::cout << "[ estimate ] " << what << " #" << i << ": " << e.meanLux.g << " ± " << e.stdErrorLux.g
              << " lux (exact " << s.exact[i].g << ")\n";
    for (int c = 0; c < 3; ++c) {
      const float exact = s.exact[i][c];
      EXPECT_LE(std::abs(e.meanLux[c] - exact), 4.0f * e.stdErrorLux[c] + 1e-4f * exact + 1e-3f)
          << what << " point " << i << " channel " << c << ": " << e.meanLux[c] << " ± " << e.stdErrorLux[c]
          << ", exact " << exact;
      EXPECT_LE(e.stdErrorLux[c], maxRelStdError * exact + 1e-3f)
          << what << " point " << i << " channel " << c;
    }
  }
}

constexpr float kHalfM = 1000.0f;  // planes far larger than the sensors' heights: the rest is < 10⁻⁶

// A ground plane (y = 0, facing +Y) whose uv0 runs 0 … uvScale over it (u along z, v along x).
void texturedGround(rdb::TraceRdbBuilder& b, uint32_t mat, float uvScale) {
  b.grid(vec3(-kHalfM, 0, -kHalfM), vec3(0, 0, 2 * kHalfM), vec3(2 * kHalfM, 0, 0), 1, mat, false, uvScale);
}

// A plane at height yM facing −Y (down), uv0 0 … uvScale (u along x, v along z).
void texturedCeiling(rdb::TraceRdbBuilder& b, float yM, uint32_t mat, float uvScale) {
  b.grid(vec3(-kHalfM, yM, -kHalfM), vec3(2 * kHalfM, 0, 0), vec3(0, 0, 2 * kHalfM), 1, mat, false, uvScale);
}

rdb::TraceTextureSlot slotOf(uint32_t texture, rdb::TraceWrap wrap = rdb::TraceWrap::kRepeat) {
  rdb::TraceTextureSlot slot;
  slot.texture = texture;
  slot.wrapS = slot.wrapT = wrap;
  return slot;
}

float srgbByte(int v) {
  return srgbToLinear(float(v) / 255.0f);
}

// A sun (directional light) and a uniform sky over a ground of a checker base-colour texture. A sensor facing
// down at height h sees the ground's radiance ρ(x) E_g / π weighted by its cosine kernel: over a checker far
// finer than h that is ρ̄ E_g, ρ̄ the texture's mean albedo (the mean of the texels: bilinear filtering of a
// periodic texture keeps its mean); under clamp-to-edge a 2 × 1 texture stretched over the plane is exactly
// its left texel on the quarter of the plane beyond the left centre, so there it is that texel's ρ E_g.
// E_g = E_sun sin(elevation) + π L_sky. Sensors facing up get E_g: the ground shadows nothing.
TEST(IntegratorMaterials, CheckerGroundReflectsItsMeanAlbedoAndEachTexel) {
  const Rgb sky(2000.0f);
  const Rgb sunLux(50000.0f);
  const vec3 toSun = glm::normalize(vec3(1.0f, 2.0f, 0.5f));
  const Rgb groundLux = sunLux * toSun.y + kPiF * sky;
  // Texels (sRGB): white-ish, dark, mid red, mid green.
  const std::vector<uint8_t> texels = {230, 230, 230, 40, 40, 40, 180, 60, 60, 60, 180, 60};
  Rgb mean(0.0f);
  for (size_t i = 0; i < texels.size(); ++i) mean[int(i % 3)] += srgbByte(texels[i]) / 4.0f;
  const Rgb factor(0.9f, 0.8f, 1.0f);  // the material's base colour multiplies the texture

  Sensors s;
  {
    rdb::TraceRdbBuilder b;
    const uint32_t tex = b.texture(2, 2, 3, texels);
    const uint32_t mat = b.material(Rgb(0.0f));
    b.rdb.materials[mat].diffuseColor = factor;
    b.rdb.materials[mat].diffuseTexture = slotOf(tex);
    // 0.02 m texels.
    texturedGround(b, mat, 2.0f * kHalfM / 0.04f);
    b.uniformSky(sky);
    b.directionalLight(toSun, sunLux);
    s.add(vec3(0.3f, 1.0f, -0.7f), vec3(0, -1, 0), factor * mean * groundLux);
    s.add(vec3(-5.0f, 2.0f, 3.0f), vec3(0, -1, 0), factor * mean * groundLux);
    s.add(vec3(0.0f, 0.0f, 0.0f), vec3(0, 1, 0), groundLux);
    expectAgrees("fine checker", run(b.rdb, s, 4096), s, 0.03f);
  }
  {
    rdb::TraceRdbBuilder b;
    const uint32_t tex = b.texture(2, 1, 3, {230, 40, 40, 60, 180, 60});
    const uint32_t mat = b.material(Rgb(0.0f));
    b.rdb.materials[mat].diffuseColor = Rgb(1.0f);
    b.rdb.materials[mat].diffuseTexture = slotOf(tex, rdb::TraceWrap::kClampToEdge);
    texturedGround(b, mat, 1.0f);
    b.uniformSky(sky);
    b.directionalLight(toSun, sunLux);
    Sensors t;
    // u runs along z: z = −750 m is texel 0's flat quarter, z = +750 m texel 1's.
    t.add(vec3(0.0f, 1.0f, -750.0f), vec3(0, -1, 0),
          Rgb(srgbByte(230), srgbByte(40), srgbByte(40)) * groundLux);
    t.add(vec3(10.0f, 1.0f, 750.0f), vec3(0, -1, 0),
          Rgb(srgbByte(60), srgbByte(180), srgbByte(60)) * groundLux);
    expectAgrees("per texel", run(b.rdb, t, 1024), t, 0.01f);
  }
}

// A fence between a sun straight above and the floor: a quad of an alpha texture (grey + alpha, 8 × 1 texels,
// alpha 0 on 3 of them) repeated every 0.08 m. Bilinear alpha between a covered and an open texel crosses the
// 0.5 cut-off half-way, so the open fraction is exactly 3/8. Floor sensors at 64 points evenly spread over
// one period see the sun through the openings only (occlusion filter): their mean is E × 3/8. Sensors facing
// up under the fence see a uniform sky through it over many periods (paths and shadow rays alike): π L × 3/8.
// BLEND with opacity 0.25 passes 75 % of both, and COLOR_0's alpha multiplies coverage.
TEST(IntegratorMaterials, AlphaMaskCutsOutAndBlendPassesOneMinusCoverage) {
  const Rgb sunLux(10000.0f);
  const Rgb sky(1000.0f);
  const std::vector<uint8_t> fenceTexels = {0, 255, 0, 0, 0, 255, 0, 255, 0, 255, 0, 0, 0, 255, 0, 0};
  constexpr float kPeriodM = 0.08f;
  auto scene = [&](rdb::TraceAlpha alpha, float opacity, bool withSky) {
    rdb::TraceRdbBuilder b;
    const uint32_t tex = b.texture(8, 1, 2, fenceTexels);
    const uint32_t floor = b.material(Rgb(0.0f));
    const uint32_t fence = b.material(Rgb(0.0f));  // black: it reflects nothing back down
    b.rdb.materials[fence].diffuseColor = Rgb(0.0f);
    b.rdb.materials[fence].diffuseTexture = slotOf(tex);
    b.rdb.materials[fence].alpha = alpha;
    b.rdb.materials[fence].opacity = opacity;
    b.ground(kHalfM, 1, floor);
    texturedCeiling(b, 1.0f, fence, 2.0f * kHalfM / kPeriodM);
    if (withSky) {
      b.uniformSky(sky);
    } else {
      b.directionalLight(vec3(0, 1, 0), sunLux);
    }
    return b.rdb;
  };
  {
    // u runs along x from −kHalfM: sensor k at the middle of the k-th 64th of a period.
    Sensors s;
    for (int k = 0; k < 64; ++k) {
      const float x = -kHalfM + 100.0f * kPeriodM + (float(k) + 0.5f) / 64.0f * kPeriodM;
      s.add(vec3(x, 0.0f, 0.25f), vec3(0, 1, 0), Rgb(0.0f));
    }
    const EstimateResult r = run(scene(rdb::TraceAlpha::kMask, 1.0f, false), s, 64);
    Rgb sum(0.0f);
    int lit = 0;
    for (const IrradianceEstimate& e : r.points) {
      sum += e.meanLux;
      lit += e.meanLux.g > 0.5f * sunLux.g ? 1 : 0;
    }
    EXPECT_EQ(lit, 24);  // 3/8 of 64
    EXPECT_NEAR((sum / 64.0f).g, sunLux.g * 3.0f / 8.0f, 1e-3f * sunLux.g);
    const EstimateResult blend = run(scene(rdb::TraceAlpha::kBlend, 0.25f, false), s, 64);
    // Every texel's alpha is 0 or 1: coverage 0.25 × alpha passes 1 − 0.25 where covered, all where open.
    for (int k = 0; k < 64; ++k) {
      const float u = (float(k) + 0.5f) / 64.0f * 8.0f - 0.5f;  // texel space, centres at integers
      const int t0 = int(std::floor(u));
      const float f = u - float(t0);
      const float a0 = fenceTexels[2 * size_t((t0 + 8) % 8) + 1] / 255.0f;
      const float a1 = fenceTexels[2 * size_t((t0 + 9) % 8) + 1] / 255.0f;
      const float coverage = 0.25f * ((1.0f - f) * a0 + f * a1);
      EXPECT_NEAR(blend.points[size_t(k)].meanLux.g, sunLux.g * (1.0f - coverage), 1e-3f * sunLux.g) << k;
    }
  }
  {
    Sensors s;
    for (const vec3& p : {vec3(0.0f, 0.0f, 0.0f), vec3(3.01f, 0.0f, -7.0f), vec3(-20.0f, 0.5f, 11.0f)}) {
      s.add(p, vec3(0, 1, 0), kPiF * sky * (3.0f / 8.0f));
    }
    expectAgrees("mask under a sky", run(scene(rdb::TraceAlpha::kMask, 1.0f, true), s, 4096), s, 0.03f);
    // BLEND over many periods: the mean coverage is 0.25 × the mean filtered alpha (5/8).
    for (Rgb& e : s.exact) e = kPiF * sky * (1.0f - 0.25f * 5.0f / 8.0f);
    expectAgrees("blend under a sky", run(scene(rdb::TraceAlpha::kBlend, 0.25f, true), s, 4096), s, 0.03f);
  }
  {
    // Opacity 0.25 without a texture, and COLOR_0's alpha 0.5 on top: coverage 0.125.
    rdb::TraceRdbBuilder b;
    const uint32_t floor = b.material(Rgb(0.0f));
    const uint32_t fence = b.material(Rgb(0.0f));
    b.rdb.materials[fence].alpha = rdb::TraceAlpha::kBlend;
    b.rdb.materials[fence].opacity = 0.25f;
    b.ground(kHalfM, 1, floor);
    texturedCeiling(b, 1.0f, fence, 1.0f);
    b.directionalLight(vec3(0, 1, 0), sunLux);
    Sensors s;
    s.add(vec3(0.0f), vec3(0, 1, 0), sunLux * 0.75f);
    expectAgrees("blend 0.25", run(b.rdb, s, 64), s, 0.01f);
    b.rdb.colors.assign(b.rdb.positionsM.size(), vec4(1.0f, 1.0f, 1.0f, 0.5f));
    s.exact[0] = sunLux * 0.875f;
    expectAgrees("blend 0.25 × COLOR_0 0.5", run(b.rdb, s, 64), s, 0.01f);
  }
}

// Two half-planes of albedo ρ meeting under a sensor 1 m up facing down, lit from straight above by E: the
// sensor sees each half over half of its cosine kernel, so E_sensor = E ρ (c_A + c_B) / 2 per channel, c the
// vertex colour (COLOR_0, which multiplies the base colour). Half A is tinted, half B white: the white half is
// the constant material, and with every vertex white the estimate is the very same as without colours.
TEST(IntegratorMaterials, VertexColoursTintOnlyTheTrianglesThatCarryThem) {
  const float rho = 0.6f;
  const Rgb lightLux(1000.0f);
  const vec4 tint(0.5f, 0.25f, 1.0f, 1.0f);
  auto scene = [&](bool colours, const vec4& colourA) {
    rdb::TraceRdbBuilder b;
    const uint32_t a = b.material(Rgb(rho));
    const uint32_t white = b.material(Rgb(rho));
    b.grid(vec3(-kHalfM, 0, -kHalfM), vec3(0, 0, 2 * kHalfM), vec3(kHalfM, 0, 0), 1, a);
    const size_t verticesA = b.rdb.positionsM.size();
    b.grid(vec3(0, 0, -kHalfM), vec3(0, 0, 2 * kHalfM), vec3(kHalfM, 0, 0), 1, white);
    if (colours) {
      b.rdb.colors.assign(b.rdb.positionsM.size(), vec4(1.0f));
      std::fill(b.rdb.colors.begin(), b.rdb.colors.begin() + std::ptrdiff_t(verticesA), colourA);
    }
    b.directionalLight(vec3(0, 1, 0), lightLux);
    return b.rdb;
  };
  Sensors s;
  s.add(vec3(0.0f, 1.0f, 0.0f), vec3(0, -1, 0), lightLux * rho * (Rgb(tint) + Rgb(1.0f)) * 0.5f);
  expectAgrees("tinted and white halves", run(scene(true, tint), s, 4096), s, 0.01f);

  s.exact[0] = lightLux * rho;
  const EstimateResult white = run(scene(true, vec4(1.0f)), s, 4096);
  expectAgrees("white vertex colours", white, s, 0.01f);
  const EstimateResult none = run(scene(false, vec4(1.0f)), s, 4096);
  for (int c = 0; c < 3; ++c) {
    EXPECT_EQ(white.points[0].meanLux[c], none.points[0].meanLux[c]) << c;
    EXPECT_EQ(white.points[0].stdErrorLux[c], none.points[0].stdErrorLux[c]) << c;
  }
}

// A plane whose normal map tilts every shading normal by α = 30° towards +x, under a directional light from
// 45° elevation in the x–y plane and no sky. It reflects as a plane tilted by α would: radiance ρ E cos(15°)
// / π everywhere (an untilted plane: ρ E cos 45° / π). A sensor facing the tilted normal's opposite −n_s at
// height 0.5 m sees the plane over the part of its cosine kernel that points below the horizon, (1 + cos α) /
// 2 of it, so E = ρ E_light cos(15°) (1 + cos α) / 2. A light below the geometric surface (but above the
// tilted shading hemisphere) lights nothing: the geometry blocks it.
TEST(IntegratorMaterials, NormalMapTiltsTheReflectionAndGeometryStillBlocks) {
  constexpr float kAlpha = 0.5235988f;  // 30°
  const float rho = 0.6f;
  const Rgb lightLux(1000.0f);
  // Tangent space: x along u (+z here), y along the bitangent, the image's up −v = −x (glTF's), so a tilt
  // towards +x is −y. The map's bytes, and the normal they encode after 8-bit rounding.
  const vec3 encoded(127.5f, 127.5f - 127.5f * std::sin(kAlpha), 127.5f + 127.5f * std::cos(kAlpha));
  const std::vector<uint8_t> map = {uint8_t(std::lround(encoded.x)), uint8_t(std::lround(encoded.y)),
                                    uint8_t(std::lround(encoded.z))};
  const vec3 local = glm::normalize(vec3(map[0], map[1], map[2]) / 255.0f * 2.0f - 1.0f);
  const vec3 ns = glm::normalize(vec3(-local.y, local.z, local.x));  // world (x, y, z) = (−B, N, T)
  auto scene = [&](const vec3& toLight) {
    rdb::TraceRdbBuilder b;
    const uint32_t tex = b.texture(1, 1, 3, map);
    const uint32_t mat = b.material(Rgb(rho));
    b.rdb.materials[mat].diffuseColor = Rgb(rho);
    b.rdb.materials[mat].normalTexture = slotOf(tex);
    texturedGround(b, mat, 1.0f);
    b.rdb.tangents = rdb::generateTangents(b.rdb.positionsM, b.rdb.normals, b.rdb.uv0, b.rdb.indices);
    b.directionalLight(toLight, lightLux);
    return b.rdb;
  };
  const rdb::TraceRdb lit = scene(glm::normalize(vec3(1, 1, 0)));
  for (const vec4& t : lit.tangents) {
    EXPECT_NEAR(t.z, 1.0f, 1e-6f);  // ∂p/∂u = +z
    EXPECT_EQ(t.w, -1.0f);          // w · N × T = −(+Y × +Z) = −x
  }
  Sensors s;
  const float cosLight = glm::dot(ns, glm::normalize(vec3(1, 1, 0)));
  const float cosTilt = ns.y;
  s.add(vec3(0.2f, 0.5f, -0.4f), -ns, lightLux * rho * cosLight * (1.0f + cosTilt) / 2.0f);
  s.add(vec3(-30.0f, 0.5f, 12.0f), -ns, lightLux * rho * cosLight * (1.0f + cosTilt) / 2.0f);
  EXPECT_NEAR(cosLight, std::cos(0.2617994f), 0.01f);
  expectAgrees("normal-mapped plane", run(lit, s, 1024), s, 0.01f);

  const vec3 below = glm::normalize(vec3(1.0f, -0.2f, 0.0f));
  ASSERT_GT(glm::dot(below, ns), 0.0f);  // above the shading hemisphere, below the geometric one
  for (Rgb& e : s.exact) e = Rgb(0.0f);
  expectAgrees("light from below the surface", run(scene(below), s, 256), s, 0.01f);
}

// An icosphere of 80 faces with smooth vertex normals, seen from inside: its inner faces emit L_e and reflect
// ρ = 0.5. With geometric normals every point's radiance is L_e / (1 − ρ) and a sensor anywhere inside sees
// E = π L_e / (1 − ρ). Shading normals may lose a little energy (directions between the shading and the
// geometric horizon count nothing) but never gain any, and no facet goes black: E stays within [0.9, 1] of
// it.
TEST(IntegratorMaterials, SmoothLowPolySphereKeepsEnergyWithinBounds) {
  // Icosahedron, subdivided once, projected onto the unit sphere; faces wound to face inwards.
  const float t = (1.0f + std::sqrt(5.0f)) / 2.0f;
  std::vector<vec3> v = {{-1, t, 0},  {1, t, 0},  {-1, -t, 0}, {1, -t, 0}, {0, -1, t},  {0, 1, t},
                         {0, -1, -t}, {0, 1, -t}, {t, 0, -1},  {t, 0, 1},  {-t, 0, -1}, {-t, 0, 1}};
  std::vector<glm::uvec3> faces = {{0, 11, 5}, {0, 5, 1},  {0, 1, 7},   {0, 7, 10}, {0, 10, 11},
                                   {1, 5, 9},  {5, 11, 4}, {11, 10, 2}, {10, 7, 6}, {7, 1, 8},
                                   {3, 9, 4},  {3, 4, 2},  {3, 2, 6},   {3, 6, 8},  {3, 8, 9},
                                   {4, 9, 5},  {2, 4, 11}, {6, 2, 10},  {8, 6, 7},  {9, 8, 1}};
  for (vec3& p : v) p = glm::normalize(p);
  std::vector<glm::uvec3> finer;
  auto midpoint = [&](uint32_t a, uint32_t b) {
    v.push_back(glm::normalize(v[a] + v[b]));
    return uint32_t(v.size() - 1);
  };
  for (const glm::uvec3& f : faces) {
    const uint32_t a = midpoint(f.x, f.y), b = midpoint(f.y, f.z), c = midpoint(f.z, f.x);
    finer.insert(finer.end(), {{f.x, a, c}, {f.y, b, a}, {f.z, c, b}, {a, b, c}});
  }
  const float le = 100.0f, rho = 0.5f;
  rdb::TraceRdbBuilder b;
  const uint32_t mat = b.material(Rgb(rho), Rgb(le));
  for (const vec3& p : v) {
    b.rdb.positionsM.push_back(p);
    b.rdb.normals.push_back(-p);  // smooth, inwards
  }
  for (const glm::uvec3& f : finer) {
    b.rdb.indices.insert(b.rdb.indices.end(), {f.x, f.z, f.y});  // reversed: the front faces inwards
    b.rdb.triangleMaterial.push_back(mat);
    b.rdb.emissiveTriangles.push_back(uint32_t(b.rdb.triangleMaterial.size() - 1));
  }
  ASSERT_EQ(b.rdb.triangleCount(), 80u);
  const float exact = kPiF * le / (1.0f - rho);
  Sensors s;
  for (const vec3& p :
       {vec3(0.0f), vec3(0.5f, 0.2f, -0.1f), vec3(0.0f, -0.8f, 0.0f), vec3(0.85f, 0.0f, 0.0f)}) {
    s.add(p, vec3(0, 1, 0), Rgb(exact));
    s.add(p, vec3(1, 0, 0), Rgb(exact));
  }
  const EstimateResult r = run(b.rdb, s, 1024);
  for (size_t i = 0; i < s.points.size(); ++i) {
    const IrradianceEstimate& e = r.points[i];
    std::cout << "[ estimate ] smooth sphere #" << i << ": " << e.meanLux.g << " ± " << e.stdErrorLux.g
              << " lux (bound " << exact << ")\n";
    EXPECT_LE(e.meanLux.g, exact + 4.0f * e.stdErrorLux.g) << i;
    EXPECT_GE(e.meanLux.g, 0.9f * exact) << i;
    EXPECT_LE(e.stdErrorLux.g, 0.01f * exact) << i;
  }
}

// Irradiance on a sensor facing up at (xs, 0, 0) from an emitting plane y = h facing down, x, z ∈ [−Z, Z]
// (Z = kHalfM), of radiance L(x): E = ∫∫ L(x) h² / r⁴ dz dx (both cosines h / r). Over z in closed form,
// ∫_{−Z}^{Z} dz / (c² + z²)² = Z / (c² (c² + Z²)) + atan(Z / c) / c³ with c² = (x − xs)² + h²; over x by the
// midpoint rule on 0.5 mm steps.
template <class F>
double stripIrradiance(F radiance, double xs, double h) {
  double sum = 0.0;
  constexpr double kStep = 5e-4;
  const double z = kHalfM;
  for (double x = -kHalfM + kStep / 2; x < kHalfM; x += kStep) {
    const double c2 = (x - xs) * (x - xs) + h * h;
    const double c = std::sqrt(c2);
    sum += radiance(x) * h * h * (z / (c2 * (c2 + z * z)) + std::atan(z / c) / (c2 * c)) * kStep;
  }
  return sum;
}

// A ceiling emitter (facing down) with an sRGB emission texture of texels 255 and 0 (linear 1 and 0) over an
// infinite plane: a sensor 1 m below, facing up, gets π L_e × the texture's mean (1/2) from a fine pattern.
// Stretched once over the plane with clamp-to-edge, the texture is 1 on x < −500 m, falls linearly to 0 at
// x = 500 m and is 0 beyond: sensors at x = ∓750 m get stripIrradiance of that profile. Emitter sampling
// chooses triangles by area × the mean emission and evaluates the texture at the sampled point. With partial
// coverage 0.25 (BLEND) the emitter gives a quarter.
TEST(IntegratorMaterials, EmissionTextureGivesItsMeanAndTexelIrradiance) {
  const Rgb le(1000.0f, 500.0f, 250.0f);
  for (bool fine : {true, false}) {
    rdb::TraceRdbBuilder b;
    const uint32_t tex = b.texture(2, 1, 1, {255, 0});
    const uint32_t mat = b.material(Rgb(0.0f), le);
    b.rdb.materials[mat].emissionTexture =
        slotOf(tex, fine ? rdb::TraceWrap::kRepeat : rdb::TraceWrap::kClampToEdge);
    texturedCeiling(b, 1.0f, mat, fine ? 2.0f * kHalfM / 0.05f : 1.0f);
    b.ground(kHalfM, 1, b.material(Rgb(0.0f)));
    Sensors s;
    if (fine) {
      s.add(vec3(0.0f), vec3(0, 1, 0), kPiF * le * 0.5f);
      s.add(vec3(7.3f, 0.0f, -2.0f), vec3(0, 1, 0), kPiF * le * 0.5f);
    } else {
      // u runs along x.
      auto profile = [](double x) { return std::clamp(0.5 - x / 1000.0, 0.0, 1.0); };
      for (float x : {-750.0f, 750.0f}) {
        s.add(vec3(x, 0.0f, 0.0f), vec3(0, 1, 0), le * float(stripIrradiance(profile, x, 1.0)));
      }
    }
    expectAgrees(fine ? "fine emission texture" : "clamped emission texel", run(b.rdb, s, 4096), s,
                 fine ? 0.03f : 0.01f);
    if (fine) {
      // Partial coverage 0.25 (BLEND): a quarter of the emission; the floor is black, so nothing else.
      b.rdb.materials[mat].alpha = rdb::TraceAlpha::kBlend;
      b.rdb.materials[mat].opacity = 0.25f;
      for (Rgb& e : s.exact) e *= 0.25f;
      expectAgrees("blended emission texture", run(b.rdb, s, 4096), s, 0.03f);
    }
  }
}

// Textures, blend coverage and shading normals keep the estimate a function of (point, sample) alone.
TEST(IntegratorMaterials, DeterministicAcrossThreadCounts) {
  rdb::TraceRdbBuilder b;
  const uint32_t tex =
      b.texture(2, 2, 4, {200, 30, 30, 255, 30, 200, 30, 60, 30, 30, 200, 255, 250, 250, 250, 128});
  const uint32_t ground = b.material(Rgb(0.0f));
  b.rdb.materials[ground].diffuseColor = Rgb(1.0f);
  b.rdb.materials[ground].diffuseTexture = slotOf(tex);
  const uint32_t fence = b.material(Rgb(0.0f));
  b.rdb.materials[fence].diffuseColor = Rgb(0.7f);
  b.rdb.materials[fence].diffuseTexture = slotOf(tex);
  b.rdb.materials[fence].alpha = rdb::TraceAlpha::kBlend;
  texturedGround(b, ground, 1000.0f);
  texturedCeiling(b, 2.0f, fence, 300.0f);
  b.uniformSky(Rgb(1000.0f));
  b.directionalLight(vec3(0.3f, 1.0f, 0.2f), Rgb(20000.0f));
  Sensors s;
  for (int i = 0; i < 16; ++i)
    s.add(vec3(float(i) * 0.37f, 1.0f, float(i % 4)), vec3(0, i % 2 ? 1 : -1, 0), Rgb(0));
  const EstimateResult one = run(b.rdb, s, 128, 1);
  const EstimateResult two = run(b.rdb, s, 128, 2);
  for (size_t i = 0; i < s.points.size(); ++i) {
    EXPECT_EQ(one.points[i].meanLux, two.points[i].meanLux) << i;
    EXPECT_GT(one.points[i].meanLux.g, 0.0f) << i;
  }
}

// A brushed-metal plate (the preset: white-ish uniform reflection, glossiness 0.35, anisotropy (0.6, 0.1))
// 6 cm square at the origin, facing +Y, its UVs' u along +x (so the tangent, the anisotropy's U axis, is +x)
// and v along +z; a point light 3 m above it; sensors 0.5 m above it facing down, which the light does not
// reach directly, measure the light the plate reflects onto that ceiling. The scene goes through the SDB
// and buildTraceRdb (tangents generated from the UVs), then the integrator.
//
// The exact irradiance at a sensor S: ∫ over the plate of I cos θi / |L − X|² · f(ωo, ωi) · cos θo cos θS /
// |S − X|² dA, by midpoint quadrature over the plate, with f = r D G2 / (4 cos θi cos θo) of the anisotropic
// GGX lobe written out here in the lobe's axes U = cos ρ T + sin ρ B, V = −sin ρ T + cos ρ B (T = +x, B =
// +z, ρ the rotation): D = 1 / (π α_U α_V h_N⁴ (1 + (h_U²/α_U² + h_V²/α_V²) / h_N²)²), Λ(ω) = (√(1 +
// (α_U² ω_U² + α_V² ω_V²) / ω_N²) − 1) / 2, G2 = 1 / (1 + Λ(ωo) + Λ(ωi)); α_U = α / a, α_V = α a, α = 0.35²,
// a = √(1 − 0.9 · 0.5) (base/ggx.h).
//
// The highlight's footprint on the ceiling is wider along U: 8 cm from the centre along U the irradiance is
// 1.79 times what it is 8 cm along V (the isotropic lobe: 1). A rotation texture of red 64/255 (ρ = 90.4°)
// turns it onto the other axis, read per hit.
TEST(IntegratorMaterials, BrushedMetalStretchesTheHighlightAlongItsWideAxis) {
  constexpr float kHalfPlateM = 0.03f;
  constexpr float kCeilingM = 0.5f;
  constexpr float kOffsetM = 0.08f;
  const vec3 lightM(0.0f, 3.0f, 0.0f);
  const float intensityCd = 1000.0f;
  const sdb::Material preset = sdb::findMaterialPreset("brushed-metal")->material;
  ASSERT_EQ(preset.reflectionModel, sdb::ReflectionModel::kUniform);
  ASSERT_EQ(maxComponent(preset.effective().diffuse), 0.0f);

  auto build = [&](bool rotationTexture) {
    sdb::Scene scene;
    sdb::Material m = preset;
    if (rotationTexture) {
      sdb::Texture t;
      t.name = "rotation";
      t.width = t.height = t.channels = 1;
      t.pixels = {64};
      m.anisotropyRotationTexture.texture = scene.addTexture(t).id;
    }
    sdb::Mesh plate;
    plate.name = "plate";
    plate.positions = {{-kHalfPlateM, 0, -kHalfPlateM},
                       {kHalfPlateM, 0, -kHalfPlateM},
                       {kHalfPlateM, 0, kHalfPlateM},
                       {-kHalfPlateM, 0, kHalfPlateM}};
    plate.normals.assign(4, vec3(0, 1, 0));
    plate.uv0 = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    plate.indices = {0, 2, 1, 0, 3, 2};
    plate.material = scene.addMaterial(m).id;
    scene.addNode({.name = "plate", .meshes = {scene.addMesh(plate).id}});
    sdb::Light light;
    light.type = sdb::LightType::kPoint;
    light.intensity = intensityCd;
    mat4 at(1.0f);
    at[3] = vec4(lightM, 1.0f);
    scene.addNode({.name = "light", .parentFromLocal = at, .light = scene.addLight(light).id});
    return rdb::buildTraceRdb(scene);
  };

  const float alpha = preset.reflectionGlossiness * preset.reflectionGlossiness;
  const float aspect = std::sqrt(1.0f - 0.9f * (preset.anisotropyU - preset.anisotropyV));
  const double alphaU = alpha / aspect, alphaV = alpha * aspect;
  const double r = preset.reflectionColor.g;
  auto exactLux = [&](const vec3& sensorM, double rotationRad) {
    const dvec3 u(std::cos(rotationRad), 0.0, std::sin(rotationRad));
    const dvec3 v(-std::sin(rotationRad), 0.0, std::cos(rotationRad));
    auto lambda = [&](const dvec3& w) {
      const double a = glm::dot(w, u), b = glm::dot(w, v);
      return 0.5 * (std::sqrt(1.0 + (alphaU * alphaU * a * a + alphaV * alphaV * b * b) / (w.y * w.y)) - 1.0);
    };
    constexpr int kCells = 120;
    const double cellM = 2.0 * kHalfPlateM / kCells;
    double sum = 0.0;
    for (int i = 0; i < kCells; ++i) {
      for (int j = 0; j < kCells; ++j) {
        const dvec3 x(-kHalfPlateM + (i + 0.5) * cellM, 0.0, -kHalfPlateM + (j + 0.5) * cellM);
        const dvec3 toLight = dvec3(lightM) - x, toSensor = dvec3(sensorM) - x;
        const double rl2 = glm::dot(toLight, toLight), rs2 = glm::dot(toSensor, toSensor);
        const dvec3 wi = toLight / std::sqrt(rl2), wo = toSensor / std::sqrt(rs2);
        const dvec3 h = glm::normalize(wi + wo);
        const double hu = glm::dot(h, u), hv = glm::dot(h, v), hn = h.y;
        const double e = 1.0 + (hu * hu / (alphaU * alphaU) + hv * hv / (alphaV * alphaV)) / (hn * hn);
        const double d = 1.0 / (kPi * alphaU * alphaV * hn * hn * hn * hn * e * e);
        const double f = r * d / (4.0 * wi.y * wo.y * (1.0 + lambda(wi) + lambda(wo)));
        sum += intensityCd * wi.y / rl2 * f * wo.y * wo.y / rs2;
      }
    }
    return sum * cellM * cellM;
  };

  const std::vector<vec3> sensors = {vec3(0.0f, kCeilingM, 0.0f), vec3(kOffsetM, kCeilingM, 0.0f),
                                     vec3(0.0f, kCeilingM, kOffsetM)};
  const std::vector<vec3> down(sensors.size(), vec3(0, -1, 0));
  double ratio[2] = {0.0, 0.0};
  for (bool textured : {false, true}) {
    const rdb::TraceRdb rdb = build(textured);
    ASSERT_EQ(rdb.tangents.size(), 4u);
    ASSERT_EQ(rdb.materials.size(), 2u);
    ASSERT_TRUE(rdb.materials[1].isAnisotropic());
    const double rotationRad = textured ? 2.0 * kPi * 64.0 / 255.0 : double(preset.anisotropyRotationRad);
    const EmbreeScene scene(rdb);
    const Integrator integrator(rdb, scene);
    EstimateSettings settings;
    settings.firstPassSamples = settings.maxSamples = 1u << 16;
    settings.replicates = 8;
    const EstimateResult result = estimateIrradiance(integrator, sensors, down, settings);
    for (size_t i = 0; i < sensors.size(); ++i) {
      const IrradianceEstimate& e = result.points[i];
      const double exact = exactLux(sensors[i], rotationRad);
      std::cout << "[ brushed  ] rotation " << rotationRad * 180.0 / kPi << "°, sensor (" << sensors[i].x
                << ", " << sensors[i].z << ") m: " << e.meanLux.g << " ± " << e.stdErrorLux.g
                << " lux (exact " << exact << ")\n";
      EXPECT_NEAR(e.meanLux.g, exact, 4.0 * e.stdErrorLux.g + 1e-3 * exact) << i << " " << textured;
      EXPECT_LE(e.stdErrorLux.g, 0.03 * exact) << i << " " << textured;
    }
    ratio[textured ? 1 : 0] = result.points[1].meanLux.g / result.points[2].meanLux.g;
    std::cout << "[ brushed  ] along x / along z at " << kOffsetM << " m: " << ratio[textured ? 1 : 0]
              << " (exact " << exactLux(sensors[1], rotationRad) / exactLux(sensors[2], rotationRad) << ")\n";
  }
  // Wider along U = +x without rotation, along +z with the quarter turn of the texture.
  EXPECT_GT(ratio[0], 1.6);
  EXPECT_LT(ratio[1], 1.0 / 1.6);
}

}  // namespace
}  // namespace fly::raytracer
