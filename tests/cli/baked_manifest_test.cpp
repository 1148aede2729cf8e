#include "cli/baked_manifest.h"

#include <gtest/gtest.h>

#include <string>

#include "base/error.h"

namespace fly::cli {
namespace {

using nlohmann::json;

// The keys of a manifest that its readers use, as writeBakedScene writes them (cli/baked_scene.h).
json manifest() {
  return {{"format", "fly-baked-scene"},
          {"format_version", 1},
          {"fly_version", "0.1.0"},
          {"scene", "room.json"},
          {"samples_per_vertex", 64},
          {"rays", 123456},
          {"bake_seconds", 2.5},
          {"relative_error_p95", 0.0125},
          {"objects",
           {{{"mesh_name", "floor"}, {"node_name", "Floor"}, {"gltf_mesh", 0}},
            {{"mesh_name", ""},
             {"node_name", "Wall"},
             {"light_texture",
              {{"width", 64},
               {"height", 32},
               {"texels_per_metre", 20.0},
               {"front", "lightmaps/object1_front.exr"},
               {"automatic", true}}}}}}};
}

// The InputError's message for `m` ("no error" when it parses).
std::string parseError(const json& m) {
  try {
    parseBakedManifest(m.dump(), "bake/manifest.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(BakedManifest, SummaryOfAValidManifest) {
  const json m = parseBakedManifest(manifest().dump(), "bake/manifest.json");
  EXPECT_EQ(bakeSummaryText(m, true),
            "baked from room.json by fly 0.1.0\n"
            "bake       64 samples per vertex, 95th percentile of relative standard error 1.25 %, 2.5 s, 2 "
            "objects\n"
            "light tex  object 1 \"Wall\": 64 x 32 texels, 20.0 texels/m (automatic), "
            "lightmaps/object1_front.exr\n");
  const json j = bakeSummaryJson(m);
  EXPECT_EQ(j["objects"], 2);
  ASSERT_EQ(j["light_textures"].size(), 1u);
  EXPECT_EQ(j["light_textures"][0]["object"], 1);
  EXPECT_EQ(j["light_textures"][0]["name"], "Wall");
}

// What fly info reads must be there with its type: before, these reached the summary and ended the program
// with a JSON library exception (exit code 1, "[json.exception.type_error.302] ...") instead of a bad-input
// error (regression inputs of the fuzz target: tests/fuzz/corpus/baked_manifest/regression-*.json).
TEST(BakedManifest, MissingOrMistypedKeysAreInputErrorsWithTheirPath) {
  json m = manifest();
  m["format"] = 1;
  EXPECT_NE(parseError(m).find("(at /format): is not a fly baked-scene manifest"), std::string::npos)
      << parseError(m);
  m = manifest();
  m.erase("samples_per_vertex");
  EXPECT_NE(parseError(m).find("(at /samples_per_vertex): needs \"samples_per_vertex\", an unsigned integer"),
            std::string::npos)
      << parseError(m);
  m = manifest();
  m["objects"][0]["mesh_name"] = 7;
  EXPECT_NE(parseError(m).find("(at /objects/0/mesh_name): needs \"mesh_name\", a string"), std::string::npos)
      << parseError(m);
  m = manifest();
  m["objects"][1]["light_texture"]["width"] = "64";
  EXPECT_NE(parseError(m).find("(at /objects/1/light_texture/width)"), std::string::npos) << parseError(m);
  m = manifest();
  m["objects"][1] = 3;
  EXPECT_NE(parseError(m).find("(at /objects/1): is not an object"), std::string::npos) << parseError(m);
}

// 2^32 + 1 is not version 1 (an int conversion made it so).
TEST(BakedManifest, FormatVersionMustBeExactlyOne) {
  json m = manifest();
  m["format_version"] = 4294967297ull;
  EXPECT_NE(parseError(m).find("has format version 4294967297"), std::string::npos) << parseError(m);
  m["format_version"] = 1.0;
  EXPECT_NE(parseError(m).find("has format version"), std::string::npos) << parseError(m);
  EXPECT_EQ(parseError(manifest()), "no error");
}

}  // namespace
}  // namespace fly::cli
