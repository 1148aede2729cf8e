// fly probe on a tiny bake made here through the commands themselves: the readings equal the stored vertex
// values, their barycentric interpolation and the light texture's texels (computed here from the store, not
// by the probe), on the side the sensor's normal faces; a point off every surface is an input error that
// writes nothing; the output lines up with fly illuminance's row by row.
#include "cli/baked_probe.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "base/error.h"
#include "cli/command.h"
#include "cli/raster_scene.h"
#include "cli/sensor_csv.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

struct QuadMesh {
  std::string name;
  vec3 corners[4];  // counter-clockwise seen from the front
};

// A 2 m × 2 m floor at y = 0 (vertex light map only), a two-sided wall at z = −0.5 (front towards +z), a 1 m
// panel with a light texture on the ground beside the floor, a shelf; a lamp on each side of the wall.
const QuadMesh kFloor{"Floor", {{-1, 0, 1}, {1, 0, 1}, {1, 0, -1}, {-1, 0, -1}}};
const QuadMesh kWall{"Wall", {{-1, 0, -0.5f}, {1, 0, -0.5f}, {1, 1, -0.5f}, {-1, 1, -0.5f}}};
const QuadMesh kPanel{"Panel", {{1.5f, 0, 0.5f}, {2.5f, 0, 0.5f}, {2.5f, 0, -0.5f}, {1.5f, 0, -0.5f}}};
// A shelf 3 cm over a corner of the floor: two surfaces within a sensor's reach.
const QuadMesh kShelf{
    "Shelf", {{-0.9f, 0.03f, 0.9f}, {-0.5f, 0.03f, 0.9f}, {-0.5f, 0.03f, 0.5f}, {-0.9f, 0.03f, 0.5f}}};
constexpr uint32_t kQuadIndices[6] = {0, 1, 2, 0, 2, 3};

void writeText(const fs::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
}

std::string readText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// probe.gltf + probe.bin: one node and mesh per quad, positions, normals and 32-bit indices.
void writeQuadsGltf(const fs::path& dir, const std::vector<QuadMesh>& quads) {
  std::string bin;
  json accessors = json::array(), views = json::array(), meshes = json::array(), nodes = json::array();
  const auto add = [&](const void* data, size_t bytes, json accessor, int target) {
    views.push_back({{"buffer", 0}, {"byteOffset", bin.size()}, {"byteLength", bytes}, {"target", target}});
    bin.append(static_cast<const char*>(data), bytes);
    accessor["bufferView"] = views.size() - 1;
    accessors.push_back(accessor);
    return accessors.size() - 1;
  };
  for (const QuadMesh& q : quads) {
    const vec3 n = glm::normalize(glm::cross(q.corners[1] - q.corners[0], q.corners[2] - q.corners[0]));
    const vec3 normals[4] = {n, n, n, n};
    const vec3 lo = glm::min(glm::min(q.corners[0], q.corners[1]), glm::min(q.corners[2], q.corners[3]));
    const vec3 hi = glm::max(glm::max(q.corners[0], q.corners[1]), glm::max(q.corners[2], q.corners[3]));
    const size_t p = add(q.corners, sizeof q.corners,
                         {{"componentType", 5126},
                          {"count", 4},
                          {"type", "VEC3"},
                          {"min", {lo.x, lo.y, lo.z}},
                          {"max", {hi.x, hi.y, hi.z}}},
                         34962);
    const size_t nn =
        add(normals, sizeof normals, {{"componentType", 5126}, {"count", 4}, {"type", "VEC3"}}, 34962);
    const size_t i = add(kQuadIndices, sizeof kQuadIndices,
                         {{"componentType", 5125}, {"count", 6}, {"type", "SCALAR"}}, 34963);
    meshes.push_back({{"name", q.name},
                      {"primitives", {{{"attributes", {{"POSITION", p}, {"NORMAL", nn}}}, {"indices", i}}}}});
    nodes.push_back({{"name", q.name}, {"mesh", meshes.size() - 1}});
  }
  json scene = {{"nodes", json::array()}};
  for (size_t k = 0; k < nodes.size(); ++k) scene["nodes"].push_back(k);
  const json gltf = {{"asset", {{"version", "2.0"}}},
                     {"scene", 0},
                     {"scenes", {scene}},
                     {"nodes", nodes},
                     {"meshes", meshes},
                     {"accessors", accessors},
                     {"bufferViews", views},
                     {"buffers", {{{"uri", "probe.bin"}, {"byteLength", bin.size()}}}}};
  writeText(dir / "probe.bin", bin);
  writeText(dir / "probe.gltf", gltf.dump(1));
}

// `fly ARGS…` through the commands' own parsing and running; InputError and UsageError propagate.
int runFly(const std::vector<std::string>& args) {
  CLI::App app("fly");
  app.require_subcommand(1);
  const std::vector<Command> commands = {addBakeCommand(app), addProbeCommand(app),
                                         addIlluminanceCommand(app)};
  std::vector<const char*> argv = {"fly"};
  for (const std::string& a : args) argv.push_back(a.c_str());
  try {
    app.parse(int(argv.size()), argv.data());
  } catch (const CLI::ParseError& e) {
    throw UsageError(e.what());
  }
  for (const Command& c : commands) {
    if (c.sub->parsed()) return c.run();
  }
  return -1;
}

// The exit code main.cpp gives those errors.
int exitCode(const std::vector<std::string>& args) {
  try {
    return runFly(args);
  } catch (const InputError&) {
    return kExitBadInput;
  } catch (const UsageError&) {
    return kExitUsage;
  }
}

// The scene and its bake, made once for all tests (8 samples: the values only need to be what the bake
// gives).
class BakedProbeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // CTest runs each test in a process of its own, in parallel: one directory per process.
    dir_ = new fs::path(fs::temp_directory_path() / ("fly_baked_probe_" + std::to_string(::getpid())));
    fs::remove_all(*dir_);
    fs::create_directories(*dir_);
    writeQuadsGltf(*dir_, {kFloor, kWall, kPanel, kShelf});
    const json scene = {
        {"fly", 1},
        {"models", {{{"file", "probe.gltf"}, {"name", "probe"}}}},
        {"sky", {{"model", "none"}, {"sun", false}}},
        {"lights",
         {{{"name", "front"}, {"type", "point"}, {"position", {0.3, 1.0, 0.4}}, {"intensity", 100}},
          {{"name", "back"}, {"type", "point"}, {"position", {-0.2, 0.6, -1.5}}, {"intensity", 60}}}},
        {"overrides", {{{"node", "Wall"}, {"twoSided", true}}, {{"node", "Floor"}, {"lightTexture", false}}}},
        {"bake", {{"texelsPerMetre", 8}, {"lightTextures", {"Panel"}}}}};
    writeText(*dir_ / "scene.json", scene.dump(1));
    // Vertex light maps everywhere but the panel: no automatic light textures where the lamps' pools are.
    ASSERT_EQ(runFly({"bake", (*dir_ / "scene.json").string(), "--samples", "8", "--threads", "2",
                      "--no-automatic-light-textures", "--out", (*dir_ / "bake").string()}),
              0);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
  }

  void SetUp() override {
    loaded_ = loadRasterScene(*dir_ / "bake", DaylightOptions{});
    ASSERT_TRUE(loaded_.lightMaps);
    rdb_ = rdb::buildRasterRdb(loaded_.scene, &*loaded_.lightMaps);
  }

  // The stored light map of the node called `name`, whose SDB mesh must hold the quad's corners in order.
  const rdb::MeshLightMap& stored(const QuadMesh& q) const {
    const sdb::NodeId node = loaded_.scene.findNode(q.name);
    const sdb::MeshId mesh = loaded_.scene.node(node).meshes.at(0);
    const std::vector<vec3>& positions = loaded_.scene.mesh(mesh).positions;
    EXPECT_EQ(positions.size(), 4u);
    for (size_t k = 0; k < 4 && k < positions.size(); ++k)
      EXPECT_EQ(positions[k], q.corners[k]) << q.name << " " << k;
    const rdb::MeshLightMap* map = loaded_.lightMaps->find(node.value, mesh.value);
    if (!map) throw std::runtime_error("no light map for " + q.name);
    return *map;
  }

  SensorReading probeOne(const vec3& p, const vec3& n, float maxDistanceM = 0.05f) const {
    SensorTable t;
    t.header = "x,y,z,nx,ny,nz";
    t.lines = {"-"};
    t.positionsM = {p};
    t.normals = {glm::normalize(n)};
    t.lineNumbers = {2};
    return probeSensors(rdb_, *loaded_.lightMaps, loaded_.scene, t, maxDistanceM, "points.csv", "bake").at(0);
  }

  static fs::path* dir_;
  RasterScene loaded_;
  rdb::RasterRdb rdb_;
};

fs::path* BakedProbeTest::dir_ = nullptr;

void expectRelativeNear(double actual, double expected, const std::string& what) {
  EXPECT_NEAR(actual, expected, 1e-5 * std::abs(expected) + 1e-9) << what;
}

TEST_F(BakedProbeTest, AtAVertexReadsTheStoredValueFromEitherSideOfTheSurface) {
  const rdb::MeshLightMap& floor = stored(kFloor);
  ASSERT_TRUE(floor.backLux.empty());
  for (uint32_t k = 0; k < 4; ++k) {
    const double e = luminance(floor.frontLux[k]), s = luminance(floor.frontStdErrorLux[k]);
    ASSERT_GT(e, 0.0) << "vertex " << k;
    // On the surface, 3 cm above and 2 cm below it: the same surface, facing up.
    for (const float dy : {0.0f, 0.03f, -0.02f}) {
      const SensorReading r = probeOne(kFloor.corners[k] + vec3(0, dy, 0), vec3(0, 1, 0));
      const std::string what = "floor vertex " + std::to_string(k) + " dy " + std::to_string(dy);
      EXPECT_FALSE(r.lux.fromLightTexture) << what;
      EXPECT_FALSE(r.lux.back) << what;
      expectRelativeNear(r.lux.illuminanceLuminanceLux, e, what);
      expectRelativeNear(*r.lux.stdErrorLuminanceLux, s, what);
      EXPECT_NEAR(r.distanceM, std::abs(dy), 1e-6) << what;
    }
  }
  // The two-sided wall: a sensor facing −z reads its back, one facing +z its front.
  const rdb::MeshLightMap& wall = stored(kWall);
  ASSERT_EQ(wall.backLux.size(), 4u);
  for (uint32_t k = 0; k < 4; ++k) {
    const std::string what = "wall vertex " + std::to_string(k);
    const SensorReading back = probeOne(kWall.corners[k] + vec3(0, 0, -0.01f), vec3(0, 0, -1));
    EXPECT_TRUE(back.lux.back) << what;
    expectRelativeNear(back.lux.illuminanceLuminanceLux, luminance(wall.backLux[k]), what + " back");
    expectRelativeNear(*back.lux.stdErrorLuminanceLux, luminance(wall.backStdErrorLux[k]), what + " back");
    // Behind the wall, but facing its front.
    const SensorReading front = probeOne(kWall.corners[k] + vec3(0, 0, -0.01f), vec3(0, 0, 1));
    EXPECT_FALSE(front.lux.back) << what;
    expectRelativeNear(front.lux.illuminanceLuminanceLux, luminance(wall.frontLux[k]), what + " front");
    EXPECT_NE(luminance(wall.frontLux[k]), luminance(wall.backLux[k])) << what;
  }
}

TEST_F(BakedProbeTest, InsideATriangleInterpolatesTheStoredValuesWithBarycentrics) {
  const rdb::MeshLightMap& floor = stored(kFloor);
  // Triangle 0 (corners 0, 1, 2) holds x + z > 0. Barycentrics by areas in the (x, z) plane.
  const vec3 q(0.5f, 0.0f, 0.2f);
  const auto area = [](const vec3& a, const vec3& b, const vec3& c) {
    return 0.5 * ((double(b.x) - a.x) * (double(c.z) - a.z) - (double(c.x) - a.x) * (double(b.z) - a.z));
  };
  const vec3* c = kFloor.corners;
  const double total = area(c[0], c[1], c[2]);
  const double w[3] = {area(q, c[1], c[2]) / total, area(c[0], q, c[2]) / total, area(c[0], c[1], q) / total};
  double e = 0.0, variance = 0.0;
  for (int k = 0; k < 3; ++k) {
    ASSERT_GT(w[k], 0.0);
    e += w[k] * luminance(floor.frontLux[k]);
    const double s = luminance(floor.frontStdErrorLux[k]);
    variance += w[k] * w[k] * s * s;
  }
  const SensorReading r = probeOne(q + vec3(0, 0.01f, 0), vec3(0, 1, 0));
  expectRelativeNear(r.lux.illuminanceLuminanceLux, e, "illuminance");
  expectRelativeNear(*r.lux.stdErrorLuminanceLux, std::sqrt(variance), "standard error");
  EXPECT_NEAR(r.distanceM, 0.01, 1e-6);
}

// Of two surfaces within reach, the one nearer the point is read, whichever the ray meets first.
TEST_F(BakedProbeTest, OfTwoSurfacesTheNearerToThePointIsRead) {
  const uint32_t floor = loaded_.scene.findNode("Floor").value, shelf = loaded_.scene.findNode("Shelf").value;
  const SensorReading onFloor = probeOne(vec3(-0.7f, 0.0f, 0.7f), vec3(0, 1, 0));
  EXPECT_EQ(onFloor.lux.sdbNodeId, floor);
  EXPECT_NEAR(onFloor.distanceM, 0.0, 1e-6);
  const SensorReading nearShelf = probeOne(vec3(-0.7f, 0.02f, 0.7f), vec3(0, 1, 0));
  EXPECT_EQ(nearShelf.lux.sdbNodeId, shelf);
  EXPECT_NEAR(nearShelf.distanceM, 0.01, 1e-6);
  // Within 1 cm only the floor is in reach from just below it; within 5 mm, nothing.
  EXPECT_EQ(probeOne(vec3(-0.7f, -0.008f, 0.7f), vec3(0, 1, 0), 0.01f).lux.sdbNodeId, floor);
  EXPECT_THROW(probeOne(vec3(-0.7f, -0.008f, 0.7f), vec3(0, 1, 0), 0.005f), InputError);
}

TEST_F(BakedProbeTest, OnALightTextureReadsTheTexelUnderThePoint) {
  const rdb::MeshLightMap& panel = stored(kPanel);
  ASSERT_TRUE(panel.lightTexture);
  const rdb::MeshLightTexture& tex = *panel.lightTexture;
  ASSERT_GE(tex.cornerUv.size(), 3u);
  // A texel whose centre lies well inside triangle 0's UV triangle; the point is that centre mapped back to
  // the panel by its UV barycentrics (affine within a triangle).
  const vec2* uv = tex.cornerUv.data();
  const auto cross2 = [](const vec2& a, const vec2& b) { return double(a.x) * b.y - double(a.y) * b.x; };
  const double total = cross2(uv[1] - uv[0], uv[2] - uv[0]);
  bool found = false;
  for (uint32_t j = 0; j < tex.height && !found; ++j) {
    for (uint32_t i = 0; i < tex.width && !found; ++i) {
      const vec2 centre((float(i) + 0.5f) / float(tex.width), (float(j) + 0.5f) / float(tex.height));
      const double w1 = cross2(centre - uv[0], uv[2] - uv[0]) / total;
      const double w2 = cross2(uv[1] - uv[0], centre - uv[0]) / total;
      const double w0 = 1.0 - w1 - w2;
      if (w0 < 0.1 || w1 < 0.1 || w2 < 0.1) continue;
      found = true;
      const vec3 p =
          float(w0) * kPanel.corners[0] + float(w1) * kPanel.corners[1] + float(w2) * kPanel.corners[2];
      const size_t texel = size_t(j) * tex.width + i;
      const SensorReading r = probeOne(p, vec3(0, 1, 0));
      EXPECT_TRUE(r.lux.fromLightTexture);
      ASSERT_GT(luminance(tex.frontLux[texel]), 0.0);
      expectRelativeNear(r.lux.illuminanceLuminanceLux, luminance(tex.frontLux[texel]), "texel value");
      expectRelativeNear(*r.lux.stdErrorLuminanceLux, luminance(tex.frontStdErrorLux[texel]), "texel error");
    }
  }
  EXPECT_TRUE(found) << tex.width << " x " << tex.height << " texels";
}

TEST_F(BakedProbeTest, APointOffEverySurfaceIsAnInputErrorAndWritesNothing) {
  const fs::path points = *dir_ / "off.csv", out = *dir_ / "off-out.csv";
  writeText(points, "x,y,z,nx,ny,nz\n0,0,0,0,1,0\n\n0,0.5,0,0,1,0\n");
  EXPECT_EQ(
      exitCode({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out", out.string()}),
      kExitBadInput);
  try {
    runFly({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out", out.string()});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().file, points.string());
    EXPECT_EQ(e.location().line, 4);
    EXPECT_NE(e.message().find("no surface within 0.05 m of the point (0, 0.5, 0)"), std::string::npos)
        << e.what();
    EXPECT_NE(e.hint().find("raise --max-distance"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  // Half a metre is enough for it.
  EXPECT_EQ(runFly({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out", out.string(),
                    "--max-distance", "0.5"}),
            0);
  EXPECT_TRUE(fs::exists(out));
  for (const char* bad : {"0", "-1", "nan", "inf", "1e4", "near"}) {
    EXPECT_EQ(exitCode({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out",
                        (*dir_ / "bad.csv").string(), "--max-distance", bad}),
              kExitUsage)
        << bad;
  }
  EXPECT_FALSE(fs::exists(*dir_ / "bad.csv"));
}

TEST_F(BakedProbeTest, ASurfaceWithoutALightMapIsAnInputError) {
  // The scene gains a second copy of the model after the bake: its meshes have no light maps.
  json scene = json::parse(readText(*dir_ / "scene.json"));
  scene["models"].push_back({{"file", "probe.gltf"}, {"name", "copy"}, {"translation", {10, 0, 0}}});
  writeText(*dir_ / "scene.json", scene.dump(1));
  const fs::path points = *dir_ / "copy.csv", out = *dir_ / "copy-out.csv";
  writeText(points, "x,y,z,nx,ny,nz\n10,0,0,0,1,0\n");
  try {
    runFly({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out", out.string()});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 2);
    EXPECT_NE(e.message().find("(node \"Floor\") has no light map"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(out));
  scene["models"].erase(1);
  writeText(*dir_ / "scene.json", scene.dump(1));
}

// fly illuminance and fly probe on one sensor file: the same rows in the same order, the same first columns,
// illuminance_lux and std_error_lux at the same positions, then source and distance_m.
TEST_F(BakedProbeTest, TheOutputLinesUpWithFlyIlluminanceRowByRow) {
  const fs::path points = *dir_ / "sensors.csv";
  writeText(points,
            "name,x,y,z,nx,ny,nz\r\nfloor-corner,-1,0,1,0,1,0\r\nwall-back,0.2,0.5,-0.5,0,0,-1\r\n"
            "panel,2.1,0.01,0.1,0,1,0\r\n");
  const fs::path lux = *dir_ / "illuminance.csv", probed = *dir_ / "probe.csv";
  ASSERT_EQ(runFly({"illuminance", (*dir_ / "scene.json").string(), "--points", points.string(), "--samples",
                    "16", "--threads", "2", "--out", lux.string()}),
            0);
  ASSERT_EQ(
      runFly({"probe", (*dir_ / "bake").string(), "--points", points.string(), "--out", probed.string()}), 0);
  std::istringstream a(readText(lux)), b(readText(probed));
  std::string la, lb;
  ASSERT_TRUE(std::getline(a, la) && std::getline(b, lb));
  EXPECT_EQ(la, "name,x,y,z,nx,ny,nz,illuminance_lux,std_error_lux");
  EXPECT_EQ(lb, la + ",source,distance_m");
  const char* sources[3] = {"vertices", "vertices", "light-texture"};
  for (int row = 0; row < 3; ++row) {
    ASSERT_TRUE(std::getline(a, la) && std::getline(b, lb)) << "row " << row;
    const std::vector<std::string> fa = splitCsvFields(la), fb = splitCsvFields(lb);
    ASSERT_EQ(fa.size(), 9u);
    ASSERT_EQ(fb.size(), 11u);
    for (size_t k = 0; k < 7; ++k) EXPECT_EQ(fa[k], fb[k]) << "row " << row << " column " << k;
    // The values are the readings (which the tests above check against the store).
    const SensorReading r = probeOne(vec3(std::stof(fb[1]), std::stof(fb[2]), std::stof(fb[3])),
                                     vec3(std::stof(fb[4]), std::stof(fb[5]), std::stof(fb[6])));
    EXPECT_EQ(fb[7], csvNumber(r.lux.illuminanceLuminanceLux)) << lb;
    EXPECT_EQ(fb[8], csvNumber(*r.lux.stdErrorLuminanceLux)) << lb;
    EXPECT_EQ(fb[9], sources[row]) << lb;
    EXPECT_EQ(fb[10], row == 2 ? "0.01" : "0") << lb;
  }
  EXPECT_FALSE(std::getline(b, lb));
}

}  // namespace
}  // namespace fly::cli
