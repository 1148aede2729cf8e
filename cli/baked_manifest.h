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

// The same as `fly info DIR` prints it, one "key  value" line each; `sourceFound` = false adds a warning that
// the scene file is gone.
std::string bakeSummaryText(const nlohmann::json& manifest, bool sourceFound);

}  // namespace fly::cli
