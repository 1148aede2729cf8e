#include "cli/baked_light_maps.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>

#include "base/error.h"
#include "base/image_io.h"
#include "cli/baked_scene.h"
#include "cli/scene_daylight.h"
#include "raster/gl_context.h"
#include "raster/renderer.h"
#include "raytracer/baker.h"
#include "raytracer/embree_scene.h"
#include "rdb/trace_rdb_build.h"
#include "sdb/scene.h"
#include "sdb/scene_load.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class BakedLightMapsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    parent_ = fs::temp_directory_path() /
              ("fly_baked_light_maps_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(parent_);
    fs::create_directories(parent_);
    dir_ = parent_ / "bake";
  }
  void TearDown() override { fs::remove_all(parent_); }

  fs::path parent_;
  fs::path dir_;
};

sdb::Mesh quad(const vec3& origin, const vec3& u, const vec3& v, bool twoSided) {
  sdb::Mesh m;
  m.positions = {origin, origin + u, origin + u + v, origin + v};
  m.normals.assign(4, glm::normalize(glm::cross(u, v)));
  m.indices = {0, 1, 2, 0, 2, 3};
  m.twoSided = twoSided;
  return m;
}

// A 0.5 m cube of 8 shared corners with a generated light texture: its charts split the corners at seams, so
// scene.gltf holds more vertices for it than the SDB mesh has.
sdb::Mesh cube() {
  sdb::Mesh m;
  for (int i = 0; i < 8; ++i)
    m.positions.emplace_back(0.5f * float(i & 1), 0.5f * float((i >> 1) & 1), 0.5f * float(i >> 2) - 1.5f);
  m.indices = {0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4,
               2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1, 3, 5, 3, 7, 5};
  for (const vec3& p : m.positions) m.normals.push_back(glm::normalize(p - vec3(0.25f, 0.25f, -1.25f)));
  m.lightTexture.enabled = true;
  m.lightTexture.texelsPerMetre = 8.0f;
  return m;
}

struct Baked {
  sdb::Scene scene;
  rdb::TraceRdb rdb;
  raytracer::VertexLightMaps maps;
};

// A floor, a two-sided wall, a light-textured cube, a mesh of only degenerate triangles and a 100 cd point
// light, lowered and baked in-process with few samples (the values only need to be what the bake gives);
// withSun adds a clear sky with the sun placed directly, whose direct part the bake keeps apart.
Baked bakeTinyScene(const fs::path& dir, bool withSun = false) {
  Baked b;
  sdb::Scene& s = b.scene;
  const auto place = [&s](const char* name, sdb::Mesh m) {
    const sdb::MeshId mesh = s.addMesh(std::move(m)).id;
    s.addNode({.name = name, .meshes = {mesh}});
  };
  place("floor", quad({-1, 0, 1}, {2, 0, 0}, {0, 0, -2}, false));
  place("wall", quad({-1, 0, -1}, {2, 0, 0}, {0, 1, 0}, true));
  place("cube", cube());
  sdb::Mesh degenerate = quad({0, 0, 0}, {1, 0, 0}, {2, 0, 0}, false);
  degenerate.normals.assign(4, vec3(0, 1, 0));
  place("degenerate", degenerate);
  sdb::Light light;
  light.intensity = 100.0f;
  const sdb::LightId lightId = s.addLight(light).id;
  s.addNode({.name = "lamp",
             .parentFromLocal = frameTransform({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.3f, 1.5f, 0.2f}),
             .light = lightId});
  if (withSun) {
    s.setSky({.model = sdb::SkyModel::kClear, .sun = true});
    s.setTime({.sunDirection = sdb::SunDirection{200.0, 35.0}});
  }

  b.rdb = rdb::buildTraceRdb(s);
  const raytracer::EmbreeScene embree(b.rdb);
  raytracer::BakeSettings settings;
  settings.estimate.firstPassSamples = 8;
  settings.estimate.maxSamples = 8;
  settings.estimate.replicates = 8;
  settings.estimate.threads = 2;
  b.maps = raytracer::bakeVertexLightMaps(b.rdb, embree, settings);

  BakeDescription d;
  d.scenePath = "in-process";
  d.daylight = daylightJson(s, false);
  d.settings = json::object();
  d.timingsS = json::object();
  d.meshNames.assign(b.rdb.meshes.size(), "");
  d.nodeNames.assign(b.rdb.meshes.size(), "");
  d.materialNames.assign(b.rdb.materials.size(), "");
  writeDirectoryAtomic(dir, [&](const fs::path& tmp) { writeBakedScene(tmp, b.rdb, b.maps, d); });
  return b;
}

void expectEqualStores(const rdb::LightMapStore& actual, const rdb::LightMapStore& expected) {
  ASSERT_EQ(actual.sun.has_value(), expected.sun.has_value());
  if (expected.sun) {
    EXPECT_EQ(actual.sun->directionWorld, expected.sun->directionWorld);
    EXPECT_EQ(actual.sun->normalIlluminanceLux, expected.sun->normalIlluminanceLux);
  }
  ASSERT_EQ(actual.meshes.size(), expected.meshes.size());
  for (size_t k = 0; k < expected.meshes.size(); ++k) {
    const rdb::MeshLightMap& a = actual.meshes[k];
    const rdb::MeshLightMap& e = expected.meshes[k];
    EXPECT_EQ(a.sdbNodeId, e.sdbNodeId) << "mesh " << k;
    EXPECT_EQ(a.sdbMeshId, e.sdbMeshId) << "mesh " << k;
    EXPECT_TRUE(a.frontLux == e.frontLux) << "mesh " << k << " front";  // bit for bit
    EXPECT_TRUE(a.backLux == e.backLux) << "mesh " << k << " back";
    EXPECT_TRUE(a.frontSunDirectLux == e.frontSunDirectLux) << "mesh " << k << " front sun direct";
    EXPECT_TRUE(a.backSunDirectLux == e.backSunDirectLux) << "mesh " << k << " back sun direct";
    EXPECT_TRUE(a.frontStdErrorLux == e.frontStdErrorLux) << "mesh " << k << " front standard error";
    EXPECT_TRUE(a.backStdErrorLux == e.backStdErrorLux) << "mesh " << k << " back standard error";
    EXPECT_EQ(a.frontStdErrorLux.size(), a.frontLux.size()) << "mesh " << k;
    EXPECT_EQ(a.backStdErrorLux.size(), a.backLux.size()) << "mesh " << k;
    ASSERT_EQ(a.lightTexture.has_value(), e.lightTexture.has_value()) << "mesh " << k;
    if (!e.lightTexture) continue;
    EXPECT_EQ(a.lightTexture->width, e.lightTexture->width) << "mesh " << k;
    EXPECT_EQ(a.lightTexture->height, e.lightTexture->height) << "mesh " << k;
    EXPECT_TRUE(a.lightTexture->frontLux == e.lightTexture->frontLux) << "mesh " << k << " front texels";
    EXPECT_TRUE(a.lightTexture->backLux == e.lightTexture->backLux) << "mesh " << k << " back texels";
    EXPECT_TRUE(a.lightTexture->frontSunDirectLux == e.lightTexture->frontSunDirectLux) << "mesh " << k;
    EXPECT_TRUE(a.lightTexture->backSunDirectLux == e.lightTexture->backSunDirectLux) << "mesh " << k;
    EXPECT_TRUE(a.lightTexture->cornerUv == e.lightTexture->cornerUv) << "mesh " << k << " corner UVs";
    EXPECT_TRUE(a.lightTexture->frontStdErrorLux == e.lightTexture->frontStdErrorLux) << "mesh " << k;
    EXPECT_TRUE(a.lightTexture->backStdErrorLux == e.lightTexture->backStdErrorLux) << "mesh " << k;
    EXPECT_EQ(a.lightTexture->frontStdErrorLux.size(), a.lightTexture->frontLux.size()) << "mesh " << k;
    EXPECT_EQ(a.lightTexture->backStdErrorLux.size(), a.lightTexture->backLux.size()) << "mesh " << k;
  }
}

json readJson(const fs::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}
void writeText(const fs::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

TEST_F(BakedLightMapsTest, ReadBackEqualsTheBakeExactly) {
  const Baked b = bakeTinyScene(dir_);
  const rdb::LightMapStore fromBake = lightMapStoreFromBake(b.rdb, b.maps);
  expectEqualStores(readBakedLightMaps(dir_), fromBake);
  // Without a sun nothing of it is stored.
  EXPECT_FALSE(fromBake.sun);
  EXPECT_TRUE(readJson(dir_ / "manifest.json")["sun_direct"].is_null());
  EXPECT_FALSE(fs::exists(dir_ / "lightmaps/object2_front_sun.exr"));

  // Floor, wall and cube; the mesh of degenerate triangles has nothing to draw and no light map.
  ASSERT_EQ(b.rdb.meshes.size(), 4u);
  EXPECT_EQ(b.rdb.meshes[3].triangleCount, 0u);
  ASSERT_EQ(fromBake.meshes.size(), 3u);
  for (size_t k = 0; k < 3; ++k) {
    const rdb::TraceMesh& tm = b.rdb.meshes[k];
    const rdb::MeshLightMap* m = fromBake.find(tm.sdbNodeId, tm.sdbMeshId);
    ASSERT_EQ(m, &fromBake.meshes[k]);
    const sdb::Mesh& sdbMesh = b.scene.mesh(sdb::MeshId{tm.sdbMeshId});
    ASSERT_EQ(m->frontLux.size(), sdbMesh.vertexCount());
    EXPECT_EQ(m->backLux.size(), sdbMesh.twoSided ? sdbMesh.vertexCount() : 0u);
    // TraceMesh vertices are the SDB mesh's, in order (identity node transforms: the same positions).
    for (size_t v = 0; v < sdbMesh.vertexCount(); ++v)
      EXPECT_EQ(b.rdb.positionsM[tm.firstVertex + v], sdbMesh.positions[v]);
  }
  EXPECT_EQ(fromBake.find(b.rdb.meshes[3].sdbNodeId, b.rdb.meshes[3].sdbMeshId), nullptr);
  EXPECT_EQ(fromBake.find(b.rdb.meshes[0].sdbNodeId, b.rdb.meshes[1].sdbMeshId), nullptr);
  // The lamp lights the floor's front and the wall's front (it is in front of the wall), not the floor's
  // back.
  EXPECT_GT(luminance(fromBake.meshes[0].frontLux[0]), 0.0f);
  EXPECT_GT(luminance(fromBake.meshes[1].frontLux[0]), 0.0f);
  // The cube's seam-split copies follow its 8 vertices in scene.gltf, and are not part of the light map.
  ASSERT_NE(b.rdb.meshes[2].lightTexture, rdb::TraceMesh::kNoLightTexture);
  const json gltf = readJson(dir_ / "scene.gltf");
  const int frontAccessor = gltf["meshes"][2]["primitives"][0]["attributes"]["_IRRADIANCE_FRONT"];
  EXPECT_GT(gltf["accessors"][size_t(frontAccessor)]["count"].get<int>(), 8);
  // Light textures where the TraceRdb has them (the cube asks for one; the floor may get one automatically):
  // the cube's texels and the UVs of its 12 triangles' corners, with seams.
  for (size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(fromBake.meshes[k].lightTexture.has_value(),
              b.rdb.meshes[k].lightTexture != rdb::TraceMesh::kNoLightTexture)
        << "mesh " << k;
  }
  ASSERT_TRUE(fromBake.meshes[2].lightTexture);
  const rdb::MeshLightTexture& t = *fromBake.meshes[2].lightTexture;
  EXPECT_EQ(t.frontLux.size(), size_t(t.width) * t.height);
  EXPECT_TRUE(t.backLux.empty());
  ASSERT_EQ(t.cornerUv.size(), 36u);
  EXPECT_NE(t.cornerUv[0], t.cornerUv[6]);  // vertex 0 in two charts (its −Z and −Y faces)
  EXPECT_TRUE(
      std::any_of(t.frontLux.begin(), t.frontLux.end(), [](const Rgb& e) { return luminance(e) > 0.0f; }));
}

// Under the sun the bake also stores the sun's direct part (vertex attributes _SUN_DIRECT_FRONT/_BACK, the
// light textures' _sun EXR files) and the bake's sun in the manifest; it reads back exactly. A baked scene
// whose manifest has no "sun_direct" (a bake by a fly that did not keep it apart) still loads, without those
// parts.
TEST_F(BakedLightMapsTest, SunDirectPartsReadBackAndOldBakesStillLoad) {
  const Baked b = bakeTinyScene(dir_, true);
  ASSERT_TRUE(b.maps.hasSunDirect());
  const rdb::LightMapStore fromBake = lightMapStoreFromBake(b.rdb, b.maps);
  ASSERT_TRUE(fromBake.sun);
  EXPECT_EQ(fromBake.sun->directionWorld, b.rdb.sun.directionWorld);
  const rdb::LightMapStore read = readBakedLightMaps(dir_);
  expectEqualStores(read, fromBake);
  // The two-sided wall has both sides; the sunlit floor's sun part is the larger share of its light and at
  // most all of it.
  EXPECT_EQ(read.meshes[1].backSunDirectLux.size(), read.meshes[1].backLux.size());
  const Rgb floorE = read.meshes[0].frontLux[0];
  const Rgb floorSun = read.meshes[0].frontSunDirectLux[0];
  EXPECT_GT(luminance(floorSun), 0.5f * luminance(floorE));
  EXPECT_LE(luminance(floorSun), luminance(floorE) * (1 + 1e-6f));
  ASSERT_TRUE(read.meshes[2].lightTexture);
  EXPECT_EQ(read.meshes[2].lightTexture->frontSunDirectLux.size(),
            read.meshes[2].lightTexture->frontLux.size());
  const json manifest = readJson(dir_ / "manifest.json");
  const json& sun = manifest["sun_direct"];
  ASSERT_TRUE(sun.is_object());
  EXPECT_NEAR(sun["elevation_deg"].get<double>(), radToDeg(std::asin(b.rdb.sun.directionWorld.y)), 1e-3);
  EXPECT_NEAR(sun["normal_illuminance_luminance_lux"].get<double>(),
              luminance(b.rdb.sun.normalIlluminanceLux), 1e-2);
  EXPECT_EQ(sun["sun_direction"]["azimuth_deg"].get<double>(), 200.0);
  EXPECT_TRUE(manifest["objects"][0].contains("front_sun_direct"));
  EXPECT_TRUE(fs::exists(dir_ / "lightmaps/object2_front_sun.exr"));
  EXPECT_TRUE(fs::exists(dir_ / "lightmaps/object2_front_sun_stderr.exr"));

  // Damage: a sun_direct without a direction names the key.
  json damaged = manifest;
  damaged["sun_direct"].erase("direction_world");
  writeText(dir_ / "manifest.json", damaged.dump());
  try {
    readBakedLightMaps(dir_);
    ADD_FAILURE() << "a sun_direct without direction_world was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().jsonPath, "/sun_direct/direction_world");
  }
  // An older bake: no "sun_direct" at all. It loads as E alone.
  json old = manifest;
  old.erase("sun_direct");
  writeText(dir_ / "manifest.json", old.dump());
  const rdb::LightMapStore oldStore = readBakedLightMaps(dir_);
  EXPECT_FALSE(oldStore.sun);
  EXPECT_TRUE(oldStore.meshes[0].frontSunDirectLux.empty());
  EXPECT_TRUE(oldStore.meshes[0].frontLux == fromBake.meshes[0].frontLux);
}

// A real scene with light textures (the one cli.bake.light_textures bakes: the floor, the tall block and the
// two-sided short block), baked in-process with few samples: the directory reads back as the bake, and the
// light textures change what the GL engine draws in light-map mode (only where there are light textures).
TEST_F(BakedLightMapsTest, CornellLightTexturesReadBackAndReachTheScreen) {
  const sdb::Scene scene = sdb::loadScene(fs::path(FLY_TEST_DATA_DIR) / "bake/cornell-light-textures.json");
  const rdb::TraceRdb trace = rdb::buildTraceRdb(scene);
  ASSERT_EQ(trace.lightTextures.size(), 3u);
  const raytracer::EmbreeScene embree(trace);
  raytracer::BakeSettings settings;
  settings.estimate.firstPassSamples = 4;
  settings.estimate.maxSamples = 4;
  settings.estimate.replicates = 4;
  settings.estimate.threads = 2;
  const raytracer::VertexLightMaps maps = raytracer::bakeVertexLightMaps(trace, embree, settings);
  BakeDescription d;
  d.scenePath = "in-process";
  d.settings = json::object();
  d.timingsS = json::object();
  d.meshNames.assign(trace.meshes.size(), "");
  d.nodeNames.assign(trace.meshes.size(), "");
  d.materialNames.assign(trace.materials.size(), "");
  writeDirectoryAtomic(dir_, [&](const fs::path& tmp) { writeBakedScene(tmp, trace, maps, d); });
  const rdb::LightMapStore store = lightMapStoreFromBake(trace, maps);
  expectEqualStores(readBakedLightMaps(dir_), store);
  size_t twoSidedTextures = 0;
  for (const rdb::MeshLightMap& m : store.meshes)
    twoSidedTextures += m.lightTexture && !m.lightTexture->backLux.empty();
  EXPECT_EQ(twoSidedTextures, 1u);  // the short block

  // Light-map mode with the light textures and with them left out (vertex values everywhere).
  rdb::LightMapStore vertexOnly = store;
  for (rdb::MeshLightMap& m : vertexOnly.meshes) m.lightTexture.reset();
  const auto render = [&](const rdb::LightMapStore& s) {
    const rdb::RasterRdb r = rdb::buildRasterRdb(scene, &s);
    raster::Renderer renderer;
    renderer.upload(r);
    raster::View view;  // the classic Cornell-box camera (scenes/cornell-box/cornell-box.json)
    view.worldFromCamera =
        sdb::lookAtTransform(vec3(0.278f, 0.273f, -0.8f), vec3(0.278f, 0.273f, 0.0f), vec3(0.0f, 1.0f, 0.0f));
    view.yfovRad = float(degToRad(39.3));
    view.znearM = 0.01f;
    view.zfarM = 10.0f;
    renderer.render(view, raster::RenderMode::kLightMap, 160, 120);
    return renderer.luminanceRgb();
  };
  const std::unique_ptr<raster::GlContext> context = raster::createHeadlessContext();
  context->makeCurrent();
  const std::vector<float> textured = render(store), vertexLit = render(vertexOnly);
  ASSERT_EQ(textured.size(), vertexLit.size());
  size_t equal = 0, different = 0;
  for (size_t i = 0; i < textured.size(); i += 3) {
    ASSERT_TRUE(std::isfinite(textured[i]) && std::isfinite(textured[i + 1]) &&
                std::isfinite(textured[i + 2]));
    const float a = textured[i] + textured[i + 1] + textured[i + 2];
    const float b = vertexLit[i] + vertexLit[i + 1] + vertexLit[i + 2];
    if (a == b) ++equal;
    if (std::abs(a - b) > 0.05f * std::max(a, b)) ++different;
  }
  const size_t pixels = textured.size() / 3;
  // The walls and the ceiling have no light texture: drawn the same, bit for bit. The floor and the blocks'
  // texels carry detail (shadows, the light's falloff) that their few vertices cannot.
  EXPECT_GT(equal, pixels / 10) << different << " of " << pixels << " differ";
  EXPECT_GT(different, pixels / 20) << equal << " of " << pixels << " are equal";
}

TEST_F(BakedLightMapsTest, FromBakeRejectsMapsOfAnotherRdb) {
  const rdb::TraceRdb r;
  raytracer::VertexLightMaps m;
  m.frontLux.resize(3);
  EXPECT_THROW(lightMapStoreFromBake(r, m), std::invalid_argument);
}

// Each damage must give an InputError whose text names `file` and `detail`.
void expectInputError(const fs::path& dir, const std::string& file, const std::string& detail) {
  try {
    readBakedLightMaps(dir);
    ADD_FAILURE() << "no error for damage to " << file << " (" << detail << ")";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find(file), std::string::npos) << what;
    EXPECT_NE(what.find(detail), std::string::npos) << what;
  }
}

TEST_F(BakedLightMapsTest, DamagedDirectoriesGiveInputErrorsNamingTheFile) {
  const fs::path good = parent_ / "good";
  bakeTinyScene(good);
  const json manifest = readJson(good / "manifest.json");
  const json gltf = readJson(good / "scene.gltf");
  const auto damaged = [&](const char* name) {
    const fs::path d = parent_ / name;
    fs::copy(good, d, fs::copy_options::recursive);
    return d;
  };
  const auto editManifest = [&](const char* name, auto edit) {
    const fs::path d = damaged(name);
    json m = manifest;
    edit(m);
    writeText(d / "manifest.json", m.dump());
    return d;
  };
  const auto editGltf = [&](const char* name, auto edit) {
    const fs::path d = damaged(name);
    json g = gltf;
    edit(g);
    writeText(d / "scene.gltf", g.dump());
    return d;
  };

  expectInputError(parent_ / "nowhere", "manifest.json", "");
  {
    const fs::path d = damaged("no-gltf");
    fs::remove(d / "scene.gltf");
    expectInputError(d, "scene.gltf", "");
  }
  {
    const fs::path d = damaged("garbage-gltf");
    writeText(d / "scene.gltf", "{\"asset\": {\"version\": \"2.0\"}, \"buffers\": [");
    expectInputError(d, "scene.gltf", "cannot be loaded");
  }
  {
    const fs::path d = damaged("truncated-bin");
    fs::resize_file(d / "scene.bin", fs::file_size(d / "scene.bin") / 2);
    expectInputError(d, "scene.bin", "");
  }
  {
    const fs::path d = damaged("no-bin");
    fs::remove(d / "scene.bin");
    expectInputError(d, "scene.bin", "");
  }
  {
    // A NaN in place of the floor's first front irradiance.
    const fs::path d = damaged("nan");
    const int accessor = gltf["meshes"][0]["primitives"][0]["attributes"]["_IRRADIANCE_FRONT"];
    const json& view = gltf["bufferViews"][gltf["accessors"][size_t(accessor)]["bufferView"].get<size_t>()];
    std::fstream bin(d / "scene.bin", std::ios::in | std::ios::out | std::ios::binary);
    bin.seekp(std::streamoff(view["byteOffset"].get<size_t>()));
    const float nan = std::numeric_limits<float>::quiet_NaN();
    bin.write(reinterpret_cast<const char*>(&nan), sizeof nan);
    bin.close();
    expectInputError(d, "scene.bin", "not a finite number");
  }
  expectInputError(editManifest("more-vertices", [](json& m) { m["objects"][1]["vertices"] = 5000; }),
                   "scene.gltf", "different bakes");
  expectInputError(editManifest("bad-mesh", [](json& m) { m["objects"][0]["gltf_mesh"] = 99; }),
                   "manifest.json", "/objects/0/gltf_mesh");
  expectInputError(editManifest("no-id", [](json& m) { m["objects"][2].erase("sdb_node_id"); }),
                   "manifest.json", "/objects/2/sdb_node_id");
  expectInputError(editManifest("negative-id", [](json& m) { m["objects"][0]["sdb_mesh_id"] = -1; }),
                   "manifest.json", "/objects/0/sdb_mesh_id");
  expectInputError(editManifest("no-objects", [](json& m) { m.erase("objects"); }), "manifest.json",
                   "/objects");
  expectInputError(editManifest("not-two-sided", [](json& m) { m["objects"][0]["two_sided"] = true; }),
                   "scene.gltf", "_IRRADIANCE_BACK");
  expectInputError(editManifest("version", [](json& m) { m["format_version"] = 99; }), "manifest.json",
                   "format version");
  // Reading only the first `vertices` values, a longer accessor is fine; a view too short for them is not.
  const auto frontView = [](json& g, int mesh) -> json& {
    const int a = g["meshes"][mesh]["primitives"][0]["attributes"]["_IRRADIANCE_FRONT"];
    return g["bufferViews"][g["accessors"][size_t(a)]["bufferView"].get<size_t>()];
  };
  expectInputError(editGltf("short-view", [&](json& g) { frontView(g, 1)["byteLength"] = 12; }), "scene.gltf",
                   "does not fit in its buffer view");
  expectInputError(editGltf("view-outside", [&](json& g) { frontView(g, 1)["byteOffset"] = 1 << 30; }),
                   "scene.bin", "too short for buffer view");
  expectInputError(editGltf("scalar-accessor",
                            [](json& g) {
                              const int a =
                                  g["meshes"][0]["primitives"][0]["attributes"]["_IRRADIANCE_FRONT"];
                              g["accessors"][size_t(a)]["type"] = "SCALAR";
                            }),
                   "scene.gltf", "VEC3 FLOAT");
  expectInputError(
      editGltf("no-front",
               [](json& g) { g["meshes"][0]["primitives"][0]["attributes"].erase("_IRRADIANCE_FRONT"); }),
      "scene.gltf", "_IRRADIANCE_FRONT");
  expectInputError(editGltf("no-meshes", [](json& g) { g.erase("meshes"); }), "manifest.json", "gltf_mesh");
  // The cube's light texture (object 2).
  {
    const fs::path d = damaged("no-exr");
    fs::remove(d / "lightmaps/object2_front.exr");
    expectInputError(d, "object2_front.exr", "");
  }
  {
    const fs::path d = damaged("small-exr");
    writeExr(d / "lightmaps/object2_front.exr", ImageRgbF{2, 1, std::vector<float>(6, 1.0f)});
    expectInputError(d, "object2_front.exr", "2×1 texels");
  }
  {
    // A 1 × 1 image is stored uncompressed (ZIP would only make it longer): a marker value is found in the
    // file and turned into a NaN.
    const fs::path d = damaged("nan-exr");
    const fs::path exr = d / "lightmaps/object2_front.exr";
    const float marker = 1234.5f, nan = std::numeric_limits<float>::quiet_NaN();
    writeExr(exr, ImageRgbF{1, 1, {marker, marker, marker}});
    std::string bytes;
    {
      std::ifstream in(exr, std::ios::binary);
      bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    }
    const size_t at = bytes.find(std::string(reinterpret_cast<const char*>(&marker), sizeof marker));
    ASSERT_NE(at, std::string::npos);
    bytes.replace(at, sizeof nan, reinterpret_cast<const char*>(&nan), sizeof nan);
    writeText(exr, bytes);
    expectInputError(d, "object2_front.exr", "NaN or infinite value");
  }
  {
    const fs::path d = damaged("corrupt-exr");
    writeText(d / "lightmaps/object2_front.exr", "not an EXR");
    expectInputError(d, "object2_front.exr", "");
  }
  expectInputError(
      editManifest("exr-outside", [](json& m) { m["objects"][2]["light_texture"]["front"] = "../x.exr"; }),
      "manifest.json", "outside the baked directory");
  expectInputError(
      editManifest("texture-size", [](json& m) { m["objects"][2]["light_texture"]["width"] = 0; }),
      "manifest.json", "/objects/2/light_texture");
  expectInputError(
      editGltf("no-uv", [](json& g) { g["meshes"][2]["primitives"][0]["attributes"].erase("TEXCOORD_1"); }),
      "scene.gltf", "TEXCOORD_1");
  expectInputError(editManifest("fewer-triangles", [](json& m) { m["objects"][2]["triangles"] = 11; }),
                   "scene.gltf", "different bakes");
  // The undamaged copy still reads.
  EXPECT_EQ(readBakedLightMaps(good).meshes.size(), 3u);
}

}  // namespace
}  // namespace fly::cli
