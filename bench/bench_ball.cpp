// fly-bench-ball: the measured materials' ball textures (raster/ball_texture.h; FLY §4) on the GL device at
// hand, printed with ratios against baselines measured in the same run (docs/architecture.md, "Performance
// figures"; results in docs/benchmarks.md).
//
// Part 1, one ball: a sphere of one measured BRDF (the car-paint model, or a MERL table made from it) under 5
// distant lights (FLY's case: "256x256 ball image for 5 point light sources"), alone and with Helsinki's sky as
// the environment term (sunlight mode: a 16² half-vector grid per texel), the ball made again at every call
// (the view turns by 0.01° between calls). Time per ball: GL_TIME_ELAPSED around Renderer::makeBalls (mean of
// ≥ 0.5 s of calls) where the queries mean something, else (Mesa's llvmpipe) glFinish after each call and
// the wall clock. Baseline ("× empty"): the same pass over the same texels with no light and no environment
// (the dispatch and the image writes alone).
//
// Part 2, a scene: 4 spheres of 4 measured materials (the metallic and pearl car-paint presets, two MERL
// tables) on a ground, 2·n² + 4 · 2·r·s triangles (≈ 300k), 4 lamps and Helsinki's clear sky with the sun, at
// the image size given (default 1920×1080). Frames per second of render + toneMap in simple and sunlight
// mode: with the camera still (the balls are reused) and turning 0.01° a frame (4 balls made every frame);
// GPU ms by GL_TIME_ELAPSED, else glFinish after every frame and the wall clock. Baseline ("× plain"): the
// same scene with the four materials analytic (no balls, no measured variant), timed the same way.
//
// Usage: fly-bench-ball [--size WxH] [--ball N] [--quick]   (--quick: 100k triangles, the ball only with
// lights). Headless (EGL); links neither OpenImageIO nor Embree (scripts/pack-gpu can carry it).
#include <epoxy/gl.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "../tests/support/helsinki_daylight.h"
#include "../tests/support/measured_tables.h"
#include "base/tone_map.h"
#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"

namespace fly::raster {
namespace {

using Clock = std::chrono::steady_clock;

sdb::CarPaintBrdf redPaint() {
  sdb::CarPaintBrdf p;
  p.baseAlbedo = Rgb(0.35f, 0.05f, 0.04f);
  p.lobes[0] = {Rgb(0.4f, 0.3f, 0.2f), 0.25f};
  p.lobes[1] = {Rgb(0.05f, 0.05f, 0.1f), 0.6f};
  p.coatIor = 1.5f;
  p.coatAlpha = 0.05f;
  return p;
}

// A UV sphere of `rings` × `segments` quads.
sdb::Mesh sphere(const vec3& centreM, float radiusM, int rings, int segments, sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "sphere";
  for (int i = 0; i <= rings; ++i) {
    const float theta = kPiF * float(i) / float(rings);
    for (int j = 0; j <= segments; ++j) {
      const float phi = 2.0f * kPiF * float(j) / float(segments);
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      m.positions.push_back(centreM + radiusM * n);
      m.normals.push_back(n);
    }
  }
  const uint32_t row = uint32_t(segments + 1);
  for (uint32_t i = 0; i < uint32_t(rings); ++i) {
    for (uint32_t j = 0; j < uint32_t(segments); ++j) {
      const uint32_t a = i * row + j, b = a + row;
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  m.material = material;
  return m;
}

// A ground of 2·cells² triangles (40 m square).
sdb::Mesh ground(uint32_t cells, sdb::MaterialId material) {
  sdb::Mesh m;
  m.name = "ground";
  for (uint32_t i = 0; i <= cells; ++i) {
    for (uint32_t j = 0; j <= cells; ++j) {
      m.positions.push_back(vec3(-20.0f + 40.0f * float(j) / float(cells), 0.0f, -20.0f + 40.0f * float(i) / float(cells)));
      m.normals.push_back(vec3(0, 1, 0));
    }
  }
  for (uint32_t i = 0; i < cells; ++i) {
    for (uint32_t j = 0; j < cells; ++j) {
      const uint32_t a = i * (cells + 1) + j, b = a + cells + 1;
      m.indices.insert(m.indices.end(), {a, b, a + 1, a + 1, b, b + 1});
    }
  }
  m.material = material;
  return m;
}

void addFiveDistantLights(sdb::Scene& s) {
  const vec3 dirs[5] = {{0.3f, 0.5f, 1.0f}, {-0.6f, 0.2f, 0.8f}, {0.5f, -0.4f, 0.7f}, {-0.2f, -0.7f, 0.6f}, {0.95f, 0.3f, 0.1f}};
  for (const vec3& d : dirs) {
    sdb::Light l;
    l.type = sdb::LightType::kDirectional;
    l.intensity = 800.0f;
    const vec3 to = glm::normalize(d);
    s.addNode({.name = "light", .parentFromLocal = sdb::lookAtTransform(vec3(0.0f), -to, std::abs(to.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0)),
               .light = s.addLight(l).id});
  }
}

View turned(const View& v, int step) {
  View t = v;
  t.worldFromCamera = glm::rotate(mat4(1.0f), float(degToRad(0.01 * (step % 2 ? 1 : -1))), vec3(0, 1, 0)) * v.worldFromCamera;
  return t;
}

struct Timing {
  double ms = 0.0;  // per call
  int calls = 0;
};

// Calls `work(i)` for ≥ `seconds` (and ≥ 3 calls) after 2 untimed ones: GL_TIME_ELAPSED per call where
// `gpuTimers`, else glFinish after each and the wall clock.
template <class Work>
Timing time(const Work& work, bool gpuTimers, double seconds) {
  work(0);
  work(1);
  glFinish();
  Timing t;
  const auto start = Clock::now();
  double gpuNs = 0.0;
  GLuint query = 0;
  if (gpuTimers) glCreateQueries(GL_TIME_ELAPSED, 1, &query);
  for (int i = 2;; ++i) {
    if (gpuTimers) glBeginQuery(GL_TIME_ELAPSED, query);
    work(i);
    if (gpuTimers) {
      glEndQuery(GL_TIME_ELAPSED);
      GLuint64 ns = 0;
      glGetQueryObjectui64v(query, GL_QUERY_RESULT, &ns);
      gpuNs += double(ns);
    } else {
      glFinish();
    }
    ++t.calls;
    if (t.calls >= 3 && std::chrono::duration<double>(Clock::now() - start).count() >= seconds) break;
  }
  if (gpuTimers) glDeleteQueries(1, &query);
  t.ms = gpuTimers ? gpuNs / 1e6 / t.calls : std::chrono::duration<double, std::milli>(Clock::now() - start).count() / t.calls;
  return t;
}

int run(int argc, char** argv) {
  uint32_t w = 1920, h = 1080, ballPx = 256;
  bool quick = false;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc && std::sscanf(argv[++i], "%ux%u", &w, &h) == 2 && w > 0 && h > 0) {
    } else if (std::strcmp(argv[i], "--ball") == 0 && i + 1 < argc && std::sscanf(argv[++i], "%u", &ballPx) == 1) {
    } else {
      std::fprintf(stderr, "usage: fly-bench-ball [--size WxH] [--ball N] [--quick]\n");
      return 2;
    }
  }
  const std::unique_ptr<GlContext> context = createHeadlessContext();
  const GlInfo& info = context->info();
  const bool gpuTimers = info.renderer.find("llvmpipe") == std::string::npos && info.renderer.find("softpipe") == std::string::npos;
  std::printf("fly-bench-ball: OpenGL %d.%d, %s, %s; timing by %s\n\n", info.major, info.minor, info.vendor.c_str(),
              info.renderer.c_str(), gpuTimers ? "GL_TIME_ELAPSED" : "glFinish and the wall clock");

  // Part 1: one ball.
  std::printf("one %u² ball, 5 distant lights\n%-10s %-12s %10s %9s %6s\n", ballPx, "BRDF", "environment", "ms/ball", "× empty", "calls");
  const sdb::CarPaintBrdf paint = redPaint();
  const std::shared_ptr<const sdb::MeasuredBrdf> table = fly::test::tableOf(paint);
  for (const bool isTable : {false, true}) {
    for (const bool sky : quick ? std::vector<bool>{false} : std::vector<bool>{false, true}) {
      auto ballScene = [&](bool lights) {
        sdb::Scene s;
        sdb::Material m;
        m.name = "paint";
        if (isTable) m.measuredBrdf = table; else m.carPaint = paint;
        const sdb::MaterialId id = s.addMaterial(m).id;
        s.addNode({.name = "ball", .meshes = {s.addMesh(sphere(vec3(0.0f), 1.0f, 8, 16, id)).id}});
        if (lights) addFiveDistantLights(s);
        if (sky && lights) fly::test::setHelsinkiClearSky(s, "2026-06-21T15:00");
        rdb::RasterRdb r = rdb::buildRasterRdb(s);
        if (!lights) r.ambient = {};
        return r;
      };
      const View view = framingView(Bounds3{vec3(-1.0f), vec3(1.0f)}, 1.0f);
      const RenderMode mode = sky ? RenderMode::kSunlight : RenderMode::kSimple;
      Timing t[2];
      for (int k = 0; k < 2; ++k) {
        rdb::RasterRdb r = ballScene(k == 1);
        if (k == 1 && !sky) r.ambient = {};  // lights only: FLY's case
        Renderer renderer;
        renderer.setBallSettings({ballPx, std::max(4u, ballPx / 4), 16});
        renderer.upload(r);
        t[k] = time([&](int i) { renderer.makeBalls(turned(view, i), k == 1 ? mode : RenderMode::kSimple); }, gpuTimers, gpuTimers ? 0.5 : 1.0);
      }
      std::printf("%-10s %-12s %10.3f %9.1f %6d\n", isTable ? "MERL table" : "car paint", sky ? "sky, 16²" : "none",
                  t[1].ms, t[1].ms / t[0].ms, t[1].calls);
    }
  }

  // Part 2: the scene.
  const uint32_t cells = quick ? 150 : 257;
  const int rings = quick ? 60 : 100, segments = quick ? 120 : 210;
  auto makeScene = [&](bool measured) {
    sdb::Scene s;
    sdb::Material g;
    g.name = "ground";
    g.diffuseColor = Rgb(0.3f);
    const sdb::MaterialId groundId = s.addMaterial(g).id;
    s.addNode({.name = "ground", .meshes = {s.addMesh(ground(cells, groundId)).id}});
    std::vector<sdb::Material> paints;
    paints.push_back(sdb::findMaterialPreset("metallic-car-paint")->material);
    paints.push_back(sdb::findMaterialPreset("pearl-car-paint")->material);
    sdb::Material t1 = sdb::findMaterialPreset("car-paint")->material;
    t1.name = "table-red";
    t1.measuredBrdf = table;
    paints.push_back(t1);
    sdb::Material t2 = t1;
    t2.name = "table-silver";
    t2.measuredBrdf = fly::test::tableOf(*sdb::findMaterialPreset("metallic-car-paint")->material.carPaint);
    paints.push_back(t2);
    for (size_t k = 0; k < paints.size(); ++k) {
      sdb::Material m = paints[k];
      if (!measured) {
        m.carPaint.reset();
        m.measuredBrdf.reset();
      }
      const sdb::MaterialId id = s.addMaterial(m).id;
      const vec3 centre(-4.5f + 3.0f * float(k), 1.0f, 0.0f);
      s.addNode({.name = "sphere", .meshes = {s.addMesh(sphere(centre, 1.0f, rings, segments, id)).id}});
    }
    const vec3 lamps[4] = {{-6.0f, 4.0f, 4.0f}, {6.0f, 3.0f, 4.0f}, {0.0f, 5.0f, -3.0f}, {0.0f, 2.0f, 6.0f}};
    for (const vec3& p : lamps) {
      sdb::Light l;
      l.intensity = 2000.0f;
      s.addNode({.name = "lamp", .parentFromLocal = glm::translate(mat4(1.0f), p), .light = s.addLight(l).id});
    }
    fly::test::setHelsinkiClearSky(s, "2026-06-21T15:00");
    return s;
  };
  std::printf("\n%-9s %-9s %-8s %9s %9s %8s %6s\n", "triangles", "mode", "camera", "ms/frame", "fps", "× plain", "balls");
  const rdb::RasterRdb plain = rdb::buildRasterRdb(makeScene(false));
  const rdb::RasterRdb measured = rdb::buildRasterRdb(makeScene(true));
  View view;
  view.worldFromCamera = sdb::lookAtTransform(vec3(0.0f, 4.0f, 10.0f), vec3(0.0f, 0.8f, 0.0f), vec3(0, 1, 0));
  view.yfovRad = 0.8f;
  view.znearM = 0.1f;
  view.zfarM = 200.0f;
  for (const RenderMode mode : {RenderMode::kSimple, RenderMode::kSunlight}) {
    Renderer base;
    base.upload(plain);
    const Timing tPlain = time([&](int) { base.render(view, mode, w, h); base.toneMap({ToneOperator::kFilmic, 12.0}); }, gpuTimers, 1.0);
    std::printf("%-9zu %-9s %-8s %9.3f %9.1f %8s %6s\n", plain.triangleCount(), renderModeName(mode), "plain", tPlain.ms, 1000.0 / tPlain.ms, "1.00", "-");
    for (const bool turning : {false, true}) {
      Renderer renderer;
      renderer.setBallSettings({ballPx, std::max(4u, ballPx / 4), 16});
      renderer.upload(measured);
      const int before = renderer.stats().ballsMade;
      const Timing t = time([&](int i) {
        renderer.render(turning ? turned(view, i) : view, mode, w, h);
        renderer.toneMap({ToneOperator::kFilmic, 12.0});
      }, gpuTimers, 1.0);
      const double ballsPerFrame = double(renderer.stats().ballsMade - before) / double(t.calls + 2);
      std::printf("%-9zu %-9s %-8s %9.3f %9.1f %8.2f %6.1f\n", measured.triangleCount(), renderModeName(mode),
                  turning ? "turning" : "still", t.ms, 1000.0 / t.ms, t.ms / tPlain.ms, ballsPerFrame);
    }
  }
  return 0;
}

}  // namespace
}  // namespace fly::raster

int main(int argc, char** argv) {
  try {
    return fly::raster::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "fly-bench-ball: %s\n", e.what());
    return 1;
  }
}
