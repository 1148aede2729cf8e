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
            "lightmaps/object1_front.exr\n"
            "sunlight   note: this bake keeps no separate sun-direct light (baked without a sun, or by a fly "
            "before it was kept apart): sunlight mode shows the baked light as light-map mode does, under the "
            "bake's sun; bake again to move the sun\n");
  const json j = bakeSummaryJson(m);
  EXPECT_EQ(j["objects"], 2);
  ASSERT_EQ(j["light_textures"].size(), 1u);
  EXPECT_EQ(j["light_textures"][0]["object"], 1);
  EXPECT_EQ(j["light_textures"][0]["name"], "Wall");
}

// A bake that kept the sun's direct light apart says when its indirect light was baked: the site's time with
// its zone, or the sun placed directly.
TEST(BakedManifest, TheBakesSunTimeForSunlightMode) {
  json m = manifest();
  m["sun_direct"] = {{"direction_world", {0.0, 0.76, 0.65}},
                     {"elevation_deg", 49.46},
                     {"normal_illuminance_lux", {90000.0, 85000.0, 70000.0}},
                     {"normal_illuminance_luminance_lux", 84290.4},
                     {"time", "2026-06-21T15:00"},
                     {"time_zone", "Europe/Helsinki"},
                     {"sun_direction", nullptr}};
  EXPECT_EQ(bakedSunTime(m), "2026-06-21 15:00 Europe/Helsinki");
  EXPECT_EQ(bakedSunlightText(m),
            "indirect light baked at 2026-06-21 15:00 Europe/Helsinki (sun at 49.5° elevation, 84290 lx); the "
            "sun's direct light is drawn for the time rendered");
  m["sun_direct"]["time"] = nullptr;
  m["sun_direct"]["sun_direction"] = {{"azimuth_deg", 200.0}, {"elevation_deg", 35.0}};
  EXPECT_EQ(bakedSunTime(m), "the sun placed at azimuth 200.0°, elevation 35.0°");
  m["sun_direct"] = nullptr;
  EXPECT_EQ(bakedSunTime(m), "");
  m["sun_direct"] = "damaged";
  EXPECT_EQ(bakedSunTime(m), "");
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
