// libFuzzer target: manifest.json of a baked scene directory and what the commands do with it: `fly info`
// (cli::parseBakedManifest, bakeSummaryJson, bakeSummaryText), `fly render` and `fly view`
// (cli::readBakedLightMaps: the manifest's objects matched against scene.gltf and the light textures' EXR
// files). The input is the manifest; the rest of the directory is a real bake written once at start by
// cli::writeBakedScene from a hand-made two-mesh TraceRdb (a one-sided triangle, and a two-sided
// light-textured quad), so that mutations of the manifest reach the glTF and EXR readers.
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/baked_light_maps.h"
#include "cli/baked_manifest.h"
#include "cli/baked_scene.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

namespace fs = std::filesystem;
using namespace fly;

// A triangle (one-sided) and a quad (two-sided, 2 × 2 light texture) with made-up light-map values.
void writeFixture(const fs::path& dir) {
  rdb::TraceRdb rdb;
  rdb.positionsM = {{0, 0, 0}, {1, 0, 0}, {0, 0, -1}, {0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  rdb.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  rdb.indices = {0, 1, 2, 3, 4, 5, 3, 5, 6};
  rdb.triangleMaterial = {0, 0, 0};
  rdb.materials.resize(1);
  rdb.meshes = {{.sdbMeshId = 1,
                 .sdbNodeId = 1,
                 .firstVertex = 0,
                 .vertexCount = 3,
                 .firstTriangle = 0,
                 .triangleCount = 1},
                {.sdbMeshId = 2,
                 .sdbNodeId = 2,
                 .firstVertex = 3,
                 .vertexCount = 4,
                 .firstTriangle = 1,
                 .triangleCount = 2,
                 .twoSided = true,
                 .lightTexture = 0}};
  rdb.lightTextures = {
      {.mesh = 1,
       .width = 2,
       .height = 2,
       .texelsPerMetre = 2.0f,
       .cornerUv = {{0.1f, 0.9f}, {0.9f, 0.9f}, {0.9f, 0.1f}, {0.1f, 0.9f}, {0.9f, 0.1f}, {0.1f, 0.1f}}}};
  raytracer::VertexLightMaps maps;
  maps.frontLux.assign(7, Rgb(100.0f));
  maps.frontStdErrorLux.assign(7, Rgb(1.0f));
  maps.backLux.assign(7, Rgb(10.0f));
  maps.backStdErrorLux.assign(7, Rgb(0.5f));
  maps.frontSamples.assign(7, 16);
  maps.samplesPerVertex = 16;
  maps.replicates = 8;
  maps.history = {{.seconds = 0.1, .samples = 16, .relativeErrorP95 = 0.05f, .raysPerSecond = 1e6}};
  maps.rays = 1000;
  maps.seconds = 0.1;
  raytracer::LightTexture t;
  t.mesh = 1;
  t.width = 2;
  t.height = 2;
  t.frontLux.assign(4, Rgb(90.0f));
  t.frontStdErrorLux.assign(4, Rgb(1.0f));
  t.backLux.assign(4, Rgb(9.0f));
  t.backStdErrorLux.assign(4, Rgb(0.5f));
  t.baked.assign(4, 1);
  t.bakedTexels = 4;
  t.samples = 16;
  maps.lightTextures = {t};
  cli::BakeDescription d;
  d.scenePath = "fixture.json";
  d.settings = nlohmann::json::object();
  d.timingsS = nlohmann::json::object();
  d.meshNames = {"triangle", "quad"};
  d.nodeNames = {"triangle", "quad"};
  d.materialNames = {"white"};
  cli::writeBakedScene(dir, rdb, maps, d);
}

const fs::path& bakedDir() {
  static const fs::path dir = [] {
    const fs::path d = fuzz::scratchDir() / "bake";
    writeFixture(d);
    return d;
  }();
  return dir;
}

}  // namespace

// fontconfig, which cairo uses for the fixture's convergence.png, keeps its configuration until exit by
// design (as tests/lsan.supp says for the unit tests).
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libfontconfig";
}

// The fixture is written here, before libFuzzer's per-input leak checks start. With the environment variable
// FLY_FUZZ_WRITE_SEED=PATH its manifest is copied to PATH: scripts/fuzz puts it into this target's corpus as
// the seed.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  fuzz::quietLog();
  bakedDir();
  if (const char* seed = std::getenv("FLY_FUZZ_WRITE_SEED")) {
    fs::copy_file(bakedDir() / "manifest.json", seed, fs::copy_options::overwrite_existing);
  }
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fs::path manifest = bakedDir() / "manifest.json";
  fuzz::writeScratchFile(manifest, fuzz::asText(data, size));
  fuzz::expectOnlyInputErrors([&] {
    const nlohmann::json m = cli::readBakedManifest(bakedDir());
    cli::bakeSummaryJson(m).dump();
    cli::bakeSummaryText(m, cli::findBakedSourceScene(bakedDir(), m).has_value());
    const rdb::LightMapStore store = cli::readBakedLightMaps(bakedDir());
    for (const rdb::MeshLightMap& map : store.meshes) {
      for (const Rgb& c : map.frontLux) fuzz::require(isFinite(c), "light-map values are finite");
    }
  });
  return 0;
}
