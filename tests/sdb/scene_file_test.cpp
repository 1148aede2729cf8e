#include "sdb/scene_file.h"

#include <gtest/gtest.h>

#include <algorithm>

#include <glm/gtc/matrix_transform.hpp>

#include <initializer_list>
#include <string>

#include "base/error.h"
#include "base/file_io.h"
#include "gltf_builder.h"
#include "sdb/features.h"
#include "sdb/measured_brdf.h"

namespace fly::sdb {
namespace {

const std::filesystem::path kDataDir = FLY_TEST_DATA_DIR "/scene_file";

Scene parse(const std::string& text) {
  return parseSceneFile(text, "s.json", kDataDir);
}

// Expects an InputError whose text begins with "s.json:<where> (at <path>)" and contains each of `parts`.
void expectError(const std::string& text, const std::string& where, const std::string& path,
                 std::initializer_list<std::string> parts) {
  SCOPED_TRACE(text);
  try {
    parse(text);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string head = "s.json:" + where + (path.empty() ? ":" : " (at " + path + "):");
    EXPECT_EQ(what.substr(0, head.size()), head) << what;
    for (const std::string& p : parts)
      EXPECT_NE(what.find(p), std::string::npos) << "missing: " << p << "\n" << what;
  }
}

const Node& nodeNamed(const Scene& s, const std::string& name) {
  const NodeId id = s.findNode(name);
  EXPECT_TRUE(id) << name;
  return s.node(id);
}

void expectNear(const vec3& a, const vec3& b) {
  EXPECT_NEAR(a.x, b.x, 1e-5f);
  EXPECT_NEAR(a.y, b.y, 1e-5f);
  EXPECT_NEAR(a.z, b.z, 1e-5f);
}

vec3 transformPoint(const mat4& m, const vec3& p) {
  return vec3(m * vec4(p, 1.0f));
}

TEST(SceneFile, CompleteExampleParses) {
  const std::filesystem::path file = kDataDir / "complete.json";
  const Scene s = loadSceneFile(file);
  EXPECT_EQ(s.sourcePath, file);

  ASSERT_TRUE(s.hasSite());
  EXPECT_DOUBLE_EQ(s.site().latitudeDeg, 60.17);
  EXPECT_DOUBLE_EQ(s.site().longitudeDeg, 24.94);
  EXPECT_DOUBLE_EQ(s.site().elevationM, 20.0);
  EXPECT_EQ(s.site().timeZone, "Europe/Helsinki");
  EXPECT_DOUBLE_EQ(s.site().northAngleDeg, 15.0);
  EXPECT_EQ(s.time().localDateTime, "2026-06-21T12:00");
  EXPECT_EQ(s.sky().model, SkyModel::kCie);
  EXPECT_EQ(s.sky().cieType, 12);
  EXPECT_DOUBLE_EQ(s.sky().turbidity, 3.5);
  EXPECT_DOUBLE_EQ(s.sky().groundAlbedo, 0.2);  // the default
  EXPECT_TRUE(s.sky().sun);
  EXPECT_EQ(s.sky().weatherFile, "");

  // The model's node: T(10, 0, −5) · Ry(90°) · S(2); local +X → world −Z.
  const Node& car = nodeNamed(s, "car");
  EXPECT_FALSE(car.parent);
  expectNear(transformPoint(car.parentFromLocal, vec3(1, 0, 0)), vec3(10, 0, -7));
  expectNear(transformPoint(car.parentFromLocal, vec3(0, 1, 0)), vec3(10, 2, -5));
  const Node& carRoot = nodeNamed(s, "Car");
  EXPECT_EQ(carRoot.parent, s.findNode("car"));

  // Overrides: presets by exact name and by prefix, parameters on top.
  const Material& glass = s.material(s.findMaterial("Glass"));
  EXPECT_EQ(glass.preset, "clear-glass");
  EXPECT_EQ(glass.transmissionColor, Rgb(1.0f));
  const Material& paint = s.material(s.findMaterial("Paint"));
  EXPECT_EQ(paint.preset, "car-paint");
  EXPECT_EQ(paint.diffuseColor, Rgb(0.1f, 0.2f, 0.6f));

  // The node override gives the window's mesh a material of its own, derived from the (overridden) glass.
  const Mesh& pane = s.mesh(s.findMesh("Pane"));
  const Material& paneMaterial = s.material(pane.material);
  EXPECT_EQ(paneMaterial.name, "Glass@Window");
  EXPECT_EQ(paneMaterial.preset, "clear-glass");
  EXPECT_EQ(paneMaterial.transmissionColor, Rgb(0.5f));
  EXPECT_TRUE(pane.twoSided);
  EXPECT_TRUE(pane.lightTexture.enabled);
  EXPECT_FLOAT_EQ(pane.lightTexture.texelsPerMetre, 40.0f);
  const Mesh& body = s.mesh(s.findMesh("Body"));
  EXPECT_EQ(body.material, s.findMaterial("Paint"));
  EXPECT_FALSE(body.twoSided);
  // Named in bake.lightTextures: a light texture at the bake's density (0 = bake.texelsPerMetre).
  EXPECT_TRUE(body.lightTexture.enabled);
  EXPECT_EQ(body.lightTexture.texelsPerMetre, 0.0f);

  ASSERT_EQ(s.lights().size(), 4u);
  const Node& bulbNode = nodeNamed(s, "bulb");
  const Light& bulb = s.light(bulbNode.light);
  EXPECT_EQ(bulb.type, LightType::kPoint);
  EXPECT_FLOAT_EQ(bulb.intensity, 100.0f);
  EXPECT_FLOAT_EQ(bulb.rangeM, 20.0f);
  EXPECT_EQ(bulb.color, Rgb(1.0f, 0.9f, 0.8f));
  expectNear(vec3(bulbNode.parentFromLocal[3]), vec3(0, 3, 0));

  const Light& spot = s.light(nodeNamed(s, "spot").light);
  EXPECT_EQ(spot.type, LightType::kSpot);
  EXPECT_FLOAT_EQ(spot.innerConeRad, glm::radians(20.0f));
  EXPECT_FLOAT_EQ(spot.outerConeRad, glm::radians(30.0f));
  EXPECT_TRUE(std::isinf(spot.rangeM));

  const Node& moonNode = nodeNamed(s, "moon");
  EXPECT_EQ(s.light(moonNode.light).type, LightType::kDirectional);
  EXPECT_FLOAT_EQ(s.light(moonNode.light).intensity, 0.3f);
  expectNear(-vec3(moonNode.parentFromLocal[2]), glm::normalize(vec3(1, -1, 0)));  // shines along local −Z

  // The IES light: −Z down, +X (the C = 0° plane) along c0Direction, a right-handed orthonormal frame.
  const Node& downNode = nodeNamed(s, "downlight");
  const Light& down = s.light(downNode.light);
  EXPECT_EQ(down.type, LightType::kGoniometric);
  ASSERT_NE(down.ies, nullptr);
  EXPECT_EQ(down.ies->verticalDeg.size(), 3u);
  EXPECT_FLOAT_EQ(down.intensity, 2.0f);
  EXPECT_EQ(std::filesystem::path(down.iesPath).filename(), "downlight.ies");
  const mat4& f = downNode.parentFromLocal;
  expectNear(vec3(f[0]), vec3(0, 0, 1));
  expectNear(vec3(f[2]), vec3(0, 1, 0));
  expectNear(glm::cross(vec3(f[0]), vec3(f[1])), vec3(f[2]));
  expectNear(vec3(f[3]), vec3(0, 2.8f, 1));

  const BakeSettings& bake = s.bakeSettings();
  EXPECT_EQ(bake.samples, 256u);
  EXPECT_DOUBLE_EQ(bake.targetErrorRel, 0.02);
  EXPECT_DOUBLE_EQ(bake.timeLimitS, 5400.0);
  EXPECT_EQ(bake.maxBounces, 4u);
  EXPECT_DOUBLE_EQ(bake.texelsPerMetre, 25.0);
  EXPECT_EQ(bake.lightTextureNames, std::vector<std::string>{"Body"});

  ASSERT_EQ(s.cameras().size(), 2u);
  const Node& frontNode = nodeNamed(s, "front");
  const Camera& front = s.camera(frontNode.camera);
  EXPECT_EQ(front.name, "front");
  EXPECT_FLOAT_EQ(front.yfovRad, glm::radians(40.0f));
  EXPECT_FLOAT_EQ(front.znearM, 0.1f);
  EXPECT_FLOAT_EQ(front.zfarM, 500.0f);
  expectNear(vec3(frontNode.parentFromLocal[3]), vec3(0, 1.6f, 10));
  expectNear(-vec3(frontNode.parentFromLocal[2]), glm::normalize(vec3(0, -0.6f, -10)));
  const Node& topNode = nodeNamed(s, "top");
  expectNear(vec3(topNode.parentFromLocal[1]), vec3(0, 0, -1));  // the given up
  EXPECT_FLOAT_EQ(s.camera(topNode.camera).yfovRad, glm::radians(50.0f));
  EXPECT_TRUE(std::isinf(s.camera(topNode.camera).zfarM));
}

TEST(SceneFile, MinimalScenesAndDefaults) {
  // Lights alone are a legal scene; models may be absent or empty.
  const Scene lightsOnly =
      parse(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": 5}]})");
  ASSERT_EQ(lightsOnly.lights().size(), 1u);
  EXPECT_EQ(lightsOnly.lights().begin()->second.name, "light 0");
  EXPECT_FALSE(lightsOnly.hasSite());

  const Scene empty = parse(R"({"fly": 1, "models": []})");
  EXPECT_TRUE(empty.nodes().empty());
  EXPECT_EQ(empty.sky().model, SkyModel::kNone);
  EXPECT_EQ(empty.bakeSettings().samples, 0u);
  EXPECT_FALSE(empty.bakeSettings().maxBounces);  // unbounded: paths end by Russian roulette

  // A leap day, a leap second, a UTC offset, durations and errors in other forms.
  const Scene s = parse(R"({"fly": 1,
    "site": {"latitude": -33.9, "longitude": 151.2, "timeZone": "+10:00"},
    "time": "2024-02-29T23:59:60",
    "bake": {"targetError": 0.05, "time": 90, "samples": 0}})");
  EXPECT_EQ(s.site().timeZone, "+10:00");
  EXPECT_DOUBLE_EQ(s.site().elevationM, 0.0);
  EXPECT_EQ(s.time().localDateTime, "2024-02-29T23:59:60");
  EXPECT_DOUBLE_EQ(s.bakeSettings().targetErrorRel, 0.05);
  EXPECT_DOUBLE_EQ(s.bakeSettings().timeLimitS, 90.0);
  EXPECT_DOUBLE_EQ(parse(R"({"fly": 1, "bake": {"time": "2.5m"}})").bakeSettings().timeLimitS, 150.0);
}

TEST(SceneFile, ModelsMirroringAndNodeOverridesByPrefix) {
  const Scene s = parse(R"({"fly": 1,
    "models": [{"file": "car.gltf", "name": "left", "scale": [-1, 1, 1], "namePrefix": "L/"},
               {"file": "car.gltf"}],
    "overrides": [{"node": "L/Win*", "preset": "frosted-glass"}],
    "bake": {"lightTextures": ["Win*", "Car", "Window"]}})");
  const Node& left = nodeNamed(s, "left");
  expectNear(transformPoint(left.parentFromLocal, vec3(1, 0, 0)), vec3(-1, 0, 0));
  EXPECT_EQ(nodeNamed(s, "L/Car").parent, s.findNode("left"));
  EXPECT_EQ(nodeNamed(s, "Car").parent, s.findNode("car"));  // the name defaults to the file's stem
  // Only the prefixed model's pane changed. (Under a mirroring node the importer gives the node a mirrored
  // copy of the mesh; the override follows the node.)
  const Node& leftWindow = nodeNamed(s, "L/Window");
  ASSERT_EQ(leftWindow.meshes.size(), 1u);
  const Material& frosted = s.material(s.mesh(leftWindow.meshes[0]).material);
  EXPECT_EQ(frosted.name, "L/Glass@L/Win*");
  EXPECT_EQ(frosted.preset, "frosted-glass");
  EXPECT_EQ(s.material(s.mesh(nodeNamed(s, "Window").meshes[0]).material).name, "Glass");
  EXPECT_EQ(s.material(s.findMaterial("L/Glass")).preset, "");
  // Name patterns are expanded, each name listed once.
  EXPECT_EQ(s.bakeSettings().lightTextureNames, (std::vector<std::string>{"Window", "Car"}));
}

TEST(SceneFile, UnknownKeysAreErrorsAtTheirLocation) {
  expectError(
      "{\n  \"fly\": 1,\n  \"nmae\": \"x\"\n}", "3:3", "/nmae",
      {"unknown key \"nmae\" at the top level; expected one of: fly, models, site, time, sky, lights, "
       "overrides, bake, cameras"});
  expectError(R"({
  "fly": 1,
  "site": {"latitude": 60, "longitude": 25, "timeZone": "Z"},
  "time": "2026-06-21T12:00",
  "sky": {
    "model": "clear",
    "sunn": true
  }
})",
              "7:5", "/sky/sunn",
              {"unknown key \"sunn\" in /sky; expected one of: model, cieType, turbidity, weatherFile, sun, groundAlbedo",
               "hint: did you mean \"sun\"?"});
  expectError("{\"fly\": 1,\n \"lights\": [{\"type\": \"point\", \"Position\": [0, 0, 0]}]}", "2:31",
              "/lights/0/Position", {"unknown key \"Position\" in /lights/0", "did you mean \"position\"?"});
  // Keys that exist but do not apply.
  expectError(
      "{\"fly\": 1,\n \"lights\": [{\"type\": \"point\", \"position\": [0, 0, 0], \"intensity\": 1,\n"
      "   \"innerConeDeg\": 10}]}",
      "3:4", "/lights/0/innerConeDeg", {"\"innerConeDeg\" applies to spot lights only", "type \"point\""});
  expectError(R"({"fly": 1, "sky": {"model": "perez", "cieType": 3}})", "1:38", "/sky/cieType",
              {"applies to the CIE sky only"});
}

TEST(SceneFile, GroundAlbedoIsReadForAnySky) {
  EXPECT_DOUBLE_EQ(parse(R"({"fly": 1, "sky": {"groundAlbedo": 0.45}})").sky().groundAlbedo, 0.45);
  EXPECT_DOUBLE_EQ(parse(R"({"fly": 1, "sky": {"groundAlbedo": 0}})").sky().groundAlbedo, 0.0);
}

TEST(SceneFile, WrongTypesAndRanges) {
  expectError("{\"fly\": 1,\n \"site\": {\"latitude\": \"60.17\", \"longitude\": 24.94}}", "2:23",
              "/site/latitude", {"expected a number in degrees, [-90, 90]; got a string (\"60.17\")"});
  expectError("{\"fly\": 1,\n \"site\": {\"latitude\": 95, \"longitude\": 24.94}}", "2:23", "/site/latitude",
              {"expected a number in degrees, [-90, 90]; got 95"});
  expectError("{\"fly\": 1,\n \"site\": {\"longitude\": 24.94}}", "2:10", "/site",
              {"missing key \"latitude\""});
  expectError(R"({"fly": 1, "site": []})", "1:20", "/site", {"expected an object with the keys latitude"});
  expectError(R"({"fly": 1, "models": {"file": "car.gltf"}})", "1:22", "/models",
              {"expected an array of models"});
  expectError(R"({"fly": 1, "sky": {"model": "cei"}})", "1:29", "/sky/model",
              {"expected one of \"none\", \"cie\", \"perez\", \"clear\", \"preetham\"; got a string (\"cei\")",
               "did you mean \"cie\"?"});
  expectError(R"({"fly": 1, "sky": {"sun": "yes"}})", "1:27", "/sky/sun",
              {"expected true or false; got a string"});
  expectError(R"({"fly": 1, "sky": {"groundAlbedo": 1.5}})", "1:36", "/sky/groundAlbedo",
              {"ground reflectance", "[0, 1]; got 1.5"});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1], "intensity": 1}]})", "1:53",
              "/lights/0/position",
              {"expected an array of 3 numbers [x, y, z] in metres; got an array of 2 elements"});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 1e39], "intensity": 1}]})",
              "1:60", "/lights/0/position/2", {"too large"});
  expectError(R"({"fly": 1, "lights": [{"type": "point", "position": [0, 1, 0], "intensity": -1}]})", "1:77",
              "/lights/0/intensity", {"expected a number in candela, ≥ 0; got -1"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "spot", "position": [0, 1, 0], "intensity": 1, "innerConeDeg": 40, "outerConeDeg": 30}]})",
      "1:95", "/lights/0/innerConeDeg", {"innerConeDeg (40) must be smaller than outerConeDeg (30)"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "spot", "position": [0, 1, 0], "direction": [0, 0, 0], "intensity": 1}]})",
      "1:76", "/lights/0/direction", {"a direction must not be the zero vector"});
  expectError(
      R"({"fly": 1, "lights": [{"type": "ies", "position": [0, 1, 0], "file": "downlight.ies", "c0Direction": [0, 2, 0]}]})",
      "1:102", "/lights/0/c0Direction", {"must not be parallel to the light's direction"});
  expectError(R"({"fly": 1, "bake": {"samples": 300}})", "1:32", "/bake/samples",
              {"expected 0 or a power of two; got 300", "256 and 512"});
  expectError(R"({"fly": 1, "bake": {"maxBounces": 2.5}})", "1:35", "/bake/maxBounces",
              {"expected an integer (indirect bounces), [0, 10000]; got 2.5"});
  expectError(R"({"fly": 1, "bake": {"targetError": "150%"}})", "1:36", "/bake/targetError", {"percentage"});
  expectError(R"({"fly": 1, "bake": {"targetError": 1}})", "1:36", "/bake/targetError", {"(0, 1); got 1"});
  expectError(R"({"fly": 1, "bake": {"time": "5 minutes"}})", "1:29", "/bake/time", {"expected a duration"});
  expectError(R"({"fly": 1, "bake": {"lightTextures": ["Floor"]}})", "1:39", "/bake/lightTextures/0",
              {"no mesh or node named \"Floor\"; mesh or nodes in the scene: none"});
  expectError(R"({"fly": 1, "site": {"latitude": 0, "longitude": 0, "timeZone": "+3"}})", "1:64",
              "/site/timeZone", {"expected an IANA time-zone name"});
  expectError(R"({"fly": 1, "models": [{"file": "car.gltf", "scale": [1, 0, 1]}]})", "1:53",
              "/models/0/scale", {"a scale factor of 0"});
}

TEST(SceneFile, BadTimes) {
  const auto timeError = [](const std::string& t, const std::string& message) {
    expectError(R"({"fly": 1, "time": ")" + t + R"("})", "1:20", "/time", {message});
  };
  timeError("2026-02-30T12:00", "day 30 is outside 1..28 for February 2026");
  timeError("2024-02-30T12:00", "day 30 is outside 1..29 for February 2024");
  timeError("2026-04-31T12:00", "day 31 is outside 1..30 for April 2026");
  timeError("2026-13-01T12:00", "month 13 is outside 1..12");
  timeError("2026-06-21T24:00", "hour 24 is outside 0..23");
  timeError("2026-06-21T12:60", "minute 60 is outside 0..59");
  timeError("2026-06-21T12:00:61", "second 61 is outside 0..60");
  timeError("2026-06-21 12:00", "expected a local date and time YYYY-MM-DDThh:mm[:ss]");
  timeError("2026-6-21T12:00", "expected a local date and time");
  timeError("2026-06-21T12:00Z", "the zone belongs in site.timeZone");
  timeError("2026-06-21T12:00:00.5", "fractions of a second");
  // A valid time needs a site with a time zone.
  expectError(R"({"fly": 1, "time": "2026-06-21T12:00"})", "1:20", "/time", {"needs a site"});
  expectError(R"({"fly": 1, "site": {"latitude": 1, "longitude": 2}, "time": "2026-06-21T12:00"})", "1:20",
              "/site", {"the site has no \"timeZone\""});
  // The sun and skies need both.
  expectError(R"({"fly": 1, "sky": {"sun": true}})", "1:27", "/sky/sun",
              {"the sun needs a site and a local time"});
  expectError(R"({"fly": 1, "sky": {"model": "clear"}})", "1:29", "/sky/model",
              {"needs a site and a local time"});
}

TEST(SceneFile, Version) {
  expectError(R"({"models": []})", "1:1", "",
              {"missing key \"fly\"", "hint: begin the file with { \"fly\": 1"});
  expectError(R"({"fly": 2})", "1:9", "/fly", {"unsupported scene-file version 2; this fly reads version 1"});
  expectError(R"({"fly": "1"})", "1:9", "/fly", {"expected the format version as an integer"});
  expectError(R"([{"fly": 1}])", "1:1", "", {"expected a JSON object at the top level; got an array"});
  // JSON syntax errors come from the parser with their location.
  expectError("{\"fly\": 1,\n}", "1:10", "", {"trailing comma"});
}

TEST(SceneFile, OverridesMustMatchAndPresetsMustExist) {
  expectError(
      "{\"fly\": 1,\n \"models\": [{\"file\": \"car.gltf\"}],\n"
      " \"overrides\": [{\"material\": \"Paint\", \"ior\": 1.4}, {\"material\": \"Glas\", \"preset\": "
      "\"clear-glass\"}]}",
      "3:64", "/overrides/1/material",
      {"no material named \"Glas\"; materials in the scene: Glass, Paint", "did you mean \"Glass\"?"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"node": "Door", "twoSided": true}]})",
      "1:69", "/overrides/0/node", {"no node named \"Door\"; nodes in the scene: Car, Window, car"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass", "preset": "glas"}]})",
      "1:92", "/overrides/0/preset",
      {"unknown preset \"glas\"; the presets are: matte-plastic, shiny-plastic", "frosted-glass, fabric"});
  expectError(R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass"}]})", "1:60",
              "/overrides/0", {"the override changes nothing"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass", "node": "Car", "ior": 2}]})",
      "1:73", "/overrides/0/material", {"either a material or a node, not both"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass", "twoSided": true}]})",
      "1:82", "/overrides/0/twoSided", {"applies to node overrides only"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass", "diffuse": [0.5, 2, 0]}]})",
      "1:99", "/overrides/0/diffuse/1", {"expected a number, [0, 1]; got 2"});
  expectError(
      R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Glass", "engineReflection": "mirror"}]})",
      "1:102", "/overrides/0/engineReflection", {"expected \"auto\", \"planar\", \"cubemap\" or \"none\"; got a string (\"mirror\")"});
}

// How the OpenGL engine shows a material's reflection, per material (docs/reflections.md).
TEST(SceneFile, EngineReflectionPerMaterial) {
  const Scene s = parse(R"({"fly": 1, "models": [{"file": "car.gltf"}],
    "overrides": [{"material": "Paint", "engineReflection": "planar"}, {"material": "Glass", "engineReflection": "none"}]})");
  EXPECT_EQ(s.material(s.findMaterial("Paint")).engineReflection, EngineReflection::kPlanar);
  EXPECT_TRUE(s.material(s.findMaterial("Paint")).showsPlanarReflection());
  EXPECT_EQ(s.material(s.findMaterial("Glass")).engineReflection, EngineReflection::kNone);
  EXPECT_FALSE(s.material(s.findMaterial("Glass")).showsPlanarReflection());
  EXPECT_FALSE(s.material(s.findMaterial("Glass")).showsCubeMapReflection(false));
  const Scene c = parse(R"({"fly": 1, "models": [{"file": "car.gltf"}],
    "overrides": [{"material": "Paint", "engineReflection": "cubemap"}]})");
  const Material& paint = c.material(c.findMaterial("Paint"));
  EXPECT_EQ(paint.engineReflection, EngineReflection::kCubemap);
  EXPECT_TRUE(paint.showsCubeMapReflection(true));
  EXPECT_TRUE(paint.showsCubeMapReflection(false));
  EXPECT_FALSE(paint.showsPlanarReflection());
}

TEST(SceneFile, CamerasNeedAViewDirection) {
  expectError(R"({"fly": 1, "cameras": [{"name": "c", "position": [1, 2, 3], "target": [1, 2, 3]}]})", "1:71",
              "/cameras/0/target", {"camera position and target are the same point"});
  expectError(R"({"fly": 1, "cameras": [{"name": "c", "position": [0, 5, 0], "target": [0, 0, 0]}]})", "1:24",
              "/cameras/0", {"parallel to the view direction", "\"up\""});
  expectError(
      R"({"fly": 1, "cameras": [{"name": "c", "position": [0, 5, 0], "target": [0, 0, 0], "up": [0, 2, 0]}]})",
      "1:88", "/cameras/0/up", {"parallel to the view direction"});
  expectError(
      R"({"fly": 1, "cameras": [{"name": "c", "position": [0, 5, 0], "target": [0, 0, 0], "fovDeg": 180}]})",
      "1:92", "/cameras/0/fovDeg", {"(0, 180); got 180"});
  expectError(R"({"fly": 1, "cameras": [{"name": "c", "position": [0, 0, 1], "target": [0, 0, 0]},
                                         {"name": "c", "position": [0, 0, 2], "target": [0, 0, 0]}]})",
              "2:51", "/cameras/1/name", {"a camera named \"c\" is already defined"});
}

TEST(SceneFile, InputFilesAreCheckedAndImporterErrorsPassThrough) {
  expectError(R"({"fly": 1, "models": [{"file": "missing.gltf"}]})", "1:32", "/models/0/file",
              {"glTF file does not exist: ", "missing.gltf"});
  expectError(R"({"fly": 1, "lights": [{"type": "ies", "position": [0, 0, 0], "file": "none.ies"}]})", "1:70",
              "/lights/0/file", {"IES file does not exist"});
  expectError(
      R"({"fly": 1, "site": {"latitude": 1, "longitude": 2, "timeZone": "Z"}, "time": "2026-01-01T00:00",
                  "sky": {"model": "perez", "weatherFile": "none.epw"}})",
      "2:60", "/sky/weatherFile", {"weather file does not exist"});
  const Scene perez = parse(R"({"fly": 1, "site": {"latitude": 1, "longitude": 2, "timeZone": "Z"},
    "time": "2026-01-01T00:00", "sky": {"model": "perez", "weatherFile": "helsinki.epw"}})");
  EXPECT_EQ(std::filesystem::path(perez.sky().weatherFile), kDataDir / "helsinki.epw");

  // The importer's own errors name the glTF file, not the scene file.
  try {
    parse(R"({"fly": 1, "models": [{"file": "truncated.gltf"}]})");
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(e.location().file.find("truncated.gltf"), std::string::npos) << e.what();
  }
}

// "brdf": a MERL file's path (read and checked when the scene loads) or a car-paint object.
TEST(SceneFile, MeasuredAndCarPaintBrdfs) {
  test::TempDir dir;
  const std::filesystem::path table = dir / "paint.binary";
  writeMerlBrdf(table, [](const HalfDiffAngles&) { return Rgb(0.1f, 0.2f, 0.3f); });
  const std::string model = R"({"fly": 1, "models": [{"file": "car.gltf"}], "overrides": [{"material": "Paint", )";
  const Scene measured = parse(model + R"("brdf": ")" + table.string() + R"("}]})");
  const Material& m = measured.material(measured.findMaterial("Paint"));
  ASSERT_TRUE(m.measuredBrdf);
  EXPECT_EQ(m.measuredBrdfPath, table.string());
  EXPECT_NEAR(m.measuredBrdf->sample(3, 4, 5).b, 0.3f, 1e-6f);
  EXPECT_TRUE(m.isMeasured());
  EXPECT_TRUE(computeFeatures(measured).measuredBrdfs);
  const std::vector<std::string> names = computeFeatures(measured).names();
  EXPECT_NE(std::find(names.begin(), names.end(), "measured-brdf"), names.end());

  const Scene painted = parse(model + R"("brdf": {"base": [0.1, 0.2, 0.3],
      "flakes": [{"reflectance": [0.5, 0.5, 0.6], "roughness": 0.4}], "coat": {"ior": 1.6, "roughness": 0.2}}}]})");
  const Material& p = painted.material(painted.findMaterial("Paint"));
  ASSERT_TRUE(p.carPaint);
  EXPECT_FALSE(p.measuredBrdf);
  EXPECT_EQ(p.carPaint->baseAlbedo, Rgb(0.1f, 0.2f, 0.3f));
  EXPECT_EQ(p.carPaint->lobes[0].f0, Rgb(0.5f, 0.5f, 0.6f));
  EXPECT_FLOAT_EQ(p.carPaint->lobes[0].alpha, 0.16f);  // α = roughness²
  EXPECT_EQ(p.carPaint->lobes[1].f0, Rgb(0.0f));
  EXPECT_FLOAT_EQ(p.carPaint->coatIor, 1.6f);
  EXPECT_FLOAT_EQ(p.carPaint->coatAlpha, 0.04f);
  // The car-paint presets carry the model.
  const Scene preset = parse(model + R"("preset": "pearl-car-paint"}]})");
  EXPECT_TRUE(preset.material(preset.findMaterial("Paint")).carPaint);

  expectError(model + R"("brdf": 5}]})", "1:90", "/overrides/0/brdf",
              {"expected a measured BRDF file's path (a MERL .binary file) or a car-paint object"});
  const std::filesystem::path cut = dir / "cut.binary";
  writeFileAtomic(cut, readInputFile(table, "table").substr(0, 1000));
  expectError(model + R"("brdf": ")" + cut.string() + R"("}]})", "1:90", "/overrides/0/brdf",
              {"(the file is cut off)", cut.string()});
  expectError(model + R"("brdf": {"base": [0, 0, 0], "flakes": [{"reflectance": [1, 1, 1], "roughness": 0.05}]}}]})",
              "1:161", "/overrides/0/brdf/flakes/0/roughness", {"expected a number, [0.1, 1]"});
  expectError(model + R"("brdf": {"base": [0, 0, 0], "coat": {"ior": 1.5, "rough": 0.1}}}]})", "1:131",
              "/overrides/0/brdf/coat/rough", {"unknown key \"rough\"", "did you mean \"roughness\"?"});
}

TEST(SceneFile, TruncationsGiveInputErrors) {
  const std::string text = fly::readInputFile(kDataDir / "complete.json", "scene file");
  for (size_t n = 0; n + 1 < text.size(); n += 7) {
    EXPECT_THROW(parse(text.substr(0, n)), InputError) << "prefix of " << n << " bytes";
  }
}

}  // namespace
}  // namespace fly::sdb

namespace fly::sdb {
namespace {

TEST(SceneFile, MapGridOfTheModel) {
  const Scene utm = parseSceneFile(
      R"({"fly": 1, "site": {"latitude": 60.17, "longitude": 24.94, "northAngle": 2, "grid": "utm:35"}})", "s.json",
      ".");
  EXPECT_EQ(utm.site().grid, Site::Grid::kUtm);
  EXPECT_EQ(utm.site().utmZone, 35);
  EXPECT_EQ(utm.site().northAngleDeg, 2.0);
  const Scene tm = parseSceneFile(R"({"fly": 1, "site": {"latitude": 60.17, "longitude": 24.94, "grid": "tm:27"}})",
                                  "s.json", ".");
  EXPECT_EQ(tm.site().grid, Site::Grid::kTransverseMercator);
  EXPECT_EQ(tm.site().gridCentralMeridianDeg, 27.0);
  for (const char* bad : {"utm:61", "utm:3.5", "tm:200", "gauss:27", "utm:"}) {
    const std::string text = std::string(R"({"fly": 1, "site": {"latitude": 60, "longitude": 24, "grid": ")") + bad +
                             "\"}}";
    try {
      parseSceneFile(text, "s.json", ".");
      ADD_FAILURE() << bad << " accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("s.json:1:62 (at /site/grid): expected \"utm:ZONE\""), std::string::npos)
          << e.what();
    }
  }
}

}  // namespace
}  // namespace fly::sdb

namespace fly::sdb {
namespace {

// The opening of a 3 × 1.5 m window in the wall z = 3 (x ∈ [−1.5, 1.5], y ∈ [0.8, 2.3]), counter-clockwise
// seen from −Z (facing −Z), and a triangular roof light.
TEST(SceneFile, PortalsDeclareOpenings) {
  const Scene s = parse(R"({"fly": 1, "portals": [
    {"name": "south window", "corners": [[1.5, 0.8, 3], [-1.5, 0.8, 3], [-1.5, 2.3, 3], [1.5, 2.3, 3]]},
    {"corners": [[0, 3, 0], [0, 3, 2], [1, 3, 0]]}
  ]})");
  ASSERT_EQ(s.portals().size(), 2u);
  const Portal& window = s.portals()[0];
  const Portal& roof = s.portals()[1];
  EXPECT_EQ(window.name, "south window");
  EXPECT_EQ(roof.name, "portal 1");
  ASSERT_EQ(window.cornersM.size(), 4u);
  expectNear(window.cornersM[2], vec3(-1.5f, 2.3f, 3.0f));
  // A quad is the triangles (0, 1, 2) and (0, 2, 3); a triangle is itself.
  const std::vector<vec3> quad = portalTrianglesM(window);
  ASSERT_EQ(quad.size(), 6u);
  const int order[6] = {0, 1, 2, 0, 2, 3};
  for (int i = 0; i < 6; ++i) expectNear(quad[i], window.cornersM[order[i]]);
  EXPECT_EQ(portalTrianglesM(roof).size(), 3u);
  EXPECT_NEAR(portalAreaM2(window), 3.0 * 1.5, 1e-5);
  EXPECT_NEAR(portalAreaM2(roof), 0.5 * 2.0 * 1.0, 1e-6);
  // (−3, 0, 0) × (−3, 1.5, 0) = (0, 0, −4.5): facing −Z; (0, 0, 2) × (1, 0, 0) = (0, 2, 0): facing up.
  expectNear(portalNormal(window), vec3(0, 0, -1));
  expectNear(portalNormal(roof), vec3(0, 1, 0));
  EXPECT_EQ(computeFeatures(s).names(), std::vector<std::string>{"sky-portals"});
  EXPECT_TRUE(parse(R"({"fly": 1, "portals": []})").portals().empty());
  EXPECT_TRUE(computeFeatures(parse(R"({"fly": 1})")).names().empty());
  // A quad 1° out of plane over 0.01 of its longest edge is refused; one within 0.001 is kept.
  EXPECT_EQ(parse(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0.0019]]}]})")
                .portals()
                .size(),
            1u);
}

TEST(SceneFile, BadPortals) {
  expectError(R"({"fly": 1, "portals": {"corners": []}})", "1:23", "/portals", {"expected an array of portals"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0]]}]})", "1:36", "/portals/0/corners",
              {"expected 3 or 4 corners; got an array of 2 elements", "hint: give a triangle of 3 corners"});
  expectError(R"({"fly": 1, "portals": [{"name": "w"}]})", "1:24", "/portals/0", {"missing key \"corners\""});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [1, "1", 0]]}]})", "1:63",
              "/portals/0/corners/2/1", {"expected a number in metres; got a string (\"1\")"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [1, 1]]}]})", "1:59",
              "/portals/0/corners/2", {"expected an array of 3 numbers [x, y, z] in metres"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [1, 1e39, 0]]}]})", "1:63",
              "/portals/0/corners/2/1", {"too large"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [2, 0.0000001, 0]]}]})", "1:36",
              "/portals/0/corners", {"the portal's area is 5e-08 m², below 1e-06 m²", "hint: give the corners"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [2, 0, 0], [2, 1, 0], [0, 1, 0.01]]}]})", "1:70",
              "/portals/0/corners/3",
              {"corner 3 lies 0.01 m off the plane of corners 0, 1 and 2", "hint: a portal is flat"});
  // A bow tie (its edges cross) and a dart (turns back at corner 3).
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [2, 0, 0], [0, 1, 0], [2, 1, 0]]}]})", "1:59",
              "/portals/0/corners/2", {"the quad is not convex at corner 2", "hint: give the 4 corners in order"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [2, 0, 0], [2, 2, 0], [1.5, 0.5, 0]]}]})",
              "1:70", "/portals/0/corners/3", {"the quad is not convex at corner 3"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]]}]})", "1:48",
              "/portals/0/corners/1", {"corner 1 lies on the line through corners 0 and 2"});
  expectError(R"({"fly": 1, "portals": [{"corners": [[0, 0, 0], [1, 0, 0], [0, 1, 0]], "normal": [0, 0, 1]}]})",
              "1:71", "/portals/0/normal", {"unknown key \"normal\" in /portals/0; expected one of: name, corners"});
  // The SDB's own precondition, for scenes built in code.
  Scene s;
  EXPECT_THROW(s.setPortals({{"flat", {vec3(0.0f), vec3(1, 0, 0), vec3(2, 0, 0)}}}), std::invalid_argument);
  EXPECT_TRUE(s.portals().empty());
}

}  // namespace
}  // namespace fly::sdb
