// glTF 2.0 import (.gltf and .glb, through tinygltf) into the SDB.
//
// Conversions (documented in docs/scene-format.md, "glTF conversion"):
// - metallic-roughness → realistic material (see gltf_import.cpp for the approximation and its source);
// - KHR_lights_punctual, KHR_materials_emissive_strength, _transmission, _ior, _specular, KHR_texture_transform;
// - doubleSided → Material::doubleSided and Mesh::twoSided; TEXCOORD_1 → Mesh::uv1; cameras;
// - nodes whose world transform has a negative determinant get a copy of the mesh with reversed winding, so that
//   counter-clockwise is the front face in world space everywhere;
// - missing normals → flat normals (vertices are split per triangle).
// Problems that can be fixed (degenerate triangles, NaN/Inf positions, bad normals) are fixed with a warning
// that says what was done; problems that cannot (truncated or malformed files, indices or accessors out of
// range, missing .bin or texture files) throw InputError naming the file and the offending element.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "sdb/scene.h"

namespace fly::sdb {

struct GltfImportOptions {
  NodeId parent;                    // the imported roots go under this node; 0 = new scene roots
  std::string namePrefix;           // prepended to imported names ("" = none), e.g. "house/"
};

struct GltfImportResult {
  std::vector<NodeId> roots;          // the imported scene's root nodes
  ChangeSet changes;
  std::vector<std::string> warnings;  // also written to the log as warnings
};

GltfImportResult importGltf(Scene& scene, const std::filesystem::path& file, const GltfImportOptions& options = {});

}  // namespace fly::sdb
