// glTF 2.0 import (.gltf and .glb, through tinygltf) into the SDB.
//
// Conversions (documented in docs/scene-format.md, "glTF conversion"):
// - metallic-roughness → realistic material (see gltf_import.cpp for the approximation and its source);
// - KHR_lights_punctual, KHR_materials_emissive_strength, _transmission, _volume, _ior, _specular,
//   _clearcoat, _sheen (material_layers.h), _anisotropy (gltf_anisotropy.h), _variants (the default
//   materials), KHR_texture_transform,
//   EXT_texture_webp (with an image decoder that reads WebP), KHR_mesh_quantization;
// - compressed meshes: KHR_draco_mesh_compression (Draco) and EXT_meshopt_compression (meshoptimizer);
// - doubleSided → Material::doubleSided and Mesh::twoSided; TEXCOORD_1 → Mesh::uv1; cameras;
// - nodes whose world transform has a negative determinant get a copy of the mesh with reversed winding, so
//   that counter-clockwise is the front face in world space everywhere;
// - missing normals → flat normals (vertices are split per triangle).
// Problems that can be fixed (degenerate triangles, NaN/Inf positions, bad normals) are fixed with a warning
// that says what was done; problems that cannot (truncated or malformed files, indices or accessors out of
// range, missing .bin or texture files) throw InputError naming the file and the offending element.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "sdb/scene.h"

namespace fly::sdb {

struct GltfImportOptions {
  NodeId parent;                    // the imported roots go under this node; 0 = new scene roots
  std::string namePrefix;           // prepended to imported names ("" = none), e.g. "house/"
  // Import budget: the most bytes that the decoded vertex attributes and indices (counted as fly stores them,
  // 4 bytes a component) and textures (RGBA, 1 or 2 bytes a channel) of one file may take together. Each
  // accessor and image is checked against what is left before it is decoded, so that a file that claims a
  // huge mesh or texture fails at once with an InputError. Default 4 GiB (docs/scene-format.md).
  uint64_t maxDecodedBytes = uint64_t(4) << 30;
};

struct GltfImportResult {
  std::vector<NodeId> roots;          // the imported scene's root nodes
  ChangeSet changes;
  std::vector<std::string> warnings;  // also written to the log as warnings
};

// Installs the decoder for the images of every later import in this process (texture.h ImageDecoder); an
// empty one restores the default, PNG and JPEG through tinygltf's stb_image. The fly program installs
// OpenImageIO's (oiio_image_decoder.h), which adds WebP (EXT_texture_webp), HDR, EXR and TIFF. Not
// synchronised: install it before imports start (the fly program does so before running a command).
void setImageDecoder(ImageDecoder decoder);

GltfImportResult importGltf(Scene& scene, const std::filesystem::path& file, const GltfImportOptions& options = {});

}  // namespace fly::sdb
