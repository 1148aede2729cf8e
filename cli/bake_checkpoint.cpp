#include "cli/bake_checkpoint.h"

#include <csignal>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <nlohmann/json.hpp>
#include <regex>
#include <stdexcept>
#include <system_error>

#include "base/error.h"
#include "base/fnv1a.h"
#include "base/file_io.h"
#include "cli/command.h"

namespace fly::cli {
namespace {

constexpr const char* kFormat = "fly-bake-checkpoint";
constexpr int kVersion = 1;

// FNV-1a, 64 bit (Fowler, Noll & Vo), over raw bytes.
class Fnv1a {
 public:
  void bytes(const void* data, size_t size) {
    hash_ = fnv1a(data, size, hash_);
  }
  template <class T>
  void value(const T& v) {
    static_assert(std::is_arithmetic_v<T>);
    bytes(&v, sizeof v);
  }
  void rgb(const Rgb& c) {
    value(c.r);
    value(c.g);
    value(c.b);
  }
  void v3(const vec3& v) {
    value(v.x);
    value(v.y);
    value(v.z);
  }
  template <class T>
  void array(const std::vector<T>& v) {
    value(static_cast<uint64_t>(v.size()));
    if (!v.empty()) bytes(v.data(), v.size() * sizeof(T));
  }
  uint64_t hash() const { return hash_; }

 private:
  uint64_t hash_ = kFnv1aOffsetBasis;
};

std::string hex(uint64_t x) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(x));
  return buf;
}

nlohmann::json historyJson(const std::vector<raytracer::ConvergencePoint>& history) {
  nlohmann::json rows = nlohmann::json::array();
  for (const raytracer::ConvergencePoint& p : history) {
    rows.push_back({p.seconds, p.samples, p.relativeErrorP95, p.raysPerSecond, p.sunDirectRelativeErrorP95});
  }
  return rows;
}

// `v` (named `what` in the message) as T, which must hold it exactly. nlohmann's get<uint32_t>() would
// convert 1e30 (undefined behaviour) and wrap -1 around; std::out_of_range (a damaged checkpoint) instead.
template <class T>
T unsignedValue(const nlohmann::json& v, const std::string& what) {
  if (!v.is_number_unsigned() || v.get<uint64_t>() > std::numeric_limits<T>::max()) {
    throw std::out_of_range(what + " must be an integer from 0 to " +
                            std::to_string(std::numeric_limits<T>::max()) + ", not " + v.dump());
  }
  return static_cast<T>(v.get<uint64_t>());
}

}  // namespace

std::filesystem::path checkpointDirFor(const std::filesystem::path& outDir) {
  std::filesystem::path dir = outDir;
  if (!dir.has_filename()) dir = dir.parent_path();  // "out/bake/" → "out/bake"
  return dir.string() + ".checkpoint";
}

uint64_t traceRdbFingerprint(const rdb::TraceRdb& rdb) {
  Fnv1a h;
  h.array(rdb.positionsM);
  h.array(rdb.normals);
  h.array(rdb.indices);
  h.array(rdb.triangleMaterial);
  h.value(static_cast<uint64_t>(rdb.materials.size()));
  for (const rdb::TraceMaterial& m : rdb.materials) {
    h.rgb(m.diffuse);
    h.rgb(m.reflection);
    h.rgb(m.transmission);
    h.rgb(m.emissionCdM2);
    h.value(m.fresnel);
    h.value(m.ior);
    h.value(m.reflectionGlossiness);
    h.value(m.transmissionGlossiness);
    if (m.isAnisotropic()) {
      // Only for anisotropic materials, so that isotropic scenes keep their fingerprints.
      h.value(m.anisotropyU);
      h.value(m.anisotropyV);
      h.value(m.anisotropyRotationRad);
    }
    h.value(m.doubleSided);
    // Only materials with metalness add it, so that the fingerprints of the others stay as they were.
    if (m.metalnessTexture) {
      h.value(m.metalness);
      h.value(m.metalnessTexture.texture);
    }
    // Only fogged materials add their fog: the fingerprints of scenes without fog stay as they were.
    if (m.hasReflectionFog()) {
      h.value(m.reflectionFogDistanceM);
      h.rgb(m.reflectionFogColor);
    }
    h.value(m.brdfTable);
    h.value(m.carPaint.has_value());
    if (m.carPaint) {
      h.rgb(m.carPaint->baseAlbedo);
      for (const CarPaintLobe& l : m.carPaint->lobes) {
        h.rgb(l.f0);
        h.value(l.alpha);
      }
      h.value(m.carPaint->coatIor);
      h.value(m.carPaint->coatAlpha);
    }
  }
  // Measured tables by content: a file measured again under the same name is another bake.
  h.value(static_cast<uint64_t>(rdb.brdfTables.size()));
  for (const rdb::TraceBrdfTable& t : rdb.brdfTables) {
    h.value(t.scale);
    for (int i = 0; i < BrdfTable::kThetaHalfRes; ++i) {
      for (int j = 0; j < BrdfTable::kThetaDiffRes; ++j) {
        for (int k = 0; k < BrdfTable::kPhiDiffRes; ++k) h.rgb(t.table->sample(i, j, k));
      }
    }
  }
  h.value(static_cast<uint64_t>(rdb.meshes.size()));
  for (const rdb::TraceMesh& m : rdb.meshes) {
    h.value(m.firstVertex);
    h.value(m.vertexCount);
    h.value(m.firstTriangle);
    h.value(m.triangleCount);
    h.value(m.twoSided);
  }
  h.value(static_cast<uint64_t>(rdb.punctualLights.size()));
  for (const rdb::TracePunctualLight& l : rdb.punctualLights) {
    h.value(static_cast<int>(l.type));
    h.v3(l.positionM);
    h.v3(l.directionWorld);
    h.v3(l.cAxisWorld);
    h.rgb(l.intensity);
    h.value(l.rangeM);
    h.value(l.cosInner);
    h.value(l.cosOuter);
    h.value(l.goniometricTable);
  }
  for (const rdb::TraceGoniometricTable& t : rdb.goniometricTables) h.array(t.candelaCd);
  h.value(rdb.hasSun);
  h.v3(rdb.sun.directionWorld);
  h.rgb(rdb.sun.normalIlluminanceLux);
  h.value(rdb.sun.halfAngleRad);
  h.value(rdb.sky.resolution);
  h.array(rdb.sky.radianceCdM2);
  // Declared portals change the estimator (where sky samples go), not its mean; only scenes that have them
  // add them, so that the fingerprints of the others stay as they were.
  if (!rdb.portalCornersM.empty()) h.array(rdb.portalCornersM);
  return h.hash();
}

void saveBakeCheckpoint(const BakeJob& job, uint64_t fingerprint, const raytracer::BakeCheckpoint& state) {
  const std::filesystem::path dir = checkpointDirFor(job.outDir);
  std::filesystem::create_directories(dir);
  // The next state file's number: one more than any there.
  const std::regex stateName(R"(state-(\d+)\.bin)");
  unsigned long long next = 1;
  std::vector<std::filesystem::path> older;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    std::smatch m;
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, m, stateName)) {
      next = std::max(next, std::stoull(m[1].str()) + 1);
      older.push_back(entry.path());
    }
  }
  const std::string bytes = raytracer::serializeProgressState(state.progress);
  const std::string stateFile = "state-" + std::to_string(next) + ".bin";
  writeFileAtomic(dir / stateFile, bytes);

  Fnv1a stateHash;
  stateHash.bytes(bytes.data(), bytes.size());
  const raytracer::EstimateSettings& e = job.settings.estimate;
  const nlohmann::json j = {
      {"format", kFormat},
      {"version", kVersion},
      {"fly_version", kFlyVersion},
      {"scene", std::filesystem::absolute(job.scenePath).string()},
      {"out", job.outDir},
      {"settings",
       {{"max_samples", e.maxSamples},
        {"first_pass_samples", e.firstPassSamples},
        {"target_relative_error", e.targetRelativeError},
        {"time_limit_s", std::isfinite(e.timeLimitS) ? nlohmann::json(e.timeLimitS) : nlohmann::json()},
        {"sampler", job.samplerName},
        {"replicates", e.replicates},
        {"seed", e.seed},
        {"threads", e.threads},
        {"max_bounces", job.settings.integrator.maxBounces},
        {"caustics", job.settings.integrator.caustics},
        {"sky_portals", job.settings.integrator.skyPortals},
        {"lit_patches", job.settings.integrator.litPatches},
        {"roulette_after_light", job.settings.integrator.rouletteAfterLight},
        {"roulette_window", job.settings.integrator.rouletteWindow},
        {"lit_patch_sky", job.settings.integrator.litPatchSky},
        {"lit_patch_maps", job.settings.integrator.litPatchMaps},
        {"lit_patch_interior_training", job.settings.integrator.litPatchInteriorTraining},
        {"portal_continuation", job.settings.integrator.portalContinuation},
        {"light_paths", job.settings.lightPaths.enabled},
        {"error_allocation", e.allocationFraction},
        {"export_gltf", job.exportGltf},
        {"automatic_light_textures", job.automaticLightTextures},
        {"checkpoint_interval_s", job.checkpointIntervalS}}},
      {"daylight", job.daylight},
      {"trace_rdb_fingerprint", hex(fingerprint)},
      {"samples_done", state.progress.samplesPerPoint},
      {"seconds", state.progress.seconds},
      {"history", historyJson(state.history)},
      {"state_file", stateFile},
      {"state_fnv1a", hex(stateHash.hash())}};
  writeFileAtomic(dir / "checkpoint.json", j.dump(2) + "\n");
  for (const std::filesystem::path& p : older) {
    std::error_code ignored;
    std::filesystem::remove(p, ignored);
  }

  // Testing aid (see the header): die right here, as a killed process would.
  if (const char* kill = std::getenv("FLY_TEST_KILL_AFTER_CHECKPOINTS")) {
    static int saves = 0;
    if (++saves >= std::atoi(kill)) std::raise(SIGKILL);
  }
}

LoadedCheckpoint loadBakeCheckpoint(const std::filesystem::path& outDir) {
  const std::filesystem::path dir = checkpointDirFor(outDir);
  const std::filesystem::path jsonPath = dir / "checkpoint.json";
  if (!std::filesystem::exists(jsonPath)) {
    throw InputError(SourceLocation{jsonPath.string()}, "no checkpoint to resume",
                     "--resume DIR continues a bake that ran with --out DIR --checkpoint SECONDS; its "
                     "checkpoint lives in DIR.checkpoint/");
  }
  const std::string text = readInputFile(jsonPath, "checkpoint");
  auto bad = [&](const std::string& what) {
    return InputError(SourceLocation{jsonPath.string()}, "not a usable checkpoint: " + what,
                      "the checkpoint is damaged or from another version of fly; start the bake afresh "
                      "(without --resume)");
  };
  LoadedCheckpoint c;
  try {
    const nlohmann::json j = nlohmann::json::parse(text);
    if (j.at("format") != kFormat) throw bad("its format is not " + std::string(kFormat));
    if (j.at("version") != kVersion)
      throw bad("format version " + j.at("version").dump() + ", this fly reads 1");
    c.job.scenePath = j.at("scene").get<std::string>();
    c.job.outDir = outDir.string();
    c.job.daylight = j.value("daylight", nlohmann::json());
    const nlohmann::json& s = j.at("settings");
    raytracer::EstimateSettings& e = c.job.settings.estimate;
    e.maxSamples = unsignedValue<uint32_t>(s.at("max_samples"), "max_samples");
    e.firstPassSamples = unsignedValue<uint32_t>(s.at("first_pass_samples"), "first_pass_samples");
    e.targetRelativeError = s.at("target_relative_error").get<float>();
    if (!s.at("time_limit_s").is_null()) e.timeLimitS = s.at("time_limit_s").get<double>();
    c.job.samplerName = s.at("sampler").get<std::string>();
    if (c.job.samplerName != "sobol" && c.job.samplerName != "random") throw bad("unknown sampler");
    e.sampler =
        c.job.samplerName == "random" ? raytracer::SamplerKind::kRandom : raytracer::SamplerKind::kSobol;
    e.replicates = unsignedValue<uint32_t>(s.at("replicates"), "replicates");
    e.seed = unsignedValue<uint64_t>(s.at("seed"), "seed");
    e.threads = unsignedValue<uint32_t>(s.at("threads"), "threads");
    c.job.settings.integrator.maxBounces = unsignedValue<uint32_t>(s.at("max_bounces"), "max_bounces");
    // Checkpoints from before the setting existed baked without sun caustics.
    c.job.settings.integrator.caustics = s.value("caustics", false);
    // ... and without sky portals.
    c.job.settings.integrator.skyPortals = s.value("sky_portals", false);
    // ... and without next-event estimation to lit patches, with Russian roulette before a vertex's light.
    c.job.settings.integrator.litPatches = s.value("lit_patches", false);
    c.job.settings.integrator.rouletteAfterLight = s.value("roulette_after_light", false);
    // ... and with throughput roulette (a weight window of 1).
    c.job.settings.integrator.rouletteWindow = s.value("roulette_window", 1.0f);
    if (!(c.job.settings.integrator.rouletteWindow > 0.0f && c.job.settings.integrator.rouletteWindow <= 1.0f)) {
      throw bad("roulette_window is not in (0, 1]");
    }
    // ... and those with lit patches from before the choice gathered the sky's light at the patches too.
    c.job.settings.integrator.litPatchSky = s.value("lit_patch_sky", true);
    // ... and with the patch's point uniform on its triangle (no maps of where the sun lights it).
    c.job.settings.integrator.litPatchMaps = s.value("lit_patch_maps", false);
    // ... and with training points at the vertices alone.
    c.job.settings.integrator.litPatchInteriorTraining = s.value("lit_patch_interior_training", false);
    // ... and with continuations by the cosine alone.
    c.job.settings.integrator.portalContinuation = s.value("portal_continuation", false);
    // ... and without light paths.
    c.job.settings.lightPaths.enabled = s.value("light_paths", false);
    // ... and with every point taking every pass.
    e.allocationFraction = s.value("error_allocation", 0.0f);
    if (!(e.allocationFraction >= 0.0f && e.allocationFraction <= 1.0f)) throw bad("error_allocation is not in [0, 1]");
    c.job.exportGltf = s.at("export_gltf").get<bool>();
    // ... and with automatic light textures on large flat meshes alone, which the trace RDB gave them.
    c.job.automaticLightTextures = s.value("automatic_light_textures", false);
    c.job.checkpointIntervalS = s.at("checkpoint_interval_s").get<double>();
    c.fingerprint = std::stoull(j.at("trace_rdb_fingerprint").get<std::string>(), nullptr, 16);
    for (const nlohmann::json& row : j.at("history")) {
      // The fifth entry, the sun-direct part's error, is missing in checkpoints of bakes that did not keep
      // it.
      if (!row.is_array() || (row.size() != 4 && row.size() != 5)) {
        throw bad(
            "a history row is not [seconds, samples, relative error, rays per second, sun-direct relative "
            "error]");
      }
      raytracer::ConvergencePoint p;
      p.seconds = row.at(0).get<double>();
      p.samples = unsignedValue<uint32_t>(row.at(1), "a history row's samples");
      p.relativeErrorP95 = row.at(2).get<float>();
      p.raysPerSecond = row.at(3).get<double>();
      if (row.size() == 5) p.sunDirectRelativeErrorP95 = row.at(4).get<float>();
      c.state.history.push_back(p);
    }
    const std::string stateFile = j.at("state_file").get<std::string>();
    if (stateFile.find('/') != std::string::npos) throw bad("state_file must name a file in " + dir.string());
    const std::filesystem::path statePath = dir / stateFile;
    const std::string bytes = readInputFile(statePath, "checkpoint state");
    Fnv1a h;
    h.bytes(bytes.data(), bytes.size());
    if (hex(h.hash()) != j.at("state_fnv1a").get<std::string>()) {
      throw InputError(SourceLocation{statePath.string()}, "the state file does not match checkpoint.json",
                       "the checkpoint is damaged; start the bake afresh (without --resume)");
    }
    c.state.progress = raytracer::deserializeProgressState(bytes, statePath.string());
  } catch (const nlohmann::json::exception& e) {
    throw bad(e.what());
  } catch (const std::invalid_argument& e) {
    throw bad(e.what());
  } catch (const std::out_of_range& e) {
    throw bad(e.what());
  }
  return c;
}

void checkCheckpointKeepsWhatTheBakeNeeds(const raytracer::BakeCheckpoint& state, const rdb::TraceRdb& rdb,
                                          const std::filesystem::path& outDir) {
  if (state.progress.channels == (raytracer::sunLights(rdb) ? 2u : 1u)) return;
  throw InputError(SourceLocation{(checkpointDirFor(outDir) / "checkpoint.json").string()},
                   "was saved by a version of fly that did not keep the sun's direct light apart, which this "
                   "bake under the sun needs",
                   "start the bake afresh without --resume (the checkpoint is replaced)");
}

}  // namespace fly::cli
