// fly-bench-raster: frames per second of the OpenGL engine in each mode, as a ratio against a baseline
// measured in the same run, the same way (docs/architecture.md, "Performance figures"; results in docs/benchmarks.md):
// the empty frame, i.e. clearing depth, filling the float image with the (black) background and running the
// tone-map pass over it, which every frame also pays.
//
// Scenes: a 40 m square ground of 2·n² triangles with a 4 × 4 array of 1 m boxes, sized to 100k, 300k and 1M
// triangles; a 400 cd lamp; Helsinki at 2026-06-21 15:00 with a clear sky and the sun; synthetic vertex light
// maps on every mesh. Headless (EGL); links neither OpenImageIO nor Embree, so scripts/pack-gpu can
// carry it to a GPU machine.
//
// A frame is Renderer::render (clear, scene, sky) + Renderer::toneMap into the sRGB8 target; nothing is read
// back. After 3 untimed frames (they compile the programs), each scene and mode is timed three ways:
//   pipelined  as an interactive viewer runs: frames are submitted back to back with at most 2 in flight (a
//              fence after each frame; before frame i is submitted the CPU waits for frame i − 2's fence),
//              until ≥ 1 s and ≥ 3 frames have passed, then one glFinish. ms/frame = wall-clock time from the
//              first submission to the end of that glFinish, divided by the frames; fps is its inverse, and
//              "× base" divides it by the empty frame's, timed the same way.
//   CPU        wall-clock time spent inside the render and toneMap calls of the pipelined loop, per frame
//              (what the application and the driver cost the CPU; excludes the fence waits).
//   GPU        a separate pipelined loop (≥ 0.5 s) with a GL_TIME_ELAPSED query around the render call
//              ("scene") and one around the toneMap call ("tone"); the mean over its frames. Only where the
//              queries are meaningful: not on Mesa's llvmpipe/softpipe, where "-" is
//              printed.
//   finish     latency: glFinish after every frame, wall-clock per frame (≥ 0.5 s, ≥ 3 frames); the way the
//              first version of this benchmark timed frames, kept for comparison.
// "mean L" is the mean luminance (cd/m²) of the last frame's float image, to compare devices' output.
//
// Textured: the 300k scene (the 100k one with --quick) again with material textures, each mode timed the same
// way, with its ratio against the untextured scene's row of that mode ("× plain"): the ground's base colour
// (2048², repeated 8 × 8 times over it) and normal map (2048²), the boxes' base colour and emission (1024²
// each), every one RGBA8 with a full mip chain and anisotropic filtering; procedural (value noise and
// stripes), so nothing is read from disk. Light-map mode samples the base colour and emission textures; the
// Phong modes the normal map too. Then light-map mode again with anisotropic filtering capped at 8, 4 and 1
// samples (rows "lm-afN").
//
// Sun shadows (raster/sun_shadows.h): sunlight mode without light maps, so that the Phong's sun term is drawn
// and shadowed, timed as above, each scene three ways: shadows off (the baseline of "× off"), shadow volumes of
// the triangles the visibility map (1024² unless --shadow-map N) keeps ("vismap"), and the classic method's
// volumes of every sun-facing triangle ("classic"); with the volumes' size (kept triangles, silhouette edges, extruded sides) and fill
// (fragments they rasterise over the 1080p frame with neither depth nor stencil test, GL_SAMPLES_PASSED). Scenes:
// the 300k and 1M boxes-on-a-ground scenes above; a generated car (a closed body of subdivided boxes with
// seats, a dashboard with 64 knobs and a steering column inside, wheels below: 280k triangles); a generated
// office (a closed room with window gaps and 80 desks and chairs, ≈ 300k triangles, seen from inside); and the
// repository's scenes/house (walls, roof, furniture, glass). "rebuild ms": a visibility map and volume rebuild,
// i.e. what a frame costs more when the sun moves every frame (each frame with glFinish, wall clock, against
// frames with a still sun).
//
// Post-processing (--post): the 300k scene (100k with --quick) in simple mode without and with the ambient
// occlusion (raster/ambient_occlusion.h, R = 0.5 m), and in sunlight mode without and with bloom (raster/bloom.h,
// strength 0.05), each with its ratio against the same scene and mode without it ("× plain").
//
// Reflections (--reflectors): the 300k scene (100k with --quick) with two planar reflectors and a cube-map one
// (addReflectorMeshes): grey ("g", the baseline of "× grey"), sharp mirrors ("m"), glossy mirrors ("gm",
// glossiness 0.2, their passes at the automatic scale, then "gm-full" with them at the image's resolution:
// Renderer::setGlossyReflectionScale), sharp mirrors with reflection fog ("fm") and anisotropic glossy mirrors
// ("am", brushed: blurred along their wide axis), each mode with its ratios against the grey and sharp rows.
//
// Anisotropic reflection (--anisotropic): the 300k scene (100k with --quick) with the reflectors' wall, pool
// and ball of the brushed-metal preset, isotropic (U = V, per vertex) and anisotropic (per fragment with
// tangents: the anisotropic lamp and sun lobes, four environment reads), each mode with its ratio against the
// isotropic row ("× plain").
//
// The room probe (--probe): the 300k scene (100k with --quick), whose materials reflect an environment, in
// light-map and sunlight modes without the probe (the baseline of "× plain"), with it from a still eye (captured
// once), and with the eye moving 0.3 m every frame (captured every frame: a walkthrough's worst case).
//
// Usage: fly-bench-raster [--size WxH] [--quick | --textured | --reflectors | --anisotropic | --post | --probe |
//   --shadows [--shadow-map N]] [--house PATH]
//   default 1920x1080; --quick: the 100k scene only (and the shadow scenes but the 1M one); --textured: the
//   300k scene only, plain and textured; --shadows: the shadow section only; --house: scenes/house/house.json
//   (relative to the working directory) by default, skipped when missing
#include <epoxy/gl.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <stdexcept>
#include <limits>
#include <string>
#include <vector>

#include "base/tone_map.h"
#include "../tests/support/helsinki_daylight.h"
#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "rdb/raster_rdb.h"
#include "sdb/camera.h"
#include "sdb/material_presets.h"
#include "sdb/scene.h"
#include "sdb/scene_load.h"

namespace fly::raster {
namespace {

using Clock = std::chrono::steady_clock;

// A size × size RGB texture of smooth value noise (a lattice of random values every 16 texels, bilinear),
// tinted by `tint`; with `normalMap`, the noise taken as a height field and encoded as tangent-space normals.
sdb::TextureId addNoiseTexture(sdb::Scene& s, int size, const Rgb& tint, bool normalMap, uint32_t seed) {
  const int cell = 16, lattice = size / cell + 2;
  std::vector<float> grid(size_t(lattice) * size_t(lattice));
  for (float& g : grid) {
    seed = seed * 1664525u + 1013904223u;  // Numerical Recipes' LCG
    g = float(seed >> 8) / float(1u << 24);
  }
  auto height = [&](int x, int y) {
    const float fx = float(x) / cell, fy = float(y) / cell;
    const int ix = int(fx), iy = int(fy);
    const float tx = fx - float(ix), ty = fy - float(iy);
    auto at = [&](int i, int j) { return grid[size_t(j) * size_t(lattice) + size_t(i)]; };
    return (1 - ty) * ((1 - tx) * at(ix, iy) + tx * at(ix + 1, iy)) +
           ty * ((1 - tx) * at(ix, iy + 1) + tx * at(ix + 1, iy + 1));
  };
  sdb::Texture t;
  t.name = normalMap ? "noise-normal" : "noise";
  t.sourcePath = "<generated>";
  t.width = t.height = size;
  t.channels = 3;
  t.pixels.resize(size_t(size) * size_t(size) * 3);
  for (int y = 0; y < size; ++y) {
    for (int x = 0; x < size; ++x) {
      uint8_t* p = &t.pixels[(size_t(y) * size_t(size) + size_t(x)) * 3];
      const float h = height(x, y);
      if (normalMap) {
        const float dx = 4.0f * (height(std::min(x + 1, size - 1), y) - h);
        const float dy = 4.0f * (height(x, std::min(y + 1, size - 1)) - h);
        const vec3 n = glm::normalize(vec3(-dx, dy, 1.0f));
        for (int c = 0; c < 3; ++c) p[c] = uint8_t(std::lround((n[c] * 0.5f + 0.5f) * 255.0f));
      } else {
        for (int c = 0; c < 3; ++c) p[c] = uint8_t(std::lround(255.0f * std::clamp(tint[c] * (0.5f + h), 0.0f, 1.0f)));
      }
    }
  }
  return s.addTexture(std::move(t)).id;
}

// With `textured`, the materials read the textures described at the top.
sdb::Scene makeScene(uint32_t cells, bool textured = false) {
  sdb::Scene s;
  sdb::Material ground;
  ground.diffuseColor = Rgb(0.5f);
  sdb::Material paint;
  paint.diffuseColor = Rgb(0.7f, 0.6f, 0.5f);
  if (textured) {
    ground.diffuseColor = Rgb(1.0f);
    ground.diffuseTexture.texture = addNoiseTexture(s, 2048, Rgb(0.6f, 0.55f, 0.45f), false, 1);
    ground.diffuseTexture.transform.scale = vec2(8.0f);
    ground.bumpTexture.texture = addNoiseTexture(s, 2048, Rgb(1.0f), true, 2);
    ground.bumpTexture.transform.scale = vec2(8.0f);
    paint.diffuseColor = Rgb(1.0f);
    paint.diffuseTexture.texture = addNoiseTexture(s, 1024, Rgb(0.8f, 0.6f, 0.5f), false, 3);
    paint.emissionLuminance = Rgb(50.0f);
    paint.emissionTexture.texture = addNoiseTexture(s, 1024, Rgb(1.0f, 0.8f, 0.3f), false, 4);
  }
  const sdb::MaterialId groundId = s.addMaterial(ground).id;
  const sdb::MaterialId paintId = s.addMaterial(paint).id;
  sdb::Mesh g;
  constexpr float kHalfM = 20.0f;
  for (uint32_t j = 0; j <= cells; ++j) {
    for (uint32_t i = 0; i <= cells; ++i) {
      g.positions.push_back(vec3(-kHalfM + 2 * kHalfM * float(i) / float(cells), 0.0f,
                                 -kHalfM + 2 * kHalfM * float(j) / float(cells)));
      g.normals.push_back(vec3(0, 1, 0));
      if (textured) g.uv0.push_back(vec2(float(i) / float(cells), float(j) / float(cells)));
    }
  }
  for (uint32_t j = 0; j < cells; ++j) {
    for (uint32_t i = 0; i < cells; ++i) {
      const uint32_t a = j * (cells + 1) + i, b = a + 1, c = a + cells + 1, d = c + 1;
      g.indices.insert(g.indices.end(), {a, c, b, b, c, d});  // counter-clockwise seen from +Y
    }
  }
  g.material = groundId;
  s.addNode({.name = "ground", .meshes = {s.addMesh(g).id}});
  sdb::Mesh box;
  for (int n = 0; n < 3; ++n) {
    for (int side = 0; side < 2; ++side) {
      const int u = side ? (n + 1) % 3 : (n + 2) % 3, v = side ? (n + 2) % 3 : (n + 1) % 3;
      vec3 normal(0.0f);
      normal[n] = side ? 1.0f : -1.0f;
      const uint32_t first = uint32_t(box.positions.size());
      for (int k = 0; k < 4; ++k) {
        vec3 p(0.0f);
        p[n] = float(side);
        p[u] = (k == 1 || k == 2) ? 1.0f : 0.0f;
        p[v] = k >= 2 ? 1.0f : 0.0f;
        box.positions.push_back(p - vec3(0.5f, 0.0f, 0.5f));
        box.normals.push_back(normal);
        if (textured) box.uv0.push_back(vec2(p[u], 1.0f - p[v]));
      }
      box.indices.insert(box.indices.end(), {first, first + 1, first + 2, first, first + 2, first + 3});
    }
  }
  box.material = paintId;
  const sdb::MeshId boxId = s.addMesh(box).id;
  for (int bz = 0; bz < 4; ++bz) {
    for (int bx = 0; bx < 4; ++bx) {
      s.addNode({.name = "box",
                 .parentFromLocal =
                     frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1),
                                    vec3(-13.5f + 9.0f * float(bx), 0.0f, -13.5f + 9.0f * float(bz))),
                 .meshes = {boxId}});
    }
  }
  sdb::Light lamp;
  lamp.intensity = 400.0f;
  s.addNode({.name = "lamp",
             .parentFromLocal = frameTransform(vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1), vec3(0, 3, 0)),
             .light = s.addLight(lamp).id});
  sdb::Camera cam;
  cam.name = "overview";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(-22, 12, 26), vec3(0, 0, 0), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T15:00");
  return s;
}

// Two flat meshes in makeScene's scene, a 40 × 8 m wall at z = −20.5 facing the camera and an 8 × 6 m pool on
// the ground, and a curved one, a 1.5 m sphere (48 × 96 quads) on the ground between them, of material `id`.
void addReflectorMeshes(sdb::Scene& s, sdb::MaterialId id) {
  auto quad = [&](const vec3& corner, const vec3& u, const vec3& v) {
    sdb::Mesh q;
    q.positions = {corner, corner + u, corner + u + v, corner + v};
    q.normals.assign(4, glm::normalize(glm::cross(u, v)));
    q.indices = {0, 1, 2, 0, 2, 3};
    q.material = id;
    return s.addMesh(q).id;
  };
  s.addNode({.name = "wall", .meshes = {quad(vec3(-20, 0, -20.5f), vec3(40, 0, 0), vec3(0, 8, 0))}});
  s.addNode({.name = "pool", .meshes = {quad(vec3(-4, 0.01f, 4), vec3(8, 0, 0), vec3(0, 0, -6))}});
  // A UV sphere: (rings + 1) × (segments + 1) vertices, unit normals from the centre.
  sdb::Mesh ball;
  constexpr int kRings = 48, kSegments = 96;
  const vec3 centre(-6.0f, 1.5f, 2.0f);
  for (int i = 0; i <= kRings; ++i) {
    const float theta = float(kPi) * float(i) / kRings;
    for (int j = 0; j <= kSegments; ++j) {
      const float phi = 2.0f * float(kPi) * float(j) / kSegments;
      const vec3 n(std::sin(theta) * std::cos(phi), std::cos(theta), -std::sin(theta) * std::sin(phi));
      ball.positions.push_back(centre + 1.5f * n);
      ball.normals.push_back(n);
    }
  }
  for (uint32_t i = 0; i < uint32_t(kRings); ++i) {
    for (uint32_t j = 0; j < uint32_t(kSegments); ++j) {
      const uint32_t a = i * (kSegments + 1) + j, b = a + kSegments + 1;
      if (i > 0) ball.indices.insert(ball.indices.end(), {a, b, a + 1});
      if (i + 1 < uint32_t(kRings)) ball.indices.insert(ball.indices.end(), {a + 1, b, b + 1});
    }
  }
  ball.material = id;
  s.addNode({.name = "ball", .meshes = {s.addMesh(ball).id}});
}

// addReflectorMeshes as two flat reflectors and a curved one: mirrors (uniform reflection 0.9, glossiness 0:
// two planar reflectors and one cube map; or glossiness 0.2, the widest lobe the automatic choice takes for a
// mirror: the planar images blurred by it, docs/reflections.md; `anisotropic`: that lobe stretched by the
// brushed-metal preset's anisotropy U 0.6, V 0.1; with a finite fogDistanceM, sharp mirrors with reflection
// fog of that distance and a dark grey-green colour) or, for the baseline, the same meshes of a plain grey.
void addReflectors(sdb::Scene& s, bool mirrors, float glossiness = 0.0f,
                   float fogDistanceM = std::numeric_limits<float>::infinity(), bool anisotropic = false) {
  sdb::Material m;
  m.name = mirrors ? "mirror" : "grey";
  m.diffuseColor = Rgb(mirrors ? 0.05f : 0.5f);
  if (mirrors) {
    m.reflectionColor = Rgb(0.9f);
    m.reflectionModel = sdb::ReflectionModel::kUniform;
    m.reflectionGlossiness = glossiness;
    if (anisotropic) {  // brushed: the brushed-metal preset's U and V
      m.anisotropyU = 0.6f;
      m.anisotropyV = 0.1f;
    }
    m.reflectionFogDistanceM = fogDistanceM;
    m.reflectionFogColor = Rgb(0.04f, 0.06f, 0.05f);
  }
  addReflectorMeshes(s, s.addMaterial(m).id);
}

// A box from `lo` to `hi` with every face split into k × k quads (vertices shared within a face; the faces'
// edge vertices coincide, so the shadow edges weld them into a closed mesh), faces pointing out.
sdb::Mesh subdividedBox(const vec3& lo, const vec3& hi, uint32_t k, sdb::MaterialId material) {
  sdb::Mesh m;
  for (int n = 0; n < 3; ++n) {
    for (int side = 0; side < 2; ++side) {
      const int u = side ? (n + 1) % 3 : (n + 2) % 3, v = side ? (n + 2) % 3 : (n + 1) % 3;
      vec3 normal(0.0f);
      normal[n] = side ? 1.0f : -1.0f;
      const uint32_t first = uint32_t(m.positions.size());
      for (uint32_t j = 0; j <= k; ++j) {
        for (uint32_t i = 0; i <= k; ++i) {
          vec3 p;
          p[n] = side ? hi[n] : lo[n];
          p[u] = lo[u] + (hi[u] - lo[u]) * float(i) / float(k);
          p[v] = lo[v] + (hi[v] - lo[v]) * float(j) / float(k);
          m.positions.push_back(p);
          m.normals.push_back(normal);
        }
      }
      for (uint32_t j = 0; j < k; ++j) {
        for (uint32_t i = 0; i < k; ++i) {
          const uint32_t a = first + j * (k + 1) + i, b = a + 1, c = a + k + 1, d = c + 1;
          m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
        }
      }
    }
  }
  m.material = material;
  return m;
}

// The generated car of the shadow section (see the top).
sdb::Scene makeCar() {
  sdb::Scene s;
  sdb::Material paint, trim, ground;
  paint.diffuseColor = Rgb(0.6f, 0.1f, 0.1f);
  trim.diffuseColor = Rgb(0.2f);
  ground.diffuseColor = Rgb(0.4f);
  const sdb::MaterialId paintId = s.addMaterial(paint).id, trimId = s.addMaterial(trim).id,
                        groundId = s.addMaterial(ground).id;
  auto add = [&](const char* name, const sdb::Mesh& m) { s.addNode({.name = name, .meshes = {s.addMesh(m).id}}); };
  add("ground", subdividedBox(vec3(-20.0f, -0.1f, -20.0f), vec3(20.0f, 0.0f, 20.0f), 1, groundId));
  add("body", subdividedBox(vec3(-2.2f, 0.3f, -0.9f), vec3(2.2f, 1.1f, 0.9f), 60, paintId));
  add("cabin", subdividedBox(vec3(-1.2f, 1.1f, -0.8f), vec3(1.3f, 1.7f, 0.8f), 60, paintId));
  for (float z : {-0.45f, 0.15f}) {
    for (float x : {-0.9f, 0.2f}) add("seat", subdividedBox(vec3(x, 0.4f, z), vec3(x + 0.5f, 1.4f, z + 0.5f), 40, trimId));
  }
  add("dashboard", subdividedBox(vec3(1.4f, 0.5f, -0.8f), vec3(1.9f, 1.0f, 0.8f), 40, trimId));
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 8; ++i) {
      const vec3 lo(1.3f, 0.55f + 0.05f * float(j), -0.7f + 0.15f * float(i));
      add("knob", subdividedBox(lo, lo + vec3(0.08f, 0.03f, 0.03f), 8, trimId));
    }
  }
  add("column", subdividedBox(vec3(1.0f, 0.6f, -0.45f), vec3(1.4f, 1.0f, -0.35f), 20, trimId));
  for (float z : {-0.95f, 0.75f}) {
    for (float x : {-1.7f, 1.1f}) add("wheel", subdividedBox(vec3(x, 0.0f, z), vec3(x + 0.6f, 0.6f, z + 0.2f), 30, trimId));
  }
  sdb::Camera cam;
  cam.name = "side";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(-7.0f, 3.0f, 6.0f), vec3(0.0f, 0.6f, 0.0f), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T15:00");
  return s;
}

// The generated office of the shadow section: a 30 × 20 m room (floor and roof slabs, thick walls as closed
// boxes, the south wall (−Z) of six piers with five window gaps between them) with 10 × 8 desks and chairs
// inside, ≈ 300k triangles: an interior whose furniture the sun reaches only through the windows.
sdb::Scene makeOffice() {
  sdb::Scene s;
  sdb::Material wall, desk, ground;
  wall.diffuseColor = Rgb(0.7f);
  desk.diffuseColor = Rgb(0.4f, 0.3f, 0.2f);
  ground.diffuseColor = Rgb(0.4f);
  const sdb::MaterialId wallId = s.addMaterial(wall).id, deskId = s.addMaterial(desk).id,
                        groundId = s.addMaterial(ground).id;
  auto add = [&](const char* name, const sdb::Mesh& m) { s.addNode({.name = name, .meshes = {s.addMesh(m).id}}); };
  add("ground", subdividedBox(vec3(-60.0f, -0.3f, -60.0f), vec3(60.0f, -0.2f, 60.0f), 1, groundId));
  add("floor", subdividedBox(vec3(-15.0f, -0.2f, -10.0f), vec3(15.0f, 0.0f, 10.0f), 40, wallId));
  add("roof", subdividedBox(vec3(-15.0f, 3.0f, -10.0f), vec3(15.0f, 3.3f, 10.0f), 40, wallId));
  add("north", subdividedBox(vec3(-15.0f, 0.0f, 9.7f), vec3(15.0f, 3.0f, 10.0f), 30, wallId));
  add("west", subdividedBox(vec3(-15.0f, 0.0f, -10.0f), vec3(-14.7f, 3.0f, 10.0f), 30, wallId));
  add("east", subdividedBox(vec3(14.7f, 0.0f, -10.0f), vec3(15.0f, 3.0f, 10.0f), 30, wallId));
  for (int k = 0; k < 6; ++k) {
    const float x = -15.0f + 5.9f * float(k);
    add("pier", subdividedBox(vec3(x, 0.0f, -10.0f), vec3(x + 1.2f, 3.0f, -9.7f), 12, wallId));
  }
  for (int j = 0; j < 8; ++j) {
    for (int i = 0; i < 10; ++i) {
      const vec3 at(-13.0f + 2.8f * float(i), 0.0f, -8.0f + 2.2f * float(j));
      add("desk", subdividedBox(at + vec3(0.0f, 0.7f, 0.0f), at + vec3(1.6f, 0.75f, 0.8f), 10, deskId));
      add("chair", subdividedBox(at + vec3(0.5f, 0.0f, 1.0f), at + vec3(1.0f, 0.9f, 1.5f), 10, deskId));
    }
  }
  sdb::Camera cam;
  cam.name = "inside";
  s.addNode({.name = "eye",
             .parentFromLocal = sdb::lookAtTransform(vec3(-12.0f, 1.6f, 8.5f), vec3(4.0f, 0.6f, -6.0f), vec3(0, 1, 0)),
             .camera = s.addCamera(cam).id});
  fly::test::setHelsinkiClearSky(s, "2026-06-21T13:00");
  return s;
}

rdb::LightMapStore syntheticLightMaps(const rdb::RasterRdb& r) {
  rdb::LightMapStore store;
  for (const rdb::RasterMesh& m : r.meshes) {
    rdb::MeshLightMap map{m.sdbNodeId, m.sdbMeshId, {}, {}};
    for (uint32_t v = m.firstVertex; v < m.firstVertex + m.vertexCount; ++v) {
      map.frontLux.push_back(Rgb(20000.0f + 500.0f * r.positionsM[v].x));
    }
    store.meshes.push_back(std::move(map));
  }
  return store;
}

struct FrameTimes {
  double pipelinedMs = 0.0;  // wall clock per frame, ≤ 2 frames in flight
  double cpuMs = 0.0;        // inside render() + toneMap(), per frame
  double gpuSceneMs = NAN;   // GL_TIME_ELAPSED of render(); NaN where not meaningful
  double gpuToneMs = NAN;    // GL_TIME_ELAPSED of toneMap()
  double finishMs = 0.0;     // glFinish after every frame, wall clock per frame
  double meanLuminanceCdM2 = 0.0;
};

// The scene's RasterRdb with syntheticLightMaps, so that every mode runs.
rdb::RasterRdb lightMapped(const sdb::Scene& scene) {
  const rdb::LightMapStore maps = syntheticLightMaps(rdb::buildRasterRdb(scene));
  return rdb::buildRasterRdb(scene, &maps);
}

double secondsSince(Clock::time_point t) {
  return std::chrono::duration<double>(Clock::now() - t).count();
}

void waitFor(GLsync fence) {
  for (;;) {
    const GLenum status = glClientWaitSync(fence, GL_SYNC_FLUSH_COMMANDS_BIT, 1'000'000'000);
    if (status == GL_ALREADY_SIGNALED || status == GL_CONDITION_SATISFIED) break;
    if (status == GL_WAIT_FAILED) throw std::runtime_error("glClientWaitSync failed");
  }
  glDeleteSync(fence);
}

// With `other`, frames alternate between `view` and *other (a moving eye).
FrameTimes timeFrames(Renderer& renderer, const View& view, RenderMode mode, uint32_t w, uint32_t h,
                      bool gpuTimers, const View* other = nullptr) {
  const ToneMapSettings tone{ToneOperator::kFilmic, 12.0};
  int frameIndex = 0;
  auto viewOfFrame = [&]() -> const View& { return other && (frameIndex++ & 1) ? *other : view; };
  auto frame = [&] {
    renderer.render(viewOfFrame(), mode, w, h);
    renderer.toneMap(tone);
  };
  for (int i = 0; i < 3; ++i) frame();
  renderer.finish();
  FrameTimes t;

  constexpr int kInFlight = 2;
  {
    std::array<GLsync, kInFlight> fences{};
    double cpuS = 0.0;
    int frames = 0;
    const Clock::time_point start = Clock::now();
    do {
      GLsync& slot = fences[size_t(frames % kInFlight)];
      if (slot) waitFor(slot);
      const Clock::time_point submit = Clock::now();
      frame();
      cpuS += secondsSince(submit);
      slot = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
      ++frames;
    } while (frames < 3 || secondsSince(start) < 1.0);
    renderer.finish();
    t.pipelinedMs = 1e3 * secondsSince(start) / frames;
    t.cpuMs = 1e3 * cpuS / frames;
    for (GLsync f : fences) glDeleteSync(f);
  }

  if (gpuTimers) {
    std::array<GLsync, kInFlight> fences{};
    std::array<std::array<GLuint, 2>, kInFlight> queries{};
    for (auto& q : queries) glCreateQueries(GL_TIME_ELAPSED, 2, q.data());
    double sceneNs = 0.0, toneNs = 0.0;
    int frames = 0, measured = 0;
    auto collect = [&](size_t slot) {
      waitFor(fences[slot]);
      fences[slot] = nullptr;
      GLuint64 scene = 0, toneMap = 0;
      glGetQueryObjectui64v(queries[slot][0], GL_QUERY_RESULT, &scene);
      glGetQueryObjectui64v(queries[slot][1], GL_QUERY_RESULT, &toneMap);
      sceneNs += double(scene);
      toneNs += double(toneMap);
      ++measured;
    };
    const Clock::time_point start = Clock::now();
    do {
      const size_t slot = size_t(frames % kInFlight);
      if (fences[slot]) collect(slot);
      glBeginQuery(GL_TIME_ELAPSED, queries[slot][0]);
      renderer.render(viewOfFrame(), mode, w, h);
      glEndQuery(GL_TIME_ELAPSED);
      glBeginQuery(GL_TIME_ELAPSED, queries[slot][1]);
      renderer.toneMap(tone);
      glEndQuery(GL_TIME_ELAPSED);
      fences[slot] = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
      ++frames;
    } while (frames < 3 || secondsSince(start) < 0.5);
    for (size_t slot = 0; slot < kInFlight; ++slot) {
      if (fences[slot]) collect(slot);
    }
    for (auto& q : queries) glDeleteQueries(2, q.data());
    t.gpuSceneMs = 1e-6 * sceneNs / measured;
    t.gpuToneMs = 1e-6 * toneNs / measured;
  }

  {
    int frames = 0;
    const Clock::time_point start = Clock::now();
    do {
      frame();
      renderer.finish();
      ++frames;
    } while (frames < 3 || secondsSince(start) < 0.5);
    t.finishMs = 1e3 * secondsSince(start) / frames;
  }

  const std::vector<float> rgb = renderer.luminanceRgb();
  double sum = 0.0;
  for (size_t i = 0; i + 2 < rgb.size(); i += 3) sum += luminance(Rgb(rgb[i], rgb[i + 1], rgb[i + 2]));
  t.meanLuminanceCdM2 = sum / double(std::max<size_t>(1, rgb.size() / 3));
  return t;
}

// One row; with `plainMs`, also the ratio of this row's ms/frame to that (the untextured scene's).
void printRow(const char* triangles, const char* mode, const FrameTimes& t, double baselineMs,
              double plainMs = NAN) {
  char scene[16] = "-", tone[16] = "-", plain[16] = "";
  if (std::isfinite(t.gpuSceneMs)) {
    std::snprintf(scene, sizeof scene, "%.3f", t.gpuSceneMs);
    std::snprintf(tone, sizeof tone, "%.3f", t.gpuToneMs);
  }
  if (std::isfinite(plainMs)) std::snprintf(plain, sizeof plain, "%8.3f", t.pipelinedMs / plainMs);
  std::printf("%-9s %-9s %9.1f %9.3f %7.2f %9s %8s %8.3f %9.3f %11.4g %s\n", triangles, mode,
              1e3 / t.pipelinedMs, t.pipelinedMs, t.pipelinedMs / baselineMs, scene, tone, t.cpuMs,
              t.finishMs, t.meanLuminanceCdM2, plain);
  std::fflush(stdout);
}

// Wall-clock ms per frame (glFinish after each) with the sun still, and with the sun turned by 0.1° about the
// vertical every frame, so that every frame rebuilds the visibility map and the volumes.
struct RebuildTimes {
  double stillMs = 0.0, movingMs = 0.0;
};
RebuildTimes timeRebuilds(Renderer& renderer, rdb::RasterRdb& r, const View& view, uint32_t w, uint32_t h) {
  const ToneMapSettings tone{ToneOperator::kFilmic, 12.0};
  const vec3 sun0 = r.sky->sunDirWorld;
  RebuildTimes t;
  for (int moving = 0; moving < 2; ++moving) {
    int frames = 0;
    renderer.render(view, RenderMode::kSunlight, w, h);
    renderer.finish();
    const Clock::time_point start = Clock::now();
    do {
      if (moving) {
        const float a = float(degToRad(0.1 * (frames + 1)));
        r.sky->sunDirWorld = vec3(std::cos(a) * sun0.x + std::sin(a) * sun0.z, sun0.y,
                                  -std::sin(a) * sun0.x + std::cos(a) * sun0.z);
      }
      renderer.render(view, RenderMode::kSunlight, w, h);
      renderer.toneMap(tone);
      renderer.finish();
      ++frames;
    } while (frames < 3 || secondsSince(start) < 0.5);
    (moving ? t.movingMs : t.stillMs) = 1e3 * secondsSince(start) / frames;
  }
  r.sky->sunDirWorld = sun0;
  return t;
}

// The shadow section (see the top): `r` has a sun and no light maps.
void benchShadows(const char* name, rdb::RasterRdb& r, const View& view, uint32_t w, uint32_t h, bool gpuTimers,
                  double baselineMs, uint32_t mapTexels) {
  Renderer renderer;
  renderer.upload(r);
  renderer.setSunShadows({SunShadowMode::kOff});
  const FrameTimes off = timeFrames(renderer, view, RenderMode::kSunlight, w, h, gpuTimers);
  char label[32];
  std::snprintf(label, sizeof label, "%s %zuk", name, (r.triangleCount() + 500) / 1000);
  std::printf("%-14s %-8s %8s %8s %8s %9s %8.1f %9.3f %7.2f %8s %9s\n", label, "off", "-", "-", "-", "-",
              1e3 / off.pipelinedMs, off.pipelinedMs, off.pipelinedMs / baselineMs, "1.000", "-");
  for (SunShadowMode mode : {SunShadowMode::kVisibilityMap, SunShadowMode::kSunFacing}) {
    renderer.setSunShadows({mode, mapTexels});
    const FrameTimes t = timeFrames(renderer, view, RenderMode::kSunlight, w, h, gpuTimers);
    renderer.render(view, RenderMode::kSunlight, w, h);
    const SunShadowCounts c = renderer.sunShadowCounts();
    const double fill = double(renderer.shadowVolumeFill()) * 1e-6;
    char rebuild[16] = "-";
    const RebuildTimes rt = timeRebuilds(renderer, r, view, w, h);
    std::snprintf(rebuild, sizeof rebuild, "%.2f", rt.movingMs - rt.stillMs);
    std::printf("%-14s %-8s %8u %8u %8u %9.2f %8.1f %9.3f %7.2f %8.3f %9s\n", label,
                mode == SunShadowMode::kVisibilityMap ? "vismap" : "classic", c.keptTriangles, c.silhouetteEdges,
                c.sideTriangles, fill, 1e3 / t.pipelinedMs, t.pipelinedMs, t.pipelinedMs / baselineMs,
                t.pipelinedMs / off.pipelinedMs, rebuild);
    if (gpuTimers) {
      // One more rebuild with time stamps around its stages (GPU ms).
      renderer.setShadowProfiling(true);
      const vec3 sun0 = r.sky->sunDirWorld;
      r.sky->sunDirWorld = glm::normalize(sun0 + vec3(1e-3f, 0.0f, 0.0f));
      renderer.render(view, RenderMode::kSunlight, w, h);
      r.sky->sunDirWorld = sun0;
      std::printf("%-14s   rebuild on the GPU (ms):", "");
      double total = 0.0;
      for (const auto& [stage, ms] : renderer.sunShadowBuildStagesMs()) {
        std::printf(" %s %.3f,", stage.c_str(), ms);
        total += ms;
      }
      std::printf(" total %.3f; kept by the depth test %u\n", total, renderer.sunShadowCounts().keptByDepthTest);
      renderer.setShadowProfiling(false);
    }
    std::fflush(stdout);
  }
}

int runShadows(bool quick, const std::string& housePath, uint32_t w, uint32_t h, bool gpuTimers, double baselineMs,
               uint32_t mapTexels) {
  std::printf("\nsun shadows: sunlight mode without light maps, visibility map %u²; fill in millions of fragments\n",
              mapTexels);
  std::printf("%-14s %-8s %8s %8s %8s %9s %8s %9s %8s %8s %9s\n", "scene", "shadows", "kept", "silhou.", "sides",
              "fill M", "fps", "ms/frame", "× base", "× off", "rebuild ms");
  for (uint32_t n : quick ? std::vector<uint32_t>{221} : std::vector<uint32_t>{387, 707}) {
    rdb::RasterRdb r = rdb::buildRasterRdb(makeScene(n));
    benchShadows("boxes", r, viewOfCamera(r.cameras.at(0)), w, h, gpuTimers, baselineMs, mapTexels);
  }
  {
    rdb::RasterRdb r = rdb::buildRasterRdb(makeCar());
    benchShadows("car", r, viewOfCamera(r.cameras.at(0)), w, h, gpuTimers, baselineMs, mapTexels);
  }
  {
    rdb::RasterRdb r = rdb::buildRasterRdb(makeOffice());
    benchShadows("office", r, viewOfCamera(r.cameras.at(0)), w, h, gpuTimers, baselineMs, mapTexels);
  }
  if (!std::filesystem::exists(housePath)) {
    std::printf("(%s not found: the house is skipped; run from the repository's root or pass --house)\n",
                housePath.c_str());
    return 0;
  }
  rdb::RasterRdb r = rdb::buildRasterRdb(sdb::loadScene(housePath));
  for (const rdb::RasterCamera& camera : r.cameras) {
    benchShadows(("house/" + camera.name).c_str(), r, viewOfCamera(camera), w, h, gpuTimers, baselineMs, mapTexels);
  }
  return 0;
}

int run(int argc, char** argv) {
  uint32_t w = 1920, h = 1080;
  uint32_t shadowMapTexels = 1024;
  bool quick = false, texturedOnly = false, shadowsOnly = false, reflectorsOnly = false, postOnly = false,
       anisotropicOnly = false, probeOnly = false;
  std::string housePath = "scenes/house/house.json";
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--textured") == 0) {
      texturedOnly = true;
    } else if (std::strcmp(argv[i], "--shadows") == 0) {
      shadowsOnly = true;
    } else if (std::strcmp(argv[i], "--reflectors") == 0) {
      reflectorsOnly = true;
    } else if (std::strcmp(argv[i], "--post") == 0) {
      postOnly = true;
    } else if (std::strcmp(argv[i], "--anisotropic") == 0) {
      anisotropicOnly = true;
    } else if (std::strcmp(argv[i], "--probe") == 0) {
      probeOnly = true;
    } else if (std::strcmp(argv[i], "--shadow-map") == 0 && i + 1 < argc &&
               std::sscanf(argv[++i], "%u", &shadowMapTexels) == 1 && shadowMapTexels >= 16) {
    } else if (std::strcmp(argv[i], "--house") == 0 && i + 1 < argc) {
      housePath = argv[++i];
    } else if (std::strcmp(argv[i], "--size") == 0 && i + 1 < argc &&
               std::sscanf(argv[++i], "%ux%u", &w, &h) == 2 && w > 0 && h > 0) {
    } else {
      std::fprintf(stderr,
                   "usage: fly-bench-raster [--size WxH] [--quick | --textured | --reflectors | --anisotropic | --post | --probe | --shadows [--shadow-map N]] [--house PATH]\n");
      return 2;
    }
  }
  const std::unique_ptr<GlContext> context = createHeadlessContext();
  const GlInfo& info = context->info();
  const bool gpuTimers = info.renderer.find("llvmpipe") == std::string::npos &&
                         info.renderer.find("softpipe") == std::string::npos;
  std::printf("fly-bench-raster: OpenGL %d.%d, %s, %s (%s), GL_VERSION %s, %u×%u\n", info.major, info.minor,
              info.vendor.c_str(), info.renderer.c_str(), info.platform.c_str(),
              reinterpret_cast<const char*>(glGetString(GL_VERSION)), w, h);
  std::printf(
      "pipelined: ≤ 2 frames in flight; GPU: GL_TIME_ELAPSED%s; finish: glFinish after every frame\n\n",
      gpuTimers ? "" : " (not meaningful on this renderer: not measured)");
  std::printf("%-9s %-9s %9s %9s %7s %9s %8s %8s %9s %11s\n", "", "", "pipelined", "", "", "GPU ms", "",
              "CPU", "finish", "");
  // %8s for "× base": × takes 2 bytes in UTF-8.
  std::printf("%-9s %-9s %9s %9s %8s %9s %8s %8s %9s %11s\n", "triangles", "mode", "fps", "ms/frame",
              "× base", "scene", "tone", "ms", "ms/frame", "mean L cd/m²");

  // Baseline: the empty frame (depth clear, background, tone map) of a scene with no triangles.
  sdb::Scene empty;
  const rdb::RasterRdb emptyRdb = rdb::buildRasterRdb(empty);
  Renderer baselineRenderer;
  baselineRenderer.upload(emptyRdb);
  const View emptyView = framingView(emptyRdb.boundsM, float(w) / float(h));
  const FrameTimes baseline = timeFrames(baselineRenderer, emptyView, RenderMode::kSimple, w, h, gpuTimers);
  printRow("0", "empty", baseline, baseline.pipelinedMs);
  if (shadowsOnly) return runShadows(quick, housePath, w, h, gpuTimers, baseline.pipelinedMs, shadowMapTexels);
  if (postOnly) {
    const sdb::Scene scene = makeScene(quick ? 221 : 387);
    const rdb::RasterRdb r = rdb::buildRasterRdb(scene);  // no light maps: simple mode shades every mesh
    const View view = viewOfCamera(r.cameras.at(0));
    const std::string triangles = std::to_string(r.triangleCount());
    std::printf("%-9s %-9s %9s %9s %8s %9s %8s %8s %9s %11s %8s\n", "triangles", "mode", "fps", "ms/frame",
                "× base", "scene", "tone", "ms", "ms/frame", "mean L cd/m²", "× plain");
    for (const RenderMode mode : {RenderMode::kSimple, RenderMode::kSunlight}) {
      Renderer plain, post;
      plain.upload(r);
      post.upload(r);
      const FrameTimes p = timeFrames(plain, view, mode, w, h, gpuTimers);
      printRow(triangles.c_str(), renderModeName(mode), p, baseline.pipelinedMs);
      if (mode == RenderMode::kSimple) {
        post.setAmbientOcclusion({true, 0.5f});
      } else {
        post.setBloom({0.05f, 1.0f});
      }
      const FrameTimes t = timeFrames(post, view, mode, w, h, gpuTimers);
      printRow(triangles.c_str(), mode == RenderMode::kSimple ? "+ssao" : "+bloom", t, baseline.pipelinedMs,
               p.pipelinedMs);
    }
    return 0;
  }
  if (probeOnly) {
    sdb::Scene scene = makeScene(quick ? 221 : 387);
    // Every material polished (a Fresnel reflection of glossiness 0.3 over its diffuse colour), so that the
    // probe has surfaces to serve.
    std::vector<std::pair<sdb::MaterialId, sdb::Material>> polished;
    for (const auto& [id, m] : scene.materials()) {
      sdb::Material p = m;
      p.reflectionColor = Rgb(1.0f);
      p.reflectionModel = sdb::ReflectionModel::kFresnel;
      p.ior = 1.5f;
      p.reflectionGlossiness = 0.3f;
      polished.emplace_back(id, p);
    }
    for (const auto& [id, m] : polished) scene.setMaterial(id, m);
    const rdb::RasterRdb r = lightMapped(scene);
    const View view = viewOfCamera(r.cameras.at(0));
    View moved = view;
    moved.worldFromCamera[3] += vec4(0.3f, 0.0f, 0.0f, 0.0f);
    const std::string triangles = std::to_string(r.triangleCount());
    std::printf("%-9s %-9s %9s %9s %8s %9s %8s %8s %9s %11s %8s\n", "triangles", "mode", "fps", "ms/frame",
                "× base", "scene", "tone", "ms", "ms/frame", "mean L cd/m²", "× plain");
    for (const RenderMode mode : {RenderMode::kLightMap, RenderMode::kSunlight}) {
      Renderer off, still, moving;
      off.setRoomProbe(false);
      off.upload(r);
      still.upload(r);
      moving.upload(r);
      const FrameTimes plain = timeFrames(off, view, mode, w, h, gpuTimers);
      printRow(triangles.c_str(), renderModeName(mode), plain, baseline.pipelinedMs);
      const FrameTimes t = timeFrames(still, view, mode, w, h, gpuTimers);
      printRow(triangles.c_str(), "+probe", t, baseline.pipelinedMs, plain.pipelinedMs);
      const FrameTimes m = timeFrames(moving, view, mode, w, h, gpuTimers, &moved);
      printRow(triangles.c_str(), "+moving", m, baseline.pipelinedMs, plain.pipelinedMs);
      std::printf("  %s: %d probe captures in the moving run\n", renderModeName(mode), moving.stats().probeCaptures);
    }
    return 0;
  }
  if (anisotropicOnly) {
    // The 300k-triangle scene with addReflectorMeshes' wall, pool and ball of the brushed-metal preset, first
    // with U = V (isotropic: shaded per vertex), then as it is (anisotropic: per fragment, with tangents),
    // mode by mode; "× plain" against the isotropic row of that mode.
    constexpr RenderMode kAll[] = {RenderMode::kSimple, RenderMode::kLightMap, RenderMode::kSunlight};
    std::printf("%-9s %-9s %9s %9s %8s %9s %8s %8s %9s %11s %8s\n", "triangles", "mode", "fps", "ms/frame",
                "× base", "scene", "tone", "ms", "ms/frame", "mean L cd/m²", "× plain");
    FrameTimes isotropic[3];
    for (const bool anisotropic : {false, true}) {
      sdb::Scene scene = makeScene(quick ? 221 : 387);
      sdb::Material brushed = sdb::findMaterialPreset("brushed-metal")->material;
      if (!anisotropic) brushed.anisotropyV = brushed.anisotropyU;
      addReflectorMeshes(scene, scene.addMaterial(brushed).id);
      const rdb::RasterRdb r = lightMapped(scene);
      Renderer renderer;
      renderer.upload(r);
      const View view = viewOfCamera(r.cameras.at(0));
      const std::string name = std::to_string(r.triangleCount()) + (anisotropic ? "an" : "is");
      for (int m = 0; m < 3; ++m) {
        const FrameTimes t = timeFrames(renderer, view, kAll[m], w, h, gpuTimers);
        if (!anisotropic) isotropic[m] = t;
        printRow(name.c_str(), renderModeName(kAll[m]), t, baseline.pipelinedMs,
                 anisotropic ? isotropic[m].pipelinedMs : NAN);
      }
    }
    return 0;
  }
  if (reflectorsOnly) {
    // The 300k-triangle scene with two mirrors against the same quads in grey, mode by mode.
    constexpr RenderMode kAll[] = {RenderMode::kSimple, RenderMode::kLightMap, RenderMode::kSunlight};
    FrameTimes grey[3], sharp[3], glossy[3];
    // Grey, mirrors, glossy mirrors (glossiness 0.2), mirrors with reflection fog (20 m), anisotropic glossy
    // mirrors (glossiness 0.2, U 0.6, V 0.1).
    for (const int kind : {0, 1, 2, 3, 4}) {
      const bool mirrors = kind > 0;
      sdb::Scene scene = makeScene(quick ? 221 : 387);
      addReflectors(scene, mirrors, kind == 2 || kind == 4 ? 0.2f : 0.0f,
                    kind == 3 ? 20.0f : std::numeric_limits<float>::infinity(), kind == 4);
      const rdb::RasterRdb r = lightMapped(scene);
      Renderer renderer;
      renderer.upload(r);
      const View view = viewOfCamera(r.cameras.at(0));
      const char* kinds[] = {"g", "m", "gm", "fm", "am"};
      const std::string name = std::to_string(r.triangleCount()) + kinds[kind];
      for (int m = 0; m < 3; ++m) {
        const FrameTimes t = timeFrames(renderer, view, kAll[m], w, h, gpuTimers);
        if (!mirrors) grey[m] = t;
        if (kind == 1) sharp[m] = t;
        if (kind == 2) glossy[m] = t;
        printRow(name.c_str(), renderModeName(kAll[m]), t, baseline.pipelinedMs);
        if (kind == 3) {
          std::printf("%-9s %-9s reflection fog: × sharp mirrors %.2f\n", "", "", t.pipelinedMs / sharp[m].pipelinedMs);
        }
        if (kind == 2 || kind == 4) {
          // The glossy passes' scale (Renderer::setGlossyReflectionScale) and their pixels in one frame.
          const int64_t before = renderer.stats().reflectionPassPixels;
          renderer.render(view, kAll[m], w, h);
          std::printf("%-9s %-9s glossy passes drawn 1/%u as wide and high: %lld pass pixels a frame; × sharp mirrors %.2f\n",
                      "", "", renderer.stats().lastGlossyReflectionScale,
                      static_cast<long long>(renderer.stats().reflectionPassPixels - before),
                      t.pipelinedMs / sharp[m].pipelinedMs);
        }
        if (kind == 4) {
          std::printf("%-9s %-9s anisotropic blur: × isotropic glossy mirrors %.2f\n", "", "",
                      t.pipelinedMs / glossy[m].pipelinedMs);
        }
        if (mirrors) {
          std::printf("%-9s %-9s planar reflectors %zu, mirrored passes a frame %.1f, cube maps %zu, × grey %.2f\n", "", "",
                      r.planarReflectors.size(), double(renderer.stats().reflectionPasses) / double(renderer.stats().scenePasses - renderer.stats().reflectionPasses),
                      r.cubeReflectors.size(), t.pipelinedMs / grey[m].pipelinedMs);
          // The per-vertex triangles one frame draws, over all its passes, the chunks no pass can see left out
          // (raster/draw_chunks.h).
          const int64_t before = renderer.stats().perVertexTrianglesDrawn;
          renderer.render(view, kAll[m], w, h);
          std::printf("%-9s %-9s per-vertex triangles drawn a frame %lld (3 passes × all %lld triangles: %lld)\n", "", "",
                      static_cast<long long>(renderer.stats().perVertexTrianglesDrawn - before),
                      static_cast<long long>(r.triangleCount()), static_cast<long long>(3 * r.triangleCount()));
        }
        if (mirrors && !r.cubeReflectors.empty()) {
          // The cube map's capture (six 64² views and its prefiltering), which runs only when the scene or its
          // light changes: one frame after a change against one without.
          auto oneFrameMs = [&](bool change) {
            if (change) renderer.update(r, {.lights = true});
            renderer.finish();
            const Clock::time_point start = Clock::now();
            renderer.render(view, kAll[m], w, h);
            renderer.finish();
            return 1e3 * secondsSince(start);
          };
          oneFrameMs(false);
          const double still = oneFrameMs(false), changed = oneFrameMs(true);
          std::printf("%-9s %-9s cube-map capture %.2f ms (a frame after a light change %.2f ms, without %.2f ms)\n", "",
                      "", changed - still, changed, still);
        }
        if (kind == 2) {
          // The same frames with the glossy passes drawn at the image's resolution.
          renderer.setGlossyReflectionScale(1);
          const FrameTimes full = timeFrames(renderer, view, kAll[m], w, h, gpuTimers);
          printRow((name + "-full").c_str(), renderModeName(kAll[m]), full, baseline.pipelinedMs);
          std::printf("%-9s %-9s glossy passes at the image's resolution; the coarser passes × %.2f\n", "", "",
                      t.pipelinedMs / full.pipelinedMs);
          renderer.setGlossyReflectionScale(0);
        }
      }
      if (kind == 1) {
        // Sunlight mode's image-based light (the sky's irradiance and split sum) against the directional
        // ambient term, in the mirrors' scene.
        renderer.setImageBasedLight(false);
        const FrameTimes off = timeFrames(renderer, view, RenderMode::kSunlight, w, h, gpuTimers);
        printRow((name + "-ibl").c_str(), "sunlight", off, baseline.pipelinedMs);
        renderer.setImageBasedLight(true);
        const FrameTimes on = timeFrames(renderer, view, RenderMode::kSunlight, w, h, gpuTimers);
        std::printf("%-9s %-9s without image-based light; with it × %.2f\n", "", "", on.pipelinedMs / off.pipelinedMs);
      }
    }
    return 0;
  }

  const uint32_t texturedCells = quick ? 221 : 387;
  const std::vector<uint32_t> cells = quick || texturedOnly ? std::vector<uint32_t>{texturedCells}
                                                            : std::vector<uint32_t>{221, 387, 707};
  constexpr RenderMode kModes[] = {RenderMode::kSimple, RenderMode::kLightMap, RenderMode::kSunlight};
  FrameTimes plainTimes[3];  // the untextured texturedCells scene, per mode
  for (uint32_t n : cells) {
    const sdb::Scene scene = makeScene(n);
    const rdb::RasterRdb r = lightMapped(scene);
    Renderer renderer;
    renderer.upload(r);
    const View view = viewOfCamera(r.cameras.at(0));
    const std::string triangles = std::to_string(r.triangleCount());
    for (int m = 0; m < 3; ++m) {
      const FrameTimes t = timeFrames(renderer, view, kModes[m], w, h, gpuTimers);
      if (n == texturedCells) plainTimes[m] = t;
      printRow(triangles.c_str(), renderModeName(kModes[m]), t, baseline.pipelinedMs);
    }
  }

  // The textured scene against the untextured one of the same size, mode by mode.
  const sdb::Scene scene = makeScene(texturedCells, true);
  const rdb::RasterRdb r = lightMapped(scene);
  Renderer renderer;
  renderer.upload(r);
  const View view = viewOfCamera(r.cameras.at(0));
  std::printf("\ntextured: %zu textures (%zu MB of RGBA8 level 0), anisotropic filtering %gx\n", r.textures.size(),
              [&] {
                size_t bytes = 0;
                for (const rdb::RasterTexture& t : r.textures) bytes += t.rgba8.size();
                return bytes >> 20;
              }(),
              double(renderer.stats().maxAnisotropy));
  std::printf("%-9s %-9s %9s %9s %8s %9s %8s %8s %9s %11s %8s\n", "triangles", "mode", "fps", "ms/frame", "× base",
              "scene", "tone", "ms", "ms/frame", "mean L cd/m²", "× plain");
  const std::string triangles = std::to_string(r.triangleCount()) + "t";
  for (int m = 0; m < 3; ++m) {
    const FrameTimes t = timeFrames(renderer, view, kModes[m], w, h, gpuTimers);
    printRow(triangles.c_str(), renderModeName(kModes[m]), t, baseline.pipelinedMs, plainTimes[m].pipelinedMs);
  }
  // Light-map mode with less anisotropic filtering (what the texture samples cost).
  for (float samples : {8.0f, 4.0f, 1.0f}) {
    renderer.setMaxAnisotropy(samples);
    char mode[24];
    std::snprintf(mode, sizeof mode, "lm-af%g", double(renderer.stats().maxAnisotropy));
    const FrameTimes t = timeFrames(renderer, view, RenderMode::kLightMap, w, h, gpuTimers);
    printRow(triangles.c_str(), mode, t, baseline.pipelinedMs, plainTimes[1].pipelinedMs);
  }
  if (texturedOnly) return 0;
  return runShadows(quick, housePath, w, h, gpuTimers, baseline.pipelinedMs, shadowMapTexels);
}

}  // namespace
}  // namespace fly::raster

int main(int argc, char** argv) {
  try {
    return fly::raster::run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}
