// libFuzzer target: the fly scene file (sdb::parseSceneFile). Relative paths in it resolve against a folder
// on tmpfs that holds the repository's sample scenes and test data (glTF models, IES and weather files), so
// that seeds made from those scene files import their models.
#include <filesystem>

#include "sdb/scene_file.h"
#include "tests/fuzz/fuzz_support.h"
#include "tests/fuzz/scene_checks.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::filesystem::path sceneDir = fly::fuzz::fixtureDir("scene");
  fly::fuzz::quietLog();
  fly::fuzz::expectOnlyInputErrors([&] {
    const fly::sdb::Scene scene =
        fly::sdb::parseSceneFile(fly::fuzz::asText(data, size), "fuzz.json", sceneDir);
    fly::fuzz::checkScene(scene);
  });
  return 0;
}
