// Checkpoints of `fly bake --checkpoint SECONDS`, and what `fly bake --resume DIR` reads back.
//
// A bake into DIR keeps its checkpoint beside it, in DIR.checkpoint/ (DIR itself appears only when the bake
// is complete, atomically):
//   checkpoint.json  format "fly-bake-checkpoint" version 1: the scene file, the output directory, the
//                    resolved settings (so that --resume needs nothing else), a fingerprint of the lowered
//                    scene (TraceRdb), the convergence history so far, and the name and FNV-1a checksum of
//                    the state file;
//   state-N.bin      the progressive driver's state (raytracer/progressive.h: serializeProgressState).
// Each save writes a new state-N.bin, then replaces checkpoint.json atomically, then deletes the older state
// files, so a process killed at any moment leaves a consistent checkpoint. When the bake completes and DIR
// has been written, DIR.checkpoint/ is deleted.
//
// Testing aid: with the environment variable FLY_TEST_KILL_AFTER_CHECKPOINTS=N the process kills itself
// (SIGKILL) right after its N-th checkpoint, so that tests can interrupt a bake at a known point.
#pragma once

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "raytracer/baker.h"
#include "rdb/trace_rdb.h"

namespace fly::cli {

// What a resumed bake needs besides the driver's state.
struct BakeJob {
  std::string scenePath;  // as given on the command line
  std::string outDir;     // DIR of --out
  raytracer::BakeSettings settings;
  std::string samplerName;  // "sobol" or "random", as the manifest records it
  bool exportGltf = false;
  // Light textures where vertices cannot carry the light (raytracer/light_resolution.h); off: only those asked.
  bool automaticLightTextures = true;
  double checkpointIntervalS = 0.0;  // > 0
  nlohmann::json daylight;           // the scene's site, time and sky (cli/scene_daylight.h, daylightJson)
};

// DIR.checkpoint for DIR.
std::filesystem::path checkpointDirFor(const std::filesystem::path& outDir);

// A 64-bit FNV-1a fingerprint of everything in the TraceRdb that a bake's result depends on (geometry,
// materials, lights, sun, sky, declared portals): a resumed bake refuses a scene that changed since the
// checkpoint.
uint64_t traceRdbFingerprint(const rdb::TraceRdb& rdb);

// Saves a checkpoint of `job` with `state` into checkpointDirFor(job.outDir) as described above; the
// directory is created when missing. std::runtime_error when it cannot be written.
void saveBakeCheckpoint(const BakeJob& job, uint64_t fingerprint, const raytracer::BakeCheckpoint& state);

// The job and state saved in checkpointDirFor(outDir). InputError naming the file when there is none, or it
// is damaged, of another format version, or inconsistent.
struct LoadedCheckpoint {
  BakeJob job;
  uint64_t fingerprint = 0;
  raytracer::BakeCheckpoint state;
};
LoadedCheckpoint loadBakeCheckpoint(const std::filesystem::path& outDir);

// Throws InputError naming checkpointDirFor(outDir)/checkpoint.json when `state` cannot continue a bake of
// `rdb` with the same fingerprint: a bake under the sun keeps the sun's direct part apart (two quantities a
// point), which checkpoints of a fly before it (progress-state formats 2 and 3, read as one) lack.
void checkCheckpointKeepsWhatTheBakeNeeds(const raytracer::BakeCheckpoint& state, const rdb::TraceRdb& rdb,
                                          const std::filesystem::path& outDir);

}  // namespace fly::cli
