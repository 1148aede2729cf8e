#include "raster/environment_light.h"

#include <epoxy/gl.h>

#include <cmath>
#include <stdexcept>

#include "raster/shaders/environment_glsl.h"

namespace fly::raster {
namespace {

bool powerOfTwo(uint32_t n) { return n != 0 && (n & (n - 1)) == 0; }

void check(bool ok, const std::string& what) {
  if (!ok) throw std::invalid_argument("EnvironmentSettings: " + what);
}

GLuint cubeTexture(uint32_t facePx, uint32_t levels) {
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_CUBE_MAP, 1, &t);
  glTextureStorage2D(t, GLsizei(levels), GL_RGBA32F, GLsizei(facePx), GLsizei(facePx));
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, levels > 1 ? GL_LINEAR_MIPMAP_LINEAR : GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  return t;
}

// One invocation per texel of the six n × n faces (8 × 8 work groups), then its image stores made visible to
// texture fetches, image access and read-backs.
void dispatchCube(uint32_t n) {
  glDispatchCompute((n + 7) / 8, (n + 7) / 8, 6);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
}

std::vector<Rgb> readFace(GLuint texture, uint32_t level, uint32_t face, uint32_t n) {
  std::vector<float> rgba(size_t(n) * n * 4);
  glGetTextureSubImage(texture, GLint(level), 0, 0, GLint(face), GLsizei(n), GLsizei(n), 1, GL_RGBA, GL_FLOAT,
                       GLsizei(rgba.size() * sizeof(float)), rgba.data());
  std::vector<Rgb> rgb(size_t(n) * n);
  for (size_t i = 0; i < rgb.size(); ++i) rgb[i] = Rgb(rgba[4 * i], rgba[4 * i + 1], rgba[4 * i + 2]);
  return rgb;
}

}  // namespace

struct EnvironmentLight::Gpu {
  GLuint source = 0, radiance = 0, irradiance = 0, table = 0;
  GLuint fromEquirect = 0, downsample = 0, prefilter = 0, irradianceProgram = 0;
  uint32_t sourceLevels = 1;
  ~Gpu() {
    const GLuint textures[] = {source, radiance, irradiance, table};
    glDeleteTextures(4, textures);
    for (GLuint p : {fromEquirect, downsample, prefilter, irradianceProgram}) glDeleteProgram(p);
  }
};

EnvironmentLight::EnvironmentLight(Compile compile, const EnvironmentSettings& s)
    : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)), settings_(s) {
  check(s.cubePx >= 8 && s.cubePx <= 2048, "cubePx must lie in [8, 2048]");
  const uint32_t maxLevels = uint32_t(std::log2(double(s.cubePx))) + 1;
  check(s.radianceLevels >= 2 && s.radianceLevels <= maxLevels, "radianceLevels must lie in [2, log2(cubePx) + 1]");
  check(s.prefilterSamples >= 16 && s.prefilterSamples <= 65536, "prefilterSamples must lie in [16, 65536]");
  check(s.irradiancePx >= 1 && s.irradiancePx <= 256, "irradiancePx must lie in [1, 256]");
  check(powerOfTwo(s.irradianceQuadPx) && s.irradianceQuadPx <= s.cubePx,
        "irradianceQuadPx must be a power of 2 no larger than cubePx");
  check(s.tablePx >= 8 && s.tablePx <= 1024, "tablePx must lie in [8, 1024]");
  check(s.tableSamples >= 16 && s.tableSamples <= 65536, "tableSamples must lie in [16, 65536]");
}

EnvironmentLight::~EnvironmentLight() = default;

float EnvironmentLight::levelAlpha(uint32_t k) const {
  const float r = float(k) / float(settings_.radianceLevels - 1);
  return r * r;
}

void EnvironmentLight::build(const std::vector<Rgb>& radianceCdM2, uint32_t width, uint32_t height) {
  if (width == 0 || height == 0 || radianceCdM2.size() != size_t(width) * height)
    throw std::invalid_argument("environment image: " + std::to_string(width) + " × " + std::to_string(height) +
                                " pixels expected, " + std::to_string(radianceCdM2.size()) + " given");
  for (size_t i = 0; i < radianceCdM2.size(); ++i) {
    const Rgb& c = radianceCdM2[i];
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(c[k]) || c[k] < 0.0f) {
        throw std::invalid_argument("environment image: pixel (" + std::to_string(i % width) + ", " +
                                    std::to_string(i / width) +
                                    ") is negative or not finite; radiance must be ≥ 0 cd/m²");
      }
    }
  }
  GLuint t = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &t);
  glTextureStorage2D(t, 1, GL_RGB32F, GLsizei(width), GLsizei(height));
  glTextureSubImage2D(t, 0, 0, 0, GLsizei(width), GLsizei(height), GL_RGB, GL_FLOAT, radianceCdM2.data());
  glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(t, GL_TEXTURE_WRAP_S, GL_REPEAT);        // φ wraps around
  glTextureParameteri(t, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);  // θ ends at the poles
  try {
    build(t);
  } catch (...) {
    glDeleteTextures(1, &t);
    throw;
  }
  glDeleteTextures(1, &t);
}

unsigned EnvironmentLight::sourceCube() {
  Gpu& g = *gpu_;
  const EnvironmentSettings& s = settings_;
  if (!g.source) {
    g.sourceLevels = uint32_t(std::log2(double(s.cubePx))) + 1;
    g.source = cubeTexture(s.cubePx, g.sourceLevels);
    g.radiance = cubeTexture(s.cubePx, s.radianceLevels);
    g.irradiance = cubeTexture(s.irradiancePx, 1);
  }
  return g.source;
}

void EnvironmentLight::build(unsigned equirectTexture) {
  Gpu& g = *gpu_;
  // The source's level 0 from the image.
  sourceCube();
  if (!g.fromEquirect) {
    g.fromEquirect = compile_("environment-cube", std::string(shaders::kEnvironmentCommon),
                              {{GL_COMPUTE_SHADER, shaders::kEnvironmentFromEquirect}});
  }
  glUseProgram(g.fromEquirect);
  glUniform1i(glGetUniformLocation(g.fromEquirect, "uSize"), GLint(settings_.cubePx));
  glBindTextureUnit(0, equirectTexture);
  glBindImageTexture(0, g.source, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatchCube(settings_.cubePx);
  buildFromSource();
}

void EnvironmentLight::buildFromSource() {
  Gpu& g = *gpu_;
  const EnvironmentSettings& s = settings_;
  auto program = [&](GLuint& p, const char* name, const char* source) {
    if (!p) p = compile_(name, std::string(shaders::kEnvironmentCommon), {{GL_COMPUTE_SHADER, source}});
    glUseProgram(p);
    return p;
  };
  sourceCube();
  // The source's coarser levels, box-filtered from level 0.
  GLuint p = program(g.downsample, "environment-downsample", shaders::kEnvironmentDownsample);
  for (uint32_t level = 1; level < g.sourceLevels; ++level) {
    const uint32_t n = std::max(1u, s.cubePx >> level);
    glUniform1i(glGetUniformLocation(p, "uSize"), GLint(n));
    glBindImageTexture(0, g.source, GLint(level - 1), GL_TRUE, 0, GL_READ_ONLY, GL_RGBA32F);
    glBindImageTexture(1, g.source, GLint(level), GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    dispatchCube(n);
  }
  // The prefiltered levels; level 0 (α = 0) is the source itself.
  glCopyImageSubData(g.source, GL_TEXTURE_CUBE_MAP, 0, 0, 0, 0, g.radiance, GL_TEXTURE_CUBE_MAP, 0, 0, 0, 0,
                     GLsizei(s.cubePx), GLsizei(s.cubePx), 6);
  p = program(g.prefilter, "environment-prefilter", shaders::kEnvironmentPrefilter);
  glBindTextureUnit(0, g.source);
  glUniform1i(glGetUniformLocation(p, "uSourceSize"), GLint(s.cubePx));
  glUniform1i(glGetUniformLocation(p, "uSamples"), GLint(s.prefilterSamples));
  for (uint32_t k = 1; k < s.radianceLevels; ++k) {
    const uint32_t n = std::max(1u, s.cubePx >> k);
    glUniform1i(glGetUniformLocation(p, "uSize"), GLint(n));
    glUniform1f(glGetUniformLocation(p, "uAlpha"), levelAlpha(k));
    glBindImageTexture(0, g.radiance, GLint(k), GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    dispatchCube(n);
  }
  // The irradiance.
  p = program(g.irradianceProgram, "environment-irradiance", shaders::kEnvironmentIrradiance);
  glBindTextureUnit(0, g.source);
  glUniform1i(glGetUniformLocation(p, "uSize"), GLint(s.irradiancePx));
  glUniform1i(glGetUniformLocation(p, "uQuadSize"), GLint(s.irradianceQuadPx));
  glUniform1f(glGetUniformLocation(p, "uQuadLod"), float(std::log2(double(s.cubePx / s.irradianceQuadPx))));
  glBindImageTexture(0, g.irradiance, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatchCube(s.irradiancePx);
  // The split-sum table depends on nothing but the settings: made once.
  if (!g.table) g.table = makeSplitSumTable(compile_, s.tablePx, s.tableSamples);
}

unsigned makeSplitSumTable(const EnvironmentLight::Compile& compile, uint32_t tablePx, uint32_t tableSamples) {
  GLuint table = 0;
  glCreateTextures(GL_TEXTURE_2D, 1, &table);
  glTextureStorage2D(table, 1, GL_RG32F, GLsizei(tablePx), GLsizei(tablePx));
  glTextureParameteri(table, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
  glTextureParameteri(table, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(table, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(table, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  const GLuint p = compile("environment-split-sum", std::string(shaders::kEnvironmentCommon),
                           {{GL_COMPUTE_SHADER, shaders::kEnvironmentSplitSum}});
  glUseProgram(p);
  glUniform1i(glGetUniformLocation(p, "uSize"), GLint(tablePx));
  glUniform1i(glGetUniformLocation(p, "uSamples"), GLint(tableSamples));
  glBindImageTexture(0, table, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32F);
  glDispatchCompute((tablePx + 7) / 8, (tablePx + 7) / 8, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_TEXTURE_UPDATE_BARRIER_BIT);
  glDeleteProgram(p);
  return table;
}

unsigned EnvironmentLight::radianceCube() const { return gpu_->radiance; }
unsigned EnvironmentLight::irradianceCube() const { return gpu_->irradiance; }
unsigned EnvironmentLight::splitSumTable() const { return gpu_->table; }

std::vector<Rgb> EnvironmentLight::readRadiance(uint32_t level, uint32_t face) const {
  return readFace(gpu_->radiance, level, face, std::max(1u, settings_.cubePx >> level));
}

std::vector<Rgb> EnvironmentLight::readIrradiance(uint32_t face) const {
  return readFace(gpu_->irradiance, 0, face, settings_.irradiancePx);
}

std::vector<vec2> EnvironmentLight::readSplitSum() const {
  const uint32_t n = settings_.tablePx;
  std::vector<vec2> ab(size_t(n) * n);
  glGetTextureImage(gpu_->table, 0, GL_RG, GL_FLOAT, GLsizei(ab.size() * sizeof(vec2)), ab.data());
  return ab;
}

}  // namespace fly::raster
