// manifest.json of a baked scene directory (cli/baked_scene.h describes the directory): reading it back, the
// scene it was baked from, and the summary `fly info DIR` prints of it.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace fly::cli {

inline constexpr const char* kBakedSceneFormat = "fly-baked-scene";
inline constexpr int kBakedSceneFormatVersion = 1;

// Whether `dir` holds a baked scene (a manifest.json).
bool isBakedScene(const std::filesystem::path& dir);

// Parses manifest text; `fileName` names it in errors. InputError (with the JSON path) when it is not JSON,
// not a baked-scene manifest of a format version this program reads, or lacks what its readers use: "scene"
// and "fly_version" (strings), "samples_per_vertex" and "rays" (unsigned integers), "bake_seconds" and
// "relative_error_p95" (numbers), "objects" (an array of objects, whose "mesh_name" and "node_name" are
// strings where present, and whose "light_texture", where present, is an object with the unsigned integers
// "width" and "height", the number "texels_per_metre", the string "front", and where present the string
// "back" and the boolean "automatic").
nlohmann::json parseBakedManifest(std::string_view text, const std::string& fileName);

// Reads and parses DIR/manifest.json (InputError naming the file when it is missing as well).
nlohmann::json readBakedManifest(const std::filesystem::path& dir);

// The scene file a bake was made from, which the GL engine shows and `fly info` describes (the baked
// scene.gltf keeps the geometry and light maps only), looked for in turn at the manifest's "scene_from_bake"
// (relative to the baked directory, so that a project folder copied whole to another machine still works),
// "scene_absolute", and its "scene" as fly bake was given it, relative to the working directory or to the
// baked directory's parent. None when it exists at none of these.
std::optional<std::filesystem::path> findBakedSourceScene(const std::filesystem::path& dir,
                                                          const nlohmann::json& manifest);

// What `fly info --json DIR` reports of a parsed manifest under "bake": scene, samples per vertex, error,
// time, rays, object count, light textures (object index, name, files, size, density) and fly version.
nlohmann::json bakeSummaryJson(const nlohmann::json& manifest);

// When the bake's light was baked, for sunlight mode (FLY §3: baked indirect light under a real-time sun),
// from the manifest's "sun_direct" (cli/baked_scene.h): "2026-06-21 15:00 Europe/Helsinki", or for a sun
// placed directly "the sun placed at azimuth 200.0°, elevation 35.0°"; "" when the bake kept no sun-direct
// part.
std::string bakedSunTime(const nlohmann::json& manifest);

// One line on what a bake's light maps hold for sunlight mode: with a sun-direct part, "indirect light baked
// at TIME (sun at E° elevation, N lx); the sun's direct light is drawn for the time rendered"; without one, a
// note that sunlight mode shows the baked light as light-map mode does (the bake's sun, shadows included).
std::string bakedSunlightText(const nlohmann::json& manifest);

// The same as `fly info DIR` prints it, one "key  value" line each; `sourceFound` = false adds a warning that
// the scene file is gone.
std::string bakeSummaryText(const nlohmann::json& manifest, bool sourceFound);

}  // namespace fly::cli
