#include "raster/ball_texture.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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

// The goniometric table's intensity towards `toSurface` (unit, world), bilinear in γ and C: the shader's
// flyGonioCd (shaders/scene_glsl.h).
float gonioCd(const rdb::RasterRdb& rdb, const rdb::RasterLight& l, const vec3& toSurface) {
  constexpr uint32_t G = rdb::kRasterGonioGammaSteps, C = rdb::kRasterGonioCSteps;
  const float gamma = std::acos(std::clamp(glm::dot(toSurface, l.directionWorld), -1.0f, 1.0f)) / kPiF * float(G - 1);
  float c = std::atan2(glm::dot(toSurface, glm::cross(l.directionWorld, l.cAxisWorld)),
                       glm::dot(toSurface, l.cAxisWorld)) /
            (2.0f * kPiF);
  if (c < 0.0f) c += 1.0f;
  c *= float(C);
  const uint32_t g0 = std::min(uint32_t(gamma), G - 2);
  const float fg = std::clamp(gamma - float(g0), 0.0f, 1.0f);
  const uint32_t c0 = std::min(uint32_t(c), C - 1), c1 = (c0 + 1) % C;
  const float fc = std::clamp(c - float(c0), 0.0f, 1.0f);
  const float* t = rdb.goniometricCd.data() + l.goniometricOffset;
  auto at = [&](uint32_t ci, uint32_t gi) { return t[ci * G + gi]; };
  return (1 - fc) * ((1 - fg) * at(c0, g0) + fg * at(c0, g0 + 1)) + fc * ((1 - fg) * at(c1, g0) + fg * at(c1, g0 + 1));
}

}  // namespace

std::vector<DistantLight> distantLights(const rdb::RasterRdb& rdb, const vec3& centreM) {
  std::vector<DistantLight> out;
  for (const rdb::RasterLight& l : rdb.lights) {
    DistantLight d;
    if (l.type == rdb::RasterLightType::kDirectional) {
      d.toLightWorld = -l.directionWorld;
      d.illuminanceLux = l.intensity;
    } else {
      const vec3 offset = l.positionM - centreM;
      const float dist2 = glm::dot(offset, offset);
      if (!(dist2 > 1e-12f)) continue;
      const float dist = std::sqrt(dist2);
      d.toLightWorld = offset / dist;
      float window = 1.0f;
      if (std::isfinite(l.rangeM)) {
        const float r = dist / l.rangeM;
        window = std::max(0.0f, 1.0f - r * r * r * r);
        window *= window;
      }
      float cd = 1.0f;
      if (l.type == rdb::RasterLightType::kSpot) {
        const float scale = 1.0f / std::max(0.001f, l.cosInner - l.cosOuter);
        const float t = std::clamp((glm::dot(-d.toLightWorld, l.directionWorld) - l.cosOuter) * scale, 0.0f, 1.0f);
        cd = t * t;
      } else if (l.type == rdb::RasterLightType::kGoniometric) {
        cd = gonioCd(rdb, l, -d.toLightWorld);
      }
      d.illuminanceLux = l.intensity * (cd * window / dist2);
    }
    if (maxComponent(d.illuminanceLux) > 0.0f) out.push_back(d);
  }
  return out;
}

struct BallTextures::Gpu {
  GLuint program = 0;
  GLint brdf = -1, firstLayer = -1, size = -1, lightCount = -1, sunView = -1, sunLux = -1, environment = -1,
        upView = -1, upCdM2 = -1, downCdM2 = -1, worldFromView = -1, envSteps = -1;
  GLuint brdfs = 0, lights = 0, tables = 0, balls = 0;
  uint32_t ballSize = 0, ballLayers = 0;

  ~Gpu() {
    glDeleteProgram(program);
    const GLuint buffers[] = {brdfs, lights};
    glDeleteBuffers(2, buffers);
    glDeleteTextures(1, &tables);
    glDeleteTextures(1, &balls);
  }
};

BallTextures::BallTextures(SunShadows::Compile compile) : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)) {}

BallTextures::~BallTextures() = default;

void BallTextures::setSettings(const BallSettings& settings) {
  if (settings.sizePx < 8 || settings.sizePx > 4096)
    throw std::invalid_argument("a ball texture takes 8 to 4096 texels per side, not " + std::to_string(settings.sizePx));
  if (settings.envGridSteps < 1 || settings.envGridSteps > 256)
    throw std::invalid_argument("the ball's environment grid takes 1 to 256 steps per axis, not " +
                                std::to_string(settings.envGridSteps));
  if (settings.sizePx != settings_.sizePx || settings.envGridSteps != settings_.envGridSteps) {
    for (auto& k : keys_) k.clear();
  }
  settings_ = settings;
}

void BallTextures::setBrdfs(const rdb::RasterRdb& rdb) {
  brdfCount_ = uint32_t(rdb.measuredBrdfs.size());
  keys_.assign(brdfCount_, {});
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

int BallTextures::update(const rdb::RasterRdb& rdb, const BallLighting& lighting) {
  if (brdfCount_ == 0) return 0;
  const uint32_t n = settings_.sizePx;
  if (gpu_->ballSize != n || gpu_->ballLayers != 2 * brdfCount_) {
    glDeleteTextures(1, &gpu_->balls);
    glCreateTextures(GL_TEXTURE_2D_ARRAY, 1, &gpu_->balls);
    glTextureStorage3D(gpu_->balls, 1, GL_RGBA32F, GLsizei(n), GLsizei(n), GLsizei(2 * brdfCount_));
    glTextureParameteri(gpu_->balls, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTextureParameteri(gpu_->balls, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTextureParameteri(gpu_->balls, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTextureParameteri(gpu_->balls, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    gpu_->ballSize = n;
    gpu_->ballLayers = 2 * brdfCount_;
    for (auto& k : keys_) k.clear();
  }
  Gpu& g = *gpu_;
  if (!g.program) {
    const std::string defines = "#define FLY_ALBEDO_STEPS " + std::to_string(rdb::kRasterAlbedoSteps) + "\n";
    const std::string source = std::string(shaders::kMeasuredBrdf) + shaders::kBallCompute;
    g.program = compile_("ball", defines, {{GL_COMPUTE_SHADER, source.c_str()}});
    auto loc = [&](const char* name) { return glGetUniformLocation(g.program, name); };
    g.brdf = loc("uBrdf");
    g.firstLayer = loc("uFirstLayer");
    g.size = loc("uSize");
    g.lightCount = loc("uLightCount");
    g.sunView = loc("uSunView");
    g.sunLux = loc("uSunLux");
    g.environment = loc("uEnvironment");
    g.upView = loc("uUpView");
    g.upCdM2 = loc("uUpCdM2");
    g.downCdM2 = loc("uDownCdM2");
    g.worldFromView = loc("uWorldFromView");
    g.envSteps = loc("uEnvSteps");
  }
  const mat3& viewFromWorld = lighting.viewFromWorld;
  const mat3 worldFromView = glm::transpose(viewFromWorld);
  const vec3 sunView = glm::normalize(viewFromWorld * lighting.sunDirWorld);
  const Rgb sunLux = lighting.sun ? lighting.sunLux : Rgb(0.0f);
  const vec3 upView = viewFromWorld * vec3(0, 1, 0);
  const int environment = int(lighting.environment);
  int made = 0;
  bool bound = false;
  for (uint32_t k = 0; k < brdfCount_; ++k) {
    const rdb::RasterMeasuredBrdf& b = rdb.measuredBrdfs[k];
    std::vector<GpuBallLight> lights;
    for (const DistantLight& d : distantLights(rdb, b.centreM)) {
      lights.push_back({vec4(glm::normalize(viewFromWorld * d.toLightWorld), 0.0f), vec4(d.illuminanceLux, 0.0f)});
    }
    // What the ball is made from.
    std::vector<float> key;
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) key.push_back(viewFromWorld[c][r]);
    key.insert(key.end(), {sunView.x, sunView.y, sunView.z, sunLux.r, sunLux.g, sunLux.b, float(environment)});
    if (lighting.environment == BallLighting::Environment::kSky) key.push_back(float(lighting.skyVersion));
    if (lighting.environment == BallLighting::Environment::kHemispheres) {
      key.insert(key.end(), {lighting.upLux.r, lighting.upLux.g, lighting.upLux.b, lighting.downLux.r,
                             lighting.downLux.g, lighting.downLux.b});
    }
    for (const GpuBallLight& l : lights) {
      for (int c = 0; c < 3; ++c) key.insert(key.end(), {l.toLightView[c], l.lux[c]});
    }
    if (key == keys_[k]) continue;
    if (!bound) {
      glUseProgram(g.program);
      glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 0, g.brdfs);
      if (g.tables) glBindTextureUnit(0, g.tables);
      if (lighting.environment == BallLighting::Environment::kSky) glBindTextureUnit(1, lighting.skyTexture);
      glBindImageTexture(0, g.balls, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glUniform1i(g.size, GLint(n));
      glUniform3fv(g.sunView, 1, &sunView[0]);
      glUniform3fv(g.sunLux, 1, &sunLux[0]);
      glUniform1i(g.environment, environment);
      glUniform3fv(g.upView, 1, &upView[0]);
      const Rgb up = lighting.upLux / kPiF, down = lighting.downLux / kPiF;
      glUniform3fv(g.upCdM2, 1, &up[0]);
      glUniform3fv(g.downCdM2, 1, &down[0]);
      glUniformMatrix3fv(g.worldFromView, 1, GL_FALSE, &worldFromView[0][0]);
      glUniform1i(g.envSteps, GLint(settings_.envGridSteps));
      bound = true;
    }
    glDeleteBuffers(1, &g.lights);
    glCreateBuffers(1, &g.lights);
    glNamedBufferStorage(g.lights, GLsizeiptr(std::max<size_t>(1, lights.size()) * sizeof(GpuBallLight)),
                         lights.empty() ? nullptr : lights.data(), 0);
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 1, g.lights);
    glUniform1i(g.brdf, GLint(k));
    glUniform1i(g.firstLayer, GLint(2 * k));
    glUniform1i(g.lightCount, GLint(lights.size()));
    glDispatchCompute((n + 7) / 8, (n + 7) / 8, 2);
    keys_[k] = std::move(key);
    ++made;
  }
  if (made > 0) glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  return made;
}

unsigned BallTextures::texture() const { return gpu_->balls; }

std::vector<float> BallTextures::readLayer(uint32_t layer) const {
  const uint32_t n = gpu_->ballSize;
  std::vector<float> rgba(size_t(n) * n * 4);
  glGetTextureSubImage(gpu_->balls, 0, 0, 0, GLint(layer), GLsizei(n), GLsizei(n), 1, GL_RGBA, GL_FLOAT,
                       GLsizei(rgba.size() * sizeof(float)), rgba.data());
  return rgba;
}

}  // namespace fly::raster
