// The baked light maps the GL engine draws, as an rdb::LightMapStore: from a bake in memory, or read back
// from the baked scene directory that `fly bake --out DIR` writes (cli/baked_scene.h describes its files).
#pragma once

#include <filesystem>

#include "raytracer/baker.h"
#include "rdb/light_map_store.h"
#include "rdb/trace_rdb.h"

namespace fly::cli {

// The light maps of a bake: one MeshLightMap per TraceMesh that has triangles (a mesh whose every triangle
// was degenerate has nothing to draw, and the baked scene.gltf leaves it out too), with the TraceMesh's
// vertices — the SDB mesh's vertices in order (rdb/trace_rdb_build.cpp) — and backLux only for two-sided
// meshes, each with its standard errors; for a light-textured mesh (TraceMesh::lightTexture) also its texture
// (maps.lightTextures' front and, two-sided, back values and standard errors) and corner UVs
// (TraceLightTexture::cornerUv: the TraceMesh's triangles are the SDB mesh's triangles with area, in order).
// std::invalid_argument when `maps` does not have one value per TraceRdb vertex or a light texture does not
// match its mesh.
rdb::LightMapStore lightMapStoreFromBake(const rdb::TraceRdb& rdb, const raytracer::VertexLightMaps& maps);

// The light maps with the errors a reader sees at any point of a vertex's ring or a texel's footprint: the
// Monte-Carlo error of the footprint's mean combined (in quadrature) with the spread of the sun's direct light
// over the footprint (raytracer::IrradianceEstimate::sunDirectSpreadLux), what a value read at one spot of it
// may differ from the mean; the mean's error alone without a sun. What a bake writes and a store holds.
raytracer::VertexLightMaps withPointReadErrors(const raytracer::VertexLightMaps& maps);

// The light maps of a baked scene directory: manifest.json's objects give each baked mesh's SDB ids, vertex
// count, sidedness and glTF mesh; scene.gltf's _IRRADIANCE_FRONT and _IRRADIANCE_FRONT_STDERR (and, for
// two-sided meshes, _IRRADIANCE_BACK and its _STDERR) attributes hold the values and their standard errors,
// of which the first `vertices` are the SDB mesh's (a light-textured mesh appends seam-split copies after
// them). An object with a "light_texture" entry also gets its light texture: the EXR files it names
// (lightmaps/objectN_front.exr and objectN_front_stderr.exr, and _back for two-sided meshes) and the corner
// UVs, TEXCOORD_1 of each corner of the glTF mesh's triangles. A manifest with a "sun_direct"
// (cli/baked_scene.h) also gives the store its sun and every map its sun-direct part
// (_SUN_DIRECT_FRONT/_BACK, the light textures' "front_sun_direct"/"back_sun_direct" EXRs); one without it
// (an earlier fly's bake) reads without them. Equals lightMapStoreFromBake of the bake that wrote the
// directory, value for value. The vertex counts are those of the scene at bake time: a caller checks them
// against the scene it draws. InputError naming the file (manifest.json, scene.gltf or its buffer, an EXR)
// when one is missing, corrupt, truncated, holds a value that is not finite, or does not match the others.
rdb::LightMapStore readBakedLightMaps(const std::filesystem::path& bakedDir);

}  // namespace fly::cli
