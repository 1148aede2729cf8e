// libFuzzer target: the checkpoint that `fly bake --resume DIR` reads (cli::loadBakeCheckpoint):
// DIR.checkpoint/checkpoint.json and the progressive driver's state file it names.
//
// The input is checkpoint.json's text, optionally followed by a NUL byte and the state file's bytes without
// their trailing FNV-1a checksum. The harness writes the state file (by default a valid one from
// raytracer::serializeProgressState, else the given bytes with their checksum appended) and replaces the
// token STATE_FNV1A in the JSON by the file's FNV-1a hash, so that mutations get past both checksums and
// reach the field checks behind them.
#include <cstring>
#include <filesystem>
#include <string>

#include "base/fnv1a.h"
#include "cli/bake_checkpoint.h"
#include "raytracer/progressive.h"
#include "tests/fuzz/fuzz_support.h"

namespace {

namespace fs = std::filesystem;
using namespace fly;

// A state of 2 points with 4 replicates, one pass of 8 samples done.
std::string validState() {
  raytracer::ProgressState s;
  s.pointCount = 2;
  s.replicates = 4;
  s.samplesPerPoint = 8;
  s.passes = 1;
  s.rays = 160;
  s.seconds = 0.5;
  s.lastPassS = 0.5;
  s.lastPassSamples = 8;
  s.lastPassPointSamples = 16;
  s.pointSamples = {8, 8};
  s.sums.assign(2 * (2 + 4), dvec3(1.0));
  return raytracer::serializeProgressState(s);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  fuzz::quietLog();
  static const fs::path outDir = fuzz::scratchDir() / "bake";
  static const std::string defaultState = validState();
  const fs::path dir = cli::checkpointDirFor(outDir);
  fs::create_directories(dir);

  const std::string_view input = fuzz::asText(data, size);
  const size_t nul = input.find('\0');
  std::string json(input.substr(0, nul));
  std::string state = defaultState;
  if (nul != std::string_view::npos) {
    state = std::string(input.substr(nul + 1));
    const uint64_t checksum = fnv1a(state);
    state.append(reinterpret_cast<const char*>(&checksum), sizeof checksum);
  }
  char hash[17];
  std::snprintf(hash, sizeof hash, "%016llx", static_cast<unsigned long long>(fnv1a(state)));
  for (size_t at = json.find("STATE_FNV1A"); at != std::string::npos; at = json.find("STATE_FNV1A", at)) {
    json.replace(at, std::strlen("STATE_FNV1A"), hash);
  }
  fuzz::writeScratchFile(dir / "checkpoint.json", json);
  fuzz::writeScratchFile(dir / "state-1.bin", state);
  fuzz::expectOnlyInputErrors([&] { cli::loadBakeCheckpoint(outDir); });
  return 0;
}
