#include "raster/ball_texture.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "raster/shaders/ball_texture_glsl.h"

namespace fly::raster {
namespace {

// shaders::kMeasuredBrdf's BallBrdf.
struct GpuBallBrdf {
  vec4 kind, base;
  vec4 lobes[3];
  vec4 albedo[rdb::kRasterAlbedoSteps];
};
struct GpuBallLight {
  vec4 toLightView, lux;
};

}  // namespace

mat3 ballFrame(const mat3& viewFromWorld, const vec3& eyeM, bool orthographic, const vec3& centreM) {
  const vec3 offset = eyeM - centreM;
  if (orthographic || !(glm::dot(offset, offset) > 0.0f)) return viewFromWorld;
  const vec3 e = glm::normalize(viewFromWorld * offset);  // towards the eye, view frame
  const vec3 z(0.0f, 0.0f, 1.0f);
  const float c = glm::dot(e, z);
  if (c < 1e-3f) return viewFromWorld;  // the centre at or behind the eye's plane
  // Rodrigues' rotation about e × z by the angle between them: R v = c v + (k × v) + (k·v) k / (1 + c),
  // k = e × z (|k| = sin).
  const vec3 k = glm::cross(e, z);
  const mat3 kx(vec3(0.0f, k.z, -k.y), vec3(-k.z, 0.0f, k.x), vec3(k.y, -k.x, 0.0f));  // columns
  const mat3 rotation = mat3(c) + kx + glm::outerProduct(k, k) / (1.0f + c);
  return rotation * viewFromWorld;
}

std::vector<DistantLight> distantLights(const rdb::RasterRdb& rdb, const vec3& centreM) {
  std::vector<DistantLight> out;
  for (uint32_t index = 0; index < rdb.lights.size(); ++index) {
    const rdb::RasterLight& l = rdb.lights[index];
    DistantLight d;
    d.light = index;
    d.illuminanceLux = rdb::punctualIlluminanceLux(rdb, l, centreM, d.toLightWorld);
    if (maxComponent(d.illuminanceLux) > 0.0f) out.push_back(d);
  }
  return out;
}

struct BallTextures::Gpu {
  struct Program {
    GLuint program = 0;
    GLint brdf = -1, size = -1, firstLayer = -1;
    GLint firstLight = -1, lightCount = -1, sunView = -1, sunLux = -1, hasEnvironment = -1;  // the ball pass
    GLint environment = -1, upView = -1, upCdM2 = -1, downCdM2 = -1, worldFromView = -1, envSteps = -1;  // env
  };
  Program ball, env;
  GLuint brdfs = 0, lights = 0, tables = 0, balls = 0, environment = 0;
  uint32_t ballSize = 0, envSize = 0, layers = 0;

  ~Gpu() {
    glDeleteProgram(ball.program);
    glDeleteProgram(env.program);
    const GLuint buffers[] = {brdfs, lights};
    glDeleteBuffers(2, buffers);
    const GLuint textures[] = {tables, balls, environment};
    glDeleteTextures(3, textures);
  }
};

BallTextures::BallTextures(SunShadows::Compile compile) : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)) {}

BallTextures::~BallTextures() = default;

void BallTextures::setSettings(const BallSettings& settings) {
  if (settings.sizePx < 8 || settings.sizePx > 4096)
    throw std::invalid_argument("a ball texture takes 8 to 4096 texels per side, not " + std::to_string(settings.sizePx));
  if (settings.envSizePx < 4 || settings.envSizePx > settings.sizePx)
    throw std::invalid_argument("the ball's environment image takes 4 texels per side up to the ball's " +
                                std::to_string(settings.sizePx) + ", not " + std::to_string(settings.envSizePx));
  if (settings.envGridSteps < 1 || settings.envGridSteps > 256)
    throw std::invalid_argument("the ball's environment grid takes 1 to 256 steps per axis, not " +
                                std::to_string(settings.envGridSteps));
  if (!(settings.nearLightRadii >= 0.0f) || !std::isfinite(settings.nearLightRadii))
    throw std::invalid_argument("the near lights' distance in object radii must be finite and ≥ 0");
  if (!(settings == settings_)) {
    for (auto& k : keys_) k.clear();
  }
  settings_ = settings;
}

void BallTextures::setBrdfs(const rdb::RasterRdb& rdb) {
  brdfCount_ = uint32_t(rdb.measuredBrdfs.size());
  keys_.assign(brdfCount_, {});
  ballFromWorld_.assign(brdfCount_, mat3(1.0f));
  nearLights_.assign(brdfCount_, {});
  std::vector<GpuBallBrdf> blocks;
  uint32_t tableSlices = 0;
  for (const rdb::RasterMeasuredBrdf& b : rdb.measuredBrdfs) {
    if (b.kind == rdb::RasterBrdfKind::kTable) tableSlices += 90;
  }
  glDeleteTextures(1, &gpu_->tables);
  gpu_->tables = 0;
  if (tableSlices > 0) {
    GLint max3d = 0;
    glGetIntegerv(GL_MAX_3D_TEXTURE_SIZE, &max3d);
    if (tableSlices > uint32_t(max3d)) {
      throw std::runtime_error("the scene's " + std::to_string(tableSlices / 90) +
                               " measured BRDF tables exceed the OpenGL driver's 3D texture depth of " +
                               std::to_string(max3d) + ": use at most " + std::to_string(max3d / 90));
    }
    glCreateTextures(GL_TEXTURE_3D, 1, &gpu_->tables);
    glTextureStorage3D(gpu_->tables, 1, GL_RGBA32F, 180, 90, GLsizei(tableSlices));
    glTextureParameteri(gpu_->tables, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(gpu_->tables, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  uint32_t slice = 0;
  for (const rdb::RasterMeasuredBrdf& b : rdb.measuredBrdfs) {
    GpuBallBrdf g{};
    const rdb::RasterCarPaint& p = b.carPaint;
    g.kind = vec4(b.kind == rdb::RasterBrdfKind::kTable ? 0.0f : 1.0f, float(slice), p.coatIor, p.coatAlpha);
    g.base = vec4(p.baseAlbedo, p.internalDiffuseReflectance);
    for (size_t k = 0; k < 3; ++k) g.lobes[k] = vec4(p.lobeF0[k], p.lobeAlpha[k]);
    for (size_t k = 0; k < rdb::kRasterAlbedoSteps && k < b.albedo.size(); ++k) g.albedo[k] = vec4(b.albedo[k], 0.0f);
    if (b.kind == rdb::RasterBrdfKind::kTable) {
      glTextureSubImage3D(gpu_->tables, 0, 0, 0, GLint(slice), 180, 90, 90, GL_RGBA, GL_FLOAT, b.tableRgba.data());
      slice += 90;
    }
    blocks.push_back(g);
  }
  glDeleteBuffers(1, &gpu_->brdfs);
  glCreateBuffers(1, &gpu_->brdfs);
  glNamedBufferStorage(gpu_->brdfs, GLsizeiptr(std::max<size_t>(1, blocks.size()) * sizeof(GpuBallBrdf)),
                       blocks.empty() ? nullptr : blocks.data(), 0);
}

namespace {

// An RGBA32F array texture of `layers` size × size layers, bilinear, clamped.
GLuint arrayTexture(uint32_t size, uint32_t layers) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &t);
  glTextureStorage3D(t, 1, GL_RGBA32F, GLsizei(size), GLsizei(size), GLsizei(layers));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

}  // namespace

int BallTextures::update(const rdb::RasterRdb& rdb, const BallLighting& lighting) {
  if (brdfCount_ == 0) return 0;
  Gpu& g = *gpu_;
  const uint32_t n = settings_.sizePx, m = settings_.envSizePx;
  if (g.ballSize != n || g.envSize != m || g.layers != brdfCount_) {
    const GLuint old[] = {g.balls, g.environment};
    glDeleteTextures(2, old);
    g.balls = arrayTexture(n, 2 * brdfCount_);
    g.environment = arrayTexture(m, brdfCount_);
    g.ballSize = n;
    g.envSize = m;
    g.layers = brdfCount_;
    for (auto& k : keys_) k.clear();
  }
  const bool hasEnvironment = lighting.environment != BallLighting::Environment::kNone;
  auto program = [&](Gpu::Program& p, bool env) {
    if (p.program) return;
    const std::string defines = "#define FLY_ALBEDO_STEPS " + std::to_string(rdb::kRasterAlbedoSteps) +
                                "\n#define FLY_BRDF_BINDING 0\n#define FLY_BRDF_TABLE_UNIT 0\n" +
                                (env ? "#define FLY_BALL_ENV\n" : "");
    const std::string source =
        std::string("const float kPi = 3.14159265358979;\n") + shaders::kMeasuredBrdf + shaders::kBallCompute;
    p.program = compile_(env ? "ball-environment" : "ball", defines, {{GL_COMPUTE_SHADER, source.c_str()}});
    auto loc = [&](const char* name) { return glGetUniformLocation(p.program, name); };
    p.brdf = loc("uBrdf");
    p.size = loc("uSize");
    p.firstLayer = loc("uFirstLayer");
    p.firstLight = loc("uFirstLight");
    p.lightCount = loc("uLightCount");
    p.sunView = loc("uSunView");
    p.sunLux = loc("uSunLux");
    p.hasEnvironment = loc("uHasEnvironment");
    p.environment = loc("uEnvironment");
    p.upView = loc("uUpView");
    p.upCdM2 = loc("uUpCdM2");
    p.downCdM2 = loc("uDownCdM2");
    p.worldFromView = loc("uWorldFromView");
    p.envSteps = loc("uEnvSteps");
  };
  const Rgb sunLux = lighting.sun ? lighting.sunLux : Rgb(0.0f);
  // Every ball's lights in one buffer; the balls whose inputs changed.
  std::vector<GpuBallLight> lights;
  std::vector<uint32_t> firstLight(brdfCount_ + 1, 0);
  std::vector<uint32_t> changed;
  for (uint32_t k = 0; k < brdfCount_; ++k) {
    const mat3 viewFromWorld =
        ballFrame(lighting.viewFromWorld, lighting.eyeM, lighting.orthographic, rdb.measuredBrdfs[k].centreM);
    const vec3 sunView = glm::normalize(viewFromWorld * lighting.sunDirWorld);
    firstLight[k] = uint32_t(lights.size());
    // The lamps near this material's objects go to its pixels (the nearest kMaxNearLights), the rest here.
    const rdb::RasterMeasuredBrdf& brdf = rdb.measuredBrdfs[k];
    std::vector<std::pair<float, uint32_t>> near;
    for (uint32_t i = 0; i < rdb.lights.size(); ++i) {
      const rdb::RasterLight& l = rdb.lights[i];
      if (l.type == rdb::RasterLightType::kDirectional) continue;
      const float d = glm::length(l.positionM - brdf.centreM);
      if (d < settings_.nearLightRadii * brdf.radiusM) near.push_back({d, i});
    }
    std::sort(near.begin(), near.end());
    if (near.size() > kMaxNearLights) near.resize(kMaxNearLights);
    std::vector<int>& nearIndices = nearLights_[k];
    nearIndices.clear();
    for (const auto& [d, i] : near) nearIndices.push_back(int(i));
    for (const DistantLight& d : distantLights(rdb, brdf.centreM)) {
      if (std::find(nearIndices.begin(), nearIndices.end(), int(d.light)) != nearIndices.end()) continue;
      lights.push_back({vec4(glm::normalize(viewFromWorld * d.toLightWorld), 0.0f), vec4(d.illuminanceLux, 0.0f)});
    }
    firstLight[k + 1] = uint32_t(lights.size());
    // What the ball is made from.
    std::vector<float> key;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) key.push_back(viewFromWorld[c][r]);
    key.insert(key.end(), {sunView.x, sunView.y, sunView.z, sunLux.r, sunLux.g, sunLux.b,
                           float(int(lighting.environment))});
    if (lighting.environment == BallLighting::Environment::kSky) key.push_back(float(lighting.skyVersion));
    if (lighting.environment == BallLighting::Environment::kHemispheres) {
      key.insert(key.end(), {lighting.upLux.r, lighting.upLux.g, lighting.upLux.b, lighting.downLux.r,
                             lighting.downLux.g, lighting.downLux.b});
    }
    for (uint32_t i = firstLight[k]; i < firstLight[k + 1]; ++i) {
      for (int c = 0; c < 3; ++c) key.insert(key.end(), {lights[i].toLightView[c], lights[i].lux[c]});
    }
    if (key == keys_[k]) continue;
    keys_[k] = std::move(key);
    ballFromWorld_[k] = viewFromWorld;
    changed.push_back(k);
  }
  if (changed.empty()) return 0;
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.brdfs);
  if (g.tables) glBindTextureUnit(0, g.tables);
  if (hasEnvironment) {
    // The environment term of each changed ball, at M × M.
    program(g.env, true);
    const Gpu::Program& p = g.env;
    glUseProgram(p.program);
    if (lighting.environment == BallLighting::Environment::kSky) glBindTextureUnit(1, lighting.skyTexture);
    glBindImageTexture(0, g.environment, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    const Rgb up = lighting.upLux / kPiF, down = lighting.downLux / kPiF;
    glUniform1i(p.size, GLint(m));
    glUniform1i(p.environment, int(lighting.environment));
    glUniform3fv(p.upCdM2, 1, &up[0]);
    glUniform3fv(p.downCdM2, 1, &down[0]);
    glUniform1i(p.envSteps, GLint(settings_.envGridSteps));
    for (uint32_t k : changed) {
      const vec3 upView = ballFromWorld_[k] * vec3(0, 1, 0);
      const mat3 worldFromView = glm::transpose(ballFromWorld_[k]);
      glUniform3fv(p.upView, 1, &upView[0]);
      glUniformMatrix3fv(p.worldFromView, 1, GL_FALSE, &worldFromView[0][0]);
      glUniform1i(p.brdf, GLint(k));
      glUniform1i(p.firstLayer, GLint(k));
      glDispatchCompute(m, (m + 3) / 4, 1);  // shaders::kBallCompute's FLY_BALL_ENV work groups
    }
    glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  program(g.ball, false);
  const Gpu::Program& p = g.ball;
  glUseProgram(p.program);
  glDeleteBuffers(1, &g.lights);
  glCreateBuffers(1, &g.lights);
  glNamedBufferStorage(g.lights, GLsizeiptr(std::max<size_t>(1, lights.size()) * sizeof(GpuBallLight)),
                       lights.empty() ? nullptr : lights.data(), 0);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.lights);
  glBindTextureUnit(2, g.environment);
  glBindImageTexture(0, g.balls, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glUniform1i(p.size, GLint(n));
  glUniform1i(p.hasEnvironment, hasEnvironment ? 1 : 0);
  glUniform3fv(p.sunLux, 1, &sunLux[0]);
  for (uint32_t k : changed) {
    const vec3 sunView = glm::normalize(ballFromWorld_[k] * lighting.sunDirWorld);
    glUniform3fv(p.sunView, 1, &sunView[0]);
    glUniform1i(p.brdf, GLint(k));
    glUniform1i(p.firstLayer, GLint(2 * k));
    glUniform1i(p.firstLight, GLint(firstLight[k]));
    glUniform1i(p.lightCount, GLint(firstLight[k + 1] - firstLight[k]));
    glDispatchCompute((n + 7) / 8, (n + 7) / 8, 2);
  }
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  return int(changed.size());
}

unsigned BallTextures::texture() const { return gpu_->balls; }

unsigned BallTextures::brdfBuffer() const { return gpu_->brdfs; }

unsigned BallTextures::tableTexture() const { return gpu_->tables; }

std::vector<float> BallTextures::readLayer(uint32_t layer) const {
  const uint32_t n = gpu_->ballSize;
  std::vector<float> rgba(size_t(n) * n * 4);
  glGetTextureSubImage(gpu_->balls, 0, 0, 0, GLint(layer), GLsizei(n), GLsizei(n), 1, GL_RGBA, GL_FLOAT,
                       GLsizei(rgba.size() * sizeof(float)), rgba.data());
  return rgba;
}

}  // namespace fly::raster
