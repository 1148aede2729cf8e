#include "cli/bake_checkpoint.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "base/error.h"
#include "rdb/trace_rdb_builder.h"

namespace fly::cli {
namespace {

namespace fs = std::filesystem;

class BakeCheckpointTest : public ::testing::Test {
 protected:
  void SetUp() override {
    parent_ = fs::temp_directory_path() /
              ("fly_bake_checkpoint_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(parent_);
    fs::create_directories(parent_);
    job_.scenePath = "scene.json";
    job_.outDir = (parent_ / "bake").string();
    job_.settings.estimate.maxSamples = 256;
    job_.settings.estimate.firstPassSamples = 8;
    job_.settings.estimate.replicates = 4;
    job_.settings.estimate.threads = 3;
    job_.settings.estimate.seed = 42;
    job_.settings.integrator.maxBounces = 5;
    job_.samplerName = "sobol";
    job_.checkpointIntervalS = 60.0;
    state_.progress.pointCount = 2;
    state_.progress.replicates = 4;
    state_.progress.samplesPerPoint = 8;
    state_.progress.sums.assign(2 * (2 + 4), dvec3(1.0));
    state_.history = {{.seconds = 0.5, .samples = 8, .relativeErrorP95 = 0.125f, .raysPerSecond = 320.0}};
    saveBakeCheckpoint(job_, 0x0123456789abcdefull, state_);
  }
  void TearDown() override { fs::remove_all(parent_); }

  fs::path jsonPath() const { return checkpointDirFor(job_.outDir) / "checkpoint.json"; }

  // Rewrites checkpoint.json with `edit` applied.
  template <class F>
  void editJson(F edit) {
    std::ifstream in(jsonPath());
    nlohmann::json j = nlohmann::json::parse(in);
    in.close();
    edit(j);
    std::ofstream(jsonPath()) << j.dump(2);
  }

  // The message of the InputError loading throws ("no error" when it loads).
  std::string loadError() const {
    try {
      loadBakeCheckpoint(job_.outDir);
    } catch (const InputError& e) {
      return e.what();
    }
    return "no error";
  }

  void expectChoiceIsKept(bool raytracer::IntegratorSettings::*choice, const char* key, bool legacy);

  fs::path parent_;
  BakeJob job_;
  raytracer::BakeCheckpoint state_;
};

// A checkpoint of a fly that did not keep the sun's direct part apart (one quantity a point: progress-state
// formats 2 and 3) resumes a bake without a sun, and is refused, naming checkpoint.json, for one under the sun.
TEST_F(BakeCheckpointTest, AnOldCheckpointCannotContinueABakeUnderTheSun) {
  rdb::TraceRdbBuilder b;
  b.ground(1.0f, 1, b.material(Rgb(0.5f)));
  b.uniformSky(Rgb(1000.0f));
  const LoadedCheckpoint c = loadBakeCheckpoint(job_.outDir);
  ASSERT_EQ(c.state.progress.channels, 1u);
  EXPECT_NO_THROW(checkCheckpointKeepsWhatTheBakeNeeds(c.state, b.rdb, job_.outDir));
  b.sun(vec3(0.3f, 0.8f, 0.1f), Rgb(80000.0f));
  try {
    checkCheckpointKeepsWhatTheBakeNeeds(c.state, b.rdb, job_.outDir);
    ADD_FAILURE() << "a one-quantity checkpoint was accepted for a bake under the sun";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().file, jsonPath().string());
    EXPECT_NE(std::string(e.what()).find("did not keep the sun's direct light apart"), std::string::npos);
  }
  raytracer::BakeCheckpoint sunState = c.state;
  sunState.progress.channels = 2;
  EXPECT_NO_THROW(checkCheckpointKeepsWhatTheBakeNeeds(sunState, b.rdb, job_.outDir));
}

TEST_F(BakeCheckpointTest, LoadGivesBackWhatWasSaved) {
  const LoadedCheckpoint c = loadBakeCheckpoint(job_.outDir);
  EXPECT_EQ(c.fingerprint, 0x0123456789abcdefull);
  EXPECT_EQ(c.job.settings.estimate.maxSamples, 256u);
  EXPECT_EQ(c.job.settings.estimate.firstPassSamples, 8u);
  EXPECT_EQ(c.job.settings.estimate.replicates, 4u);
  EXPECT_EQ(c.job.settings.estimate.threads, 3u);
  EXPECT_EQ(c.job.settings.estimate.seed, 42u);
  EXPECT_EQ(c.job.settings.integrator.maxBounces, 5u);
  ASSERT_EQ(c.state.history.size(), 1u);
  EXPECT_EQ(c.state.history[0].samples, 8u);
  EXPECT_EQ(c.state.progress.sums.size(), 12u);
}

// An estimator choice travels with the checkpoint both ways, and one written before the choice existed (the
// key absent) resumes with `legacy`, the estimator it started with.
void BakeCheckpointTest::expectChoiceIsKept(bool raytracer::IntegratorSettings::*choice, const char* key,
                                            bool legacy) {
  const auto loaded = [&] { return loadBakeCheckpoint(job_.outDir).job.settings.integrator.*choice; };
  EXPECT_EQ(loaded(), raytracer::IntegratorSettings{}.*choice) << key;
  for (const bool value : {false, true}) {
    job_.settings.integrator.*choice = value;
    saveBakeCheckpoint(job_, 0x0123456789abcdefull, state_);
    EXPECT_EQ(loaded(), value) << key;
  }
  job_.settings.integrator.*choice = !legacy;
  saveBakeCheckpoint(job_, 0x0123456789abcdefull, state_);
  editJson([&](nlohmann::json& j) { j["settings"].erase(key); });
  EXPECT_EQ(loaded(), legacy) << key;
}

// Whether the lit patches' samples gather the sky's light too: checkpoints from before resume with the sky's
// light at the patches. Whether their points follow the maps of the triangles' sunlit parts, whether the
// regions also train from points inside large triangles, and whether continuations head through the portals:
// checkpoints from before resume without.
TEST_F(BakeCheckpointTest, EstimatorChoicesAreKeptAndOlderCheckpointsResumeAsTheyStarted) {
  using S = raytracer::IntegratorSettings;
  expectChoiceIsKept(&S::litPatchSky, "lit_patch_sky", true);
  expectChoiceIsKept(&S::litPatchMaps, "lit_patch_maps", false);
  expectChoiceIsKept(&S::litPatchInteriorTraining, "lit_patch_interior_training", false);
  expectChoiceIsKept(&S::portalContinuation, "portal_continuation", false);
}

// Russian roulette's weight window travels with the checkpoint; one written before the window existed resumes
// with throughput roulette (a window of 1), the estimator it started with, and a window outside (0, 1] is bad
// input.
TEST_F(BakeCheckpointTest, RouletteWindowIsKeptAndOlderCheckpointsResumeWithThroughputRoulette) {
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.integrator.rouletteWindow, raytracer::kRouletteWindow);
  job_.settings.integrator.rouletteWindow = 0.5f;
  saveBakeCheckpoint(job_, 0x0123456789abcdefull, state_);
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.integrator.rouletteWindow, 0.5f);
  editJson([](nlohmann::json& j) { j["settings"].erase("roulette_window"); });
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.integrator.rouletteWindow, 1.0f);
  editJson([](nlohmann::json& j) { j["settings"]["roulette_window"] = 0.0; });
  EXPECT_THROW(loadBakeCheckpoint(job_.outDir), InputError);
}

// The allocation by error's fraction travels with the checkpoint (the resumed passes must skip the same
// points); one written before the allocation existed resumes with every point taking every pass, and a
// fraction outside [0, 1] is a damaged checkpoint.
TEST_F(BakeCheckpointTest, ErrorAllocationIsKeptAndOlderCheckpointsResumeWithoutIt) {
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.estimate.allocationFraction, 0.0f);
  job_.settings.estimate.allocationFraction = raytracer::kBakeAllocationFraction;
  saveBakeCheckpoint(job_, 0x0123456789abcdefull, state_);
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.estimate.allocationFraction,
            raytracer::kBakeAllocationFraction);
  editJson([](nlohmann::json& j) { j["settings"].erase("error_allocation"); });
  EXPECT_EQ(loadBakeCheckpoint(job_.outDir).job.settings.estimate.allocationFraction, 0.0f);
  editJson([](nlohmann::json& j) { j["settings"]["error_allocation"] = 2.0; });
  EXPECT_NE(loadError().find("error_allocation is not in [0, 1]"), std::string::npos) << loadError();
}

// Counts that do not fit their type are a damaged checkpoint, not a float-to-integer conversion out of range
// (undefined behaviour, found by fuzzing: tests/fuzz/corpus/bake_checkpoint/regression-*.json) or a
// wrap-around of -1 to 4294967295 threads.
TEST_F(BakeCheckpointTest, CountsOutOfRangeAreRejectedWithTheirName) {
  editJson([](nlohmann::json& j) { j["settings"]["max_samples"] = 1e30; });
  EXPECT_NE(loadError().find("max_samples must be an integer from 0 to 4294967295, not 1e+30"),
            std::string::npos)
      << loadError();
  editJson([](nlohmann::json& j) {
    j["settings"]["max_samples"] = 256;
    j["settings"]["threads"] = -1;
  });
  EXPECT_NE(loadError().find("threads must be an integer"), std::string::npos) << loadError();
  editJson([](nlohmann::json& j) {
    j["settings"]["threads"] = 3;
    j["history"][0][1] = 2.5;
  });
  EXPECT_NE(loadError().find("samples must be an integer"), std::string::npos) << loadError();
  editJson([](nlohmann::json& j) { j["history"] = {{1.0, 8}}; });
  EXPECT_NE(loadError().find("a history row is not"), std::string::npos) << loadError();
}

// A resumed bake must be of the same scene: the fingerprint follows the measured BRDFs, a car paint's
// parameters and a table's content and scale.
TEST(TraceRdbFingerprint, FollowsMeasuredBrdfs) {
  rdb::TraceRdbBuilder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.ground(1.0f, 1, mat);
  const uint64_t analytic = traceRdbFingerprint(b.rdb);
  CarPaintBrdf paint;
  paint.baseAlbedo = Rgb(0.2f);
  b.rdb.materials[mat].carPaint = paint;
  const uint64_t painted = traceRdbFingerprint(b.rdb);
  EXPECT_NE(painted, analytic);
  b.rdb.materials[mat].carPaint->coatAlpha = 0.05f;
  EXPECT_NE(traceRdbFingerprint(b.rdb), painted);

  b.rdb.materials[mat].carPaint.reset();
  std::vector<Rgb> samples(BrdfTable::kSamples, Rgb(0.1f));
  b.rdb.brdfTables.push_back({"a.binary", std::make_shared<const BrdfTable>(samples)});
  b.rdb.materials[mat].brdfTable = 0;
  const uint64_t measured = traceRdbFingerprint(b.rdb);
  EXPECT_NE(measured, analytic);
  samples[12345] = Rgb(0.2f);
  b.rdb.brdfTables[0].table = std::make_shared<const BrdfTable>(samples);
  const uint64_t remeasured = traceRdbFingerprint(b.rdb);
  EXPECT_NE(remeasured, measured);
  b.rdb.brdfTables[0].scale = 0.9f;
  EXPECT_NE(traceRdbFingerprint(b.rdb), remeasured);
}

// It follows the anisotropy and its rotation; equal U and V (isotropic, whatever their value) leave it as it
// was, so that checkpoints of isotropic scenes stay valid.
TEST(TraceRdbFingerprint, FollowsAnisotropy) {
  rdb::TraceRdbBuilder b;
  const uint32_t mat = b.material(Rgb(0.5f));
  b.rdb.materials[mat].reflection = Rgb(1.0f);
  b.ground(1.0f, 1, mat);
  const uint64_t isotropic = traceRdbFingerprint(b.rdb);
  b.rdb.materials[mat].anisotropyU = b.rdb.materials[mat].anisotropyV = 0.4f;
  EXPECT_EQ(traceRdbFingerprint(b.rdb), isotropic);
  b.rdb.materials[mat].anisotropyU = 0.6f;
  const uint64_t anisotropic = traceRdbFingerprint(b.rdb);
  EXPECT_NE(anisotropic, isotropic);
  b.rdb.materials[mat].anisotropyRotationRad = 0.5f;
  EXPECT_NE(traceRdbFingerprint(b.rdb), anisotropic);
}

}  // namespace
}  // namespace fly::cli
