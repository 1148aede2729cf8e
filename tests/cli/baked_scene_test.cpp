#include "cli/baked_scene.h"

#include <gtest/gtest.h>
#include <tiny_gltf.h>

#include <charconv>
#include <cstring>
#include <fstream>
#include <sstream>

#include "base/error.h"
#include "base/image_io.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

class BakedSceneTest : public ::testing::Test {
 protected:
  void SetUp() override {
    parent_ = fs::temp_directory_path() /
              ("fly_baked_scene_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) + "_" +
               ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(parent_);
    fs::create_directories(parent_);
    dir_ = parent_ / "bake";
  }
  void TearDown() override { fs::remove_all(parent_); }

  size_t entriesInParent() const {
    return size_t(std::distance(fs::directory_iterator(parent_), fs::directory_iterator()));
  }

  fs::path parent_;
  fs::path dir_;
};

// Two unit quads in world space: mesh 0 one-sided on the floor (y = 0, facing up), mesh 1 two-sided as a wall
// (z = −1, facing +Z), each of two triangles and its own material.
rdb::TraceRdb twoQuads() {
  rdb::TraceRdb r;
  const vec3 floor[4] = {{0, 0, 0}, {1, 0, 0}, {1, 0, -1}, {0, 0, -1}};
  const vec3 wall[4] = {{0, 0, -1}, {1, 0, -1}, {1, 1, -1}, {0, 1, -1}};
  for (const vec3& p : floor) {
    r.positionsM.push_back(p);
    r.normals.emplace_back(0, 1, 0);
  }
  for (const vec3& p : wall) {
    r.positionsM.push_back(p);
    r.normals.emplace_back(0, 0, 1);
  }
  r.indices = {0, 1, 2, 0, 2, 3, 4, 5, 6, 4, 6, 7};
  r.triangleMaterial = {0, 0, 1, 1};
  r.materials.resize(2);
  r.materials[1].diffuse = Rgb(0.5f, 0.25f, 0.125f);
  r.materials[1].sdbMaterialId = 7;
  r.meshes = {{.sdbMeshId = 1,
               .sdbNodeId = 2,
               .firstVertex = 0,
               .vertexCount = 4,
               .firstTriangle = 0,
               .triangleCount = 2},
              {.sdbMeshId = 3,
               .sdbNodeId = 4,
               .firstVertex = 4,
               .vertexCount = 4,
               .firstTriangle = 2,
               .triangleCount = 2,
               .twoSided = true}};
  return r;
}

// Distinct, non-round values per vertex and side, so that any mix-up or rounding shows.
raytracer::VertexLightMaps lightMaps(uint32_t samples = 64) {
  raytracer::VertexLightMaps m;
  for (int v = 0; v < 8; ++v) {
    const float f = float(v);
    m.frontLux.emplace_back(1000.1f + f, 2000.3f + f / 3.0f, 3000.7f + f / 7.0f);
    m.frontStdErrorLux.emplace_back(10.1f + f, 20.2f, 30.3f);
    m.backLux.push_back(v < 4 ? Rgb(0.0f) : Rgb(50.5f + f / 9.0f, 60.6f, 70.7f));
    m.backStdErrorLux.push_back(v < 4 ? Rgb(0.0f) : Rgb(1.5f, 1.25f, 1.125f));
  }
  m.samplesPerVertex = samples;
  m.history = {
      {0.1234567, 16, 0.0812345f, 1.234567e6}, {0.25, 32, 0.0577f, 2.5e6}, {0.5000001, 64, 0.04123f, 3e6}};
  m.rays = 123456789;
  m.seconds = 0.5000001;
  return m;
}

BakeDescription description(bool exportGltf) {
  BakeDescription d;
  d.scenePath = "scenes/two-quads.json";
  d.settings = {{"max_samples", 64}};
  d.targetRelativeError = 0.05f;
  d.meshNames = {"floor", "wall"};
  d.nodeNames = {"floor-node", ""};
  d.materialNames = {"default", "brick"};
  d.timingsS = {{"bake", 0.5}};
  d.exportGltf = exportGltf;
  return d;
}

void bake(const fs::path& dir, uint32_t samples = 64, bool exportGltf = true) {
  const rdb::TraceRdb r = twoQuads();
  const raytracer::VertexLightMaps m = lightMaps(samples);
  const BakeDescription d = description(exportGltf);
  writeDirectoryAtomic(dir, [&](const fs::path& tmp) { writeBakedScene(tmp, r, m, d); });
}

tinygltf::Model loadGltf(const fs::path& path) {
  tinygltf::TinyGLTF loader;
  tinygltf::Model model;
  std::string error, warning;
  EXPECT_TRUE(loader.LoadASCIIFromFile(&model, &error, &warning, path.string())) << error;
  EXPECT_TRUE(error.empty()) << error;
  return model;
}

std::vector<vec3> readVec3s(const tinygltf::Model& model, int accessorIndex) {
  const tinygltf::Accessor& a = model.accessors.at(size_t(accessorIndex));
  EXPECT_EQ(a.type, TINYGLTF_TYPE_VEC3);
  EXPECT_EQ(a.componentType, TINYGLTF_COMPONENT_TYPE_FLOAT);
  const tinygltf::BufferView& view = model.bufferViews.at(size_t(a.bufferView));
  const unsigned char* data =
      model.buffers.at(size_t(view.buffer)).data.data() + view.byteOffset + a.byteOffset;
  std::vector<vec3> v(a.count);
  std::memcpy(v.data(), data, a.count * sizeof(vec3));
  return v;
}

TEST_F(BakedSceneTest, BakedSceneRoundTripManifestAndGltfHoldTheInputsExactly) {
  bake(dir_);
  const json manifest = readBakedManifest(dir_);
  EXPECT_EQ(manifest["format"], kBakedSceneFormat);
  EXPECT_EQ(manifest["samples_per_vertex"], 64);
  EXPECT_EQ(manifest["rays"], 123456789);
  EXPECT_FLOAT_EQ(manifest["relative_error_p95"].get<float>(), 0.04123f);
  ASSERT_EQ(manifest["objects"].size(), 2u);
  EXPECT_EQ(manifest["objects"][0]["mesh_name"], "floor");
  EXPECT_EQ(manifest["objects"][1]["sdb_node_id"], 4);
  EXPECT_EQ(manifest["objects"][1]["gltf_mesh"], 1);
  EXPECT_FALSE(manifest["objects"][0].contains("back"));
  EXPECT_TRUE(manifest["objects"][1].contains("back"));
  // Front luminance of floor vertices 0..3: Y(1000.1 + v, 2000.3 + v/3, 3000.7 + v/7), mean over v.
  double mean = 0.0;
  for (int v = 0; v < 4; ++v) mean += luminance(lightMaps().frontLux[size_t(v)]) / 4.0;
  EXPECT_NEAR(manifest["objects"][0]["front"]["mean_irradiance_lux"].get<double>(), mean, 1e-3);
  for (const json& f : manifest["files"]) EXPECT_TRUE(fs::is_regular_file(dir_ / f.get<std::string>())) << f;

  const tinygltf::Model model = loadGltf(dir_ / "scene.gltf");
  const raytracer::VertexLightMaps maps = lightMaps();
  ASSERT_EQ(model.meshes.size(), 2u);
  EXPECT_EQ(model.meshes[1].name, "wall");
  EXPECT_EQ(model.nodes[0].name, "floor-node");
  for (size_t mesh = 0; mesh < 2; ++mesh) {
    const tinygltf::Primitive& prim = model.meshes[mesh].primitives.at(0);
    EXPECT_EQ(prim.material, int(mesh));
    const std::vector<vec3> front = readVec3s(model, prim.attributes.at("_IRRADIANCE_FRONT"));
    const std::vector<vec3> frontErr = readVec3s(model, prim.attributes.at("_IRRADIANCE_FRONT_STDERR"));
    const std::vector<vec3> position = readVec3s(model, prim.attributes.at("POSITION"));
    ASSERT_EQ(front.size(), 4u);
    for (size_t v = 0; v < 4; ++v) {
      EXPECT_EQ(front[v], maps.frontLux[4 * mesh + v]);
      EXPECT_EQ(frontErr[v], maps.frontStdErrorLux[4 * mesh + v]);
      EXPECT_EQ(position[v], twoQuads().positionsM[4 * mesh + v]);
    }
    EXPECT_EQ(prim.attributes.count("_IRRADIANCE_BACK"), mesh == 1 ? 1u : 0u);
  }
  const std::vector<vec3> back =
      readVec3s(model, model.meshes[1].primitives[0].attributes.at("_IRRADIANCE_BACK"));
  for (size_t v = 0; v < 4; ++v) EXPECT_EQ(back[v], maps.backLux[4 + v]);
  const std::vector<double> base = model.materials[1].pbrMetallicRoughness.baseColorFactor;
  EXPECT_DOUBLE_EQ(base[0], 0.5);
  EXPECT_DOUBLE_EQ(base[2], 0.125);
}

TEST_F(BakedSceneTest, BakedSceneExportHasColoursUnlitMaterialsAndBothSidesOfTwoSidedMeshes) {
  bake(dir_);
  const tinygltf::Model model = loadGltf(dir_ / "export" / "scene.gltf");
  ASSERT_EQ(model.meshes.size(), 2u);
  EXPECT_EQ(model.meshes[0].primitives.size(), 1u);
  ASSERT_EQ(model.meshes[1].primitives.size(), 2u);
  EXPECT_TRUE(model.materials[0].extensions.count("KHR_materials_unlit"));
  const tinygltf::Primitive& front = model.meshes[1].primitives[0];
  const tinygltf::Primitive& back = model.meshes[1].primitives[1];
  const std::vector<vec3> frontColour = readVec3s(model, front.attributes.at("COLOR_0"));
  const std::vector<vec3> backColour = readVec3s(model, back.attributes.at("COLOR_0"));
  const std::vector<vec3> backNormal = readVec3s(model, back.attributes.at("NORMAL"));
  for (size_t v = 0; v < 4; ++v) {
    for (int c = 0; c < 3; ++c) {
      EXPECT_GT(frontColour[v][c], 0.0f);
      EXPECT_LT(frontColour[v][c], 1.0f);
    }
    // The back receives 1/20 of the front's light: darker on screen.
    EXPECT_LT(luminance(backColour[v]), luminance(frontColour[v]));
    EXPECT_EQ(backNormal[v], vec3(0, 0, -1));
  }
}

TEST_F(BakedSceneTest, BakedSceneConvergenceCsvRowsEqualTheHistory) {
  bake(dir_);
  std::ifstream in(dir_ / "convergence.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "seconds,samples,estimated_error,rays_per_second");
  const std::vector<raytracer::ConvergencePoint> history = lightMaps().history;
  size_t row = 0;
  while (std::getline(in, line)) {
    ASSERT_LT(row, history.size());
    std::vector<std::string> f;
    std::stringstream s(line);
    for (std::string x; std::getline(s, x, ',');) f.push_back(x);
    ASSERT_EQ(f.size(), 4u);
    double seconds = 0.0, rays = 0.0;
    float error = 0.0f;
    std::from_chars(f[0].data(), f[0].data() + f[0].size(), seconds);
    std::from_chars(f[2].data(), f[2].data() + f[2].size(), error);
    std::from_chars(f[3].data(), f[3].data() + f[3].size(), rays);
    EXPECT_EQ(seconds, history[row].seconds);
    EXPECT_EQ(std::stoul(f[1]), history[row].samples);
    EXPECT_EQ(error, history[row].relativeErrorP95);
    EXPECT_EQ(rays, history[row].raysPerSecond);
    ++row;
  }
  EXPECT_EQ(row, history.size());
}

TEST_F(BakedSceneTest, BakedSceneAnEarlierBakeIsReplacedAndNothingElseIsLeft) {
  bake(dir_, 64);
  bake(dir_, 128, false);
  EXPECT_EQ(readBakedManifest(dir_)["samples_per_vertex"], 128);
  EXPECT_FALSE(fs::exists(dir_ / "export"));  // the whole directory was replaced, not merged
  EXPECT_EQ(entriesInParent(), 1u);
}

TEST_F(BakedSceneTest, BakedSceneADirectoryThatIsNotABakeIsRefusedAndUntouched) {
  fs::create_directories(dir_);
  std::ofstream(dir_ / "thesis.txt") << "precious";
  EXPECT_THROW(bake(dir_), UsageError);
  EXPECT_TRUE(fs::is_regular_file(dir_ / "thesis.txt"));
  EXPECT_EQ(size_t(std::distance(fs::directory_iterator(dir_), fs::directory_iterator())), 1u);
  EXPECT_EQ(entriesInParent(), 1u);
  const fs::path file = parent_ / "file";
  std::ofstream(file) << "x";
  EXPECT_THROW(checkBakeOutput(file), UsageError);
}

TEST_F(BakedSceneTest, BakedSceneAFailedWriteLeavesNoDirectoryAndNoTemporary) {
  const auto failing = [](const fs::path& tmp) {
    fs::create_directory(tmp);
    std::ofstream(tmp / "half.bin") << "half";
    throw std::runtime_error("disk full");
  };
  EXPECT_THROW(writeDirectoryAtomic(dir_, failing), std::runtime_error);
  EXPECT_FALSE(fs::exists(dir_));
  EXPECT_EQ(entriesInParent(), 0u);

  // With an earlier bake there, it stays as it was.
  bake(dir_, 64);
  EXPECT_THROW(writeDirectoryAtomic(dir_, failing), std::runtime_error);
  EXPECT_EQ(readBakedManifest(dir_)["samples_per_vertex"], 64);
  EXPECT_EQ(entriesInParent(), 1u);
}

TEST_F(BakedSceneTest, BakedSceneManifestReaderRejectsWhatIsNotABake) {
  EXPECT_THROW(readBakedManifest(parent_), InputError);  // no manifest
  std::ofstream(parent_ / "manifest.json") << R"({"format": "something-else"})";
  EXPECT_THROW(readBakedManifest(parent_), InputError);
  std::ofstream(parent_ / "manifest.json") << R"({"format": "fly-baked-scene", "format_version": 99})";
  EXPECT_THROW(readBakedManifest(parent_), InputError);
  std::ofstream(parent_ / "manifest.json") << "{not json";
  EXPECT_THROW(readBakedManifest(parent_), InputError);
}

// The wall (mesh 1, two-sided) with a light texture whose two triangles lie in separate charts: its
// vertices 4 and 6 (mesh-relative 0 and 2) appear twice in scene.gltf, the copies appended after the
// TraceMesh's 4 vertices with _SOURCE_VERTEX naming them; the EXR files hold the texels bit for bit.
TEST_F(BakedSceneTest, LightTexturesAreWrittenAsExrAndReferencedFromManifestAndGltf) {
  rdb::TraceRdb r = twoQuads();
  rdb::TraceLightTexture lt;
  lt.mesh = 1;
  lt.width = 4;
  lt.height = 3;
  lt.texelsPerMetre = 2.5f;
  // Triangle (4, 5, 6) in the left half, (4, 6, 7) in the right half.
  lt.cornerUv = {{0.1f, 0.1f}, {0.4f, 0.1f}, {0.4f, 0.9f}, {0.6f, 0.1f}, {0.9f, 0.9f}, {0.6f, 0.9f}};
  r.lightTextures.push_back(lt);
  r.meshes[1].lightTexture = 0;
  raytracer::VertexLightMaps m = lightMaps();
  raytracer::LightTexture tex;
  tex.mesh = 1;
  tex.width = 4;
  tex.height = 3;
  for (int t = 0; t < 12; ++t) {
    const float f = float(t);
    tex.frontLux.emplace_back(100.1f + f, 200.2f + f / 3.0f, 300.3f + f / 7.0f);
    tex.frontStdErrorLux.emplace_back(1.1f + f, 2.2f, 3.3f);
    tex.backLux.emplace_back(5.5f + f / 9.0f, 6.6f, 7.7f);
    tex.backStdErrorLux.emplace_back(0.5f, 0.25f + f, 0.125f);
  }
  tex.baked.assign(12, 1);
  tex.bakedTexels = 12;
  m.lightTextures.push_back(tex);
  const BakeDescription d = description(true);
  writeDirectoryAtomic(dir_, [&](const fs::path& tmp) { writeBakedScene(tmp, r, m, d); });

  const json manifest = readBakedManifest(dir_);
  EXPECT_FALSE(manifest["objects"][0].contains("light_texture"));
  const json& t = manifest["objects"][1]["light_texture"];
  EXPECT_EQ(t["width"], 4);
  EXPECT_EQ(t["height"], 3);
  EXPECT_EQ(t["uv"], "generated");
  EXPECT_EQ(t["baked_texels"], 12);
  const std::pair<const char*, const std::vector<Rgb>*> files[] = {{"front", &tex.frontLux},
                                                                   {"front_stderr", &tex.frontStdErrorLux},
                                                                   {"back", &tex.backLux},
                                                                   {"back_stderr", &tex.backStdErrorLux}};
  for (const auto& [key, values] : files) {
    const std::string file = t.at(key).get<std::string>();
    EXPECT_NE(std::find(manifest["files"].begin(), manifest["files"].end(), file), manifest["files"].end())
        << file;
    ExrAttributes attributes;
    const ImageRgbF image = readExr(dir_ / file, &attributes);
    ASSERT_EQ(image.width, 4);
    ASSERT_EQ(image.height, 3);
    for (size_t i = 0; i < 12; ++i) {
      EXPECT_EQ(image.rgb[3 * i], (*values)[i].r) << file;
      EXPECT_EQ(image.rgb[3 * i + 1], (*values)[i].g) << file;
      EXPECT_EQ(image.rgb[3 * i + 2], (*values)[i].b) << file;
    }
    const std::pair<std::string, std::string> units("units", "lux");
    EXPECT_NE(std::find(attributes.begin(), attributes.end(), units), attributes.end());
  }
  for (const char* png : {"export/lightmaps/object1_front.png", "export/lightmaps/object1_back.png"}) {
    const ImageU8 image = readPng(dir_ / png);
    EXPECT_EQ(image.width, 4);
    EXPECT_EQ(image.height, 3);
  }

  const tinygltf::Model model = loadGltf(dir_ / "scene.gltf");
  const tinygltf::Primitive& wall = model.meshes.at(1).primitives.at(0);
  EXPECT_EQ(model.meshes.at(1).extras.Get("fly").Get("light_texture").Get("front").Get<std::string>(),
            "lightmaps/object1_front.exr");
  const std::vector<vec3> positions = readVec3s(model, wall.attributes.at("POSITION"));
  ASSERT_EQ(positions.size(), 6u);  // 4 + copies of vertices 0 and 2
  for (size_t v = 0; v < 4; ++v) EXPECT_EQ(positions[v], r.positionsM[4 + v]);
  EXPECT_EQ(positions[4], r.positionsM[4]);
  EXPECT_EQ(positions[5], r.positionsM[6]);
  const std::vector<vec3> irradiance = readVec3s(model, wall.attributes.at("_IRRADIANCE_BACK"));
  EXPECT_EQ(irradiance[5], m.backLux[6]);
  auto readFloats = [&](int accessor, int components) {
    const tinygltf::Accessor& a = model.accessors.at(size_t(accessor));
    const tinygltf::BufferView& view = model.bufferViews.at(size_t(a.bufferView));
    std::vector<float> out(a.count * size_t(components));
    std::memcpy(out.data(), model.buffers.at(0).data.data() + view.byteOffset + a.byteOffset,
                out.size() * sizeof(float));
    return out;
  };
  EXPECT_EQ(readFloats(wall.attributes.at("_SOURCE_VERTEX"), 1), (std::vector<float>{0, 1, 2, 3, 0, 2}));
  EXPECT_EQ(readFloats(wall.attributes.at("TEXCOORD_1"), 2),
            (std::vector<float>{0.1f, 0.1f, 0.4f, 0.1f, 0.4f, 0.9f, 0.6f, 0.9f, 0.6f, 0.1f, 0.9f, 0.9f}));
}

}  // namespace
}  // namespace fly::cli
