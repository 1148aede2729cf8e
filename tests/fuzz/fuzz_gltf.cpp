// libFuzzer target: glTF 2.0 import (sdb::importGltf), .gltf (JSON) and .glb (binary) alike. The input is
// written to a file on tmpfs, named .glb when it starts with the GLB magic "glTF" and .gltf otherwise, in a
// folder that also holds the buffers and textures of the repository's sample scenes and test data, so that
// seeds made from those files find what they refer to.
#include <filesystem>

#include "sdb/gltf_import.h"
#include "tests/fuzz/fuzz_support.h"
#include "tests/fuzz/scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path gltfDir = fly::fuzz::fixtureDir("gltf");
  fly::fuzz::quietLog();
  const std::string_view bytes = fly::fuzz::asText(data, size);
  const std::filesystem::path file = gltfDir / (bytes.substr(0, 4) == "glTF" ? "fuzz.glb" : "fuzz.gltf");
  fly::fuzz::writeScratchFile(file, bytes);
  fly::fuzz::expectOnlyInputErrors([&] {
    fly::sdb::Scene scene;
    fly::sdb::importGltf(scene, file);
    fly::fuzz::checkScene(scene);
  });
  return 0;
}
