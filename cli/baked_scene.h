// The baked scene directory that `fly bake --out DIR` writes and `fly info DIR` and the GL engine read.
//
// manifest.json: format "fly-baked-scene" version 1; fly version, scene path, settings, samples per vertex,
//   rays, timings, final error; per object (TraceMesh: SDB ids and names, its glTF mesh) the mean over
//   vertices of the irradiance's luminance and of its relative error (and of the sun-direct part's,
//   "front_sun_direct"); the list of files; "sun_direct": null, or for a bake under the sun the sun whose
//   direct light was kept apart: direction_world (unit, towards the sun), elevation_deg,
//   normal_illuminance_lux (RGB) and normal_illuminance_luminance_lux, the bake's time and time_zone (null
//   for a sun placed directly, whose sun_direction is given instead) and relative_error_p95 (the sun-direct
//   part's). A manifest without it (an earlier fly's) reads as a bake without a sun-direct part.
// scene.gltf + scene.bin: the baked geometry in world space (metres, +Y up), one glTF mesh and node per
//   TraceMesh with POSITION, NORMAL and the application-specific (glTF 2.0 §3.7.2.1: names start with "_")
//   VEC3 FLOAT attributes _IRRADIANCE_FRONT and _IRRADIANCE_FRONT_STDERR, for two-sided meshes also
//   _IRRADIANCE_BACK and _IRRADIANCE_BACK_STDERR, in lux (linear Rec.709 RGB, photometric luminance); one
//   primitive per material, pbrMetallicRoughness with baseColor = the diffuse albedo.
//   Light-textured meshes (TraceMesh::lightTexture) also carry TEXCOORD_1 (the light-map UVs, v = 0 at the
//   image's top row) and _SOURCE_VERTEX (SCALAR FLOAT, an integer exact below 2^24: the index, within the
//   mesh, of the TraceMesh vertex the glTF vertex copies). Their first TraceMesh::vertexCount vertices are
//   the TraceMesh's vertices in order (= the SDB mesh's; _SOURCE_VERTEX = its own index), each with the UV of
//   its first triangle corner ((0, 0) for a vertex of no triangle); a copy follows for every further UV a
//   vertex has where charts meet (seams), with the attributes of its source vertex. The mesh's extras hold
//   {"fly": {"light_texture": {"front", "front_stderr", ["back", "back_stderr"], "width", "height",
//   "texels_per_metre"}}}: the EXR paths (relative to the directory) and the atlas.
//   A bake under the sun (raytracer::VertexLightMaps::hasSunDirect) adds _SUN_DIRECT_FRONT and
//   _SUN_DIRECT_FRONT_STDERR (and _BACK, _BACK_STDERR for two-sided meshes): the part of the irradiance that
//   came straight from the sun's disc, lux, from the same samples (docs/mixed-lighting.md).
// lightmaps/objectN_front.exr, objectN_front_stderr.exr (and _back, _back_stderr for two-sided meshes), for
//   every object N (the manifest's objects index) with a light texture: 32-bit float RGB, ZIP, the irradiance
//   in lux per texel (mean over the texel's footprint on the mesh) and its standard error, row 0 = v ∈ [0,
//   1/height). Every texel is finite: texels no triangle covers (padding, empty) are filled from their
//   neighbours. Header attributes: units "lux", fly:quantity, fly:side, fly:object, fly:texelsPerMetre.
//   The manifest's object lists them under "light_texture" with the atlas size, density, whether it was
//   chosen automatically, the UV source ("TEXCOORD_1" or "generated"), baked/empty texel and seam-edge
//   counts, and front_summary/back_summary (as "front", over the baked texels). Under the sun also
//   objectN_front_sun.exr, objectN_front_sun_stderr.exr (and _back_sun …): the sun-direct part, listed as
//   "front_sun_direct", "front_sun_direct_stderr" … with front_sun_direct_summary.
// convergence.csv: seconds,samples,estimated_error,rays_per_second, one row per pass (under the sun also
//   sun_direct_estimated_error: raytracer::ConvergencePoint::sunDirectRelativeErrorP95).
// convergence.png: the estimated error against run time, log-log (cli/convergence_plot.h).
// Every image carries the bake's site, time and sky and the command line in its metadata (PNG text chunks,
//   EXR header attributes; cli/image_metadata.h), and with `fly bake --dpi N` its print resolution.
// export/scene.gltf + scene.bin (optional), for any glTF viewer: COLOR_0 = the tone-mapped luminance
//   albedo·E/π, KHR_materials_unlit; two-sided meshes twice, the back with reversed winding. Light-textured
//   meshes instead use export/lightmaps/objectN_front.png (and _back): 8-bit sRGB of the same tone-mapped
//   albedo·E/π + emission per texel (albedo of the mesh's first triangle's material; the exposure of the
//   vertex colours), as the baseColorTexture (texCoord 1, linear filtering, clamped) of an unlit material.
//
// The directory appears atomically (writeDirectoryAtomic): readers see the old bake or the whole new one.
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "cli/baked_manifest.h"
#include "cli/image_metadata.h"
#include "raytracer/baker.h"
#include "rdb/trace_rdb.h"

namespace fly::cli {

// What the manifest records besides the light maps: names from the SDB (the TraceRdb holds ids only).
struct BakeDescription {
  std::string scenePath;
  nlohmann::json settings;                 // the resolved options, as the command reports them
  // With a bounce cap: the light it removes (cli/bounce_cap_warning.h), manifest key bounce_cap_bias; null
  // without one.
  nlohmann::json bounceCapBias;
  nlohmann::json daylight;                 // the site, time and sky baked with (cli/scene_daylight.h)
  // The same as the images' metadata (cli/image_metadata.h, daylightSettings), and their print resolution
  // (dots per inch; 0 = none): in convergence.png, the light textures' EXR headers and export's PNGs.
  ImageSettings imageSettings;
  double dotsPerInch = 0.0;
  float targetRelativeError = 0.0f;        // drawn in convergence.png; 0 = none
  std::vector<std::string> meshNames;      // per TraceMesh (rdb.meshes order); "" = unnamed
  std::vector<std::string> nodeNames;      // per TraceMesh
  std::vector<std::string> materialNames;  // per TraceMaterial (rdb.materials order)
  nlohmann::json timingsS;                 // named phases in seconds, e.g. {"build": 0.2, "bake": 61.3}
  bool exportGltf = false;                 // also write export/scene.gltf for glTF viewers
};

// Writes the baked scene into `dir`, which must not exist (writeDirectoryAtomic gives it a fresh one).
// std::runtime_error when a file cannot be written; std::invalid_argument when the light maps or the names do
// not match rdb.
void writeBakedScene(const std::filesystem::path& dir, const rdb::TraceRdb& rdb,
                     const raytracer::VertexLightMaps& maps, const BakeDescription& description);

// convergence.csv's text: the header and one row per point, numbers in the shortest form that reads back
// exactly; with sunDirect, a last column sun_direct_estimated_error.
std::string convergenceCsv(const std::vector<raytracer::ConvergencePoint>& history, bool sunDirect);

// Throws UsageError when `dir` exists and is not a baked scene (a file, or a directory of something else):
// a bake replaces only an earlier bake.
void checkBakeOutput(const std::filesystem::path& dir);

// Creates `dir` atomically: `fill` writes everything into a fresh sibling temporary directory
// (DIR.tmp-NNNN), which is then renamed to `dir`. An earlier bake at `dir` is renamed away first and deleted
// after. When fill throws, or any step fails, the temporary is removed, an earlier bake stays where it was,
// and the exception propagates. checkBakeOutput(dir) first.
void writeDirectoryAtomic(const std::filesystem::path& dir,
                          const std::function<void(const std::filesystem::path& tmp)>& fill);

// The samples an object's vertices took: the most of any (an object settled before the last pass took fewer
// than the bake's samplesPerVertex; raytracer/progressive.h, kSettledPercentile).
uint32_t objectSamples(const raytracer::VertexLightMaps& maps, const rdb::TraceMesh& m);

}  // namespace fly::cli
