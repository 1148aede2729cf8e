#include "raster/sun_glass.h"

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>
#include <string>

#include "raster/shaders/scene_glsl.h"
#include "raster/shaders/sun_glass_glsl.h"

namespace fly::raster {

namespace {

// One clear-glass vertex of the map's pass (kSunGlassMapVertex's attributes).
struct GlassVertex {
  vec3 positionM;
  vec3 normal;
  vec4 transmission;  // rgb, w fresnelF0
  vec3 reflection;
};

// The map's clear value: T = 1, no pane (the lowest finite height, so that h − bias stays finite).
constexpr float kNoPaneHeightM = -3.0e38f;

}  // namespace

struct SunGlassMap::Gpu {
  std::vector<GlassVertex> vertices;  // CPU copy: the fit needs their positions
  GLuint buffer = 0, vao = 0, map = 0, fbo = 0, program = 0;
  GLint sunClipFromWorld = -1, sunDir = -1;
  uint32_t mapTexels = 0;
  bool built = false;
  vec3 builtSunDir{0.0f};
  uint32_t builtTexels = 0;
  mat4 mapFromWorld{1.0f};
  float texelSizeM = 0.0f;

  ~Gpu() {
    glDeleteBuffers(1, &buffer);
    glDeleteVertexArrays(1, &vao);
    glDeleteTextures(1, &map);
    glDeleteFramebuffers(1, &fbo);
    glDeleteProgram(program);
  }
};

SunGlassMap::SunGlassMap(SunShadows::Compile compile)
    : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)) {
  glCreateVertexArrays(1, &gpu_->vao);
}

SunGlassMap::~SunGlassMap() = default;

size_t SunGlassMap::setGlass(const rdb::RasterRdb& r) {
  Gpu& g = *gpu_;
  g.built = false;
  g.vertices.clear();
  for (const rdb::RasterMesh& mesh : r.meshes) {
    const rdb::RasterMaterial& m = r.materials[mesh.material];
    if (!(maxComponent(m.transmission) > 0.0f)) continue;
    for (uint32_t i = mesh.firstIndex; i + 2 < mesh.firstIndex + mesh.indexCount; i += 3) {
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t v = r.indices[i + k];
        g.vertices.push_back(
            {r.positionsM[v], r.normals[v], vec4(m.transmission, m.fresnelF0), m.reflection});
      }
    }
  }
  glDeleteBuffers(1, &g.buffer);
  glCreateBuffers(1, &g.buffer);
  glNamedBufferStorage(g.buffer, GLsizeiptr(std::max<size_t>(1, g.vertices.size()) * sizeof(GlassVertex)),
                       g.vertices.empty() ? nullptr : g.vertices.data(), 0);
  glVertexArrayVertexBuffer(g.vao, 0, g.buffer, 0, sizeof(GlassVertex));
  const struct {
    GLuint index;
    GLint components;
    size_t offset;
  } attributes[] = {{0, 3, offsetof(GlassVertex, positionM)},
                    {1, 3, offsetof(GlassVertex, normal)},
                    {2, 4, offsetof(GlassVertex, transmission)},
                    {3, 3, offsetof(GlassVertex, reflection)}};
  for (const auto& a : attributes) {
    glVertexArrayAttribFormat(g.vao, a.index, a.components, GL_FLOAT, GL_FALSE, GLuint(a.offset));
    glVertexArrayAttribBinding(g.vao, a.index, 0);
    glEnableVertexArrayAttrib(g.vao, a.index);
  }
  return g.vertices.size() / 3;
}

bool SunGlassMap::empty() const {
  return gpu_->vertices.empty();
}

bool SunGlassMap::build(const vec3& sunDirWorld, uint32_t texels) {
  Gpu& g = *gpu_;
  if (g.vertices.empty()) return false;
  if (g.built && g.builtSunDir == sunDirWorld && g.builtTexels == texels) return false;
  if (!g.program) {
    const std::string vertex = std::string(shaders::kGlassPane) + shaders::kSunGlassMapVertex;
    g.program =
        compile_("sun-glass", "",
                 {{GL_VERTEX_SHADER, vertex.c_str()}, {GL_FRAGMENT_SHADER, shaders::kSunGlassMapFragment}});
    g.sunClipFromWorld = glGetUniformLocation(g.program, "uSunClipFromWorld");
    g.sunDir = glGetUniformLocation(g.program, "uSunDirWorld");
  }
  GLint maxTexturePx = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexturePx);
  const uint32_t n = std::clamp<uint32_t>(texels, 16u, uint32_t(std::min(maxTexturePx, 16384)));
  if (g.mapTexels != n) {
    glDeleteTextures(1, &g.map);
    glDeleteFramebuffers(1, &g.fbo);
    glCreateTextures(GL_TEXTURE_2D, 1, &g.map);
    glTextureStorage2D(g.map, 1, GL_RGBA32F, GLsizei(n), GLsizei(n));
    glTextureParameteri(g.map, GL_TEXTURE_MIN_FILTER, GL_NEAREST);  // read with texelFetch
    glTextureParameteri(g.map, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glCreateFramebuffers(1, &g.fbo);
    glNamedFramebufferTexture(g.fbo, GL_COLOR_ATTACHMENT0, g.map, 0);
    if (glCheckNamedFramebufferStatus(g.fbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
      throw std::runtime_error("the OpenGL driver cannot render a " + std::to_string(n) +
                               "² RGBA32F transmittance map");
    }
    g.mapTexels = n;
  }
  // The sun's image plane (as the visibility map's, raster/sun_shadows.cpp) fitted to the glass.
  const vec3 z = glm::normalize(sunDirWorld);
  const vec3 x =
      glm::normalize(std::abs(z.y) < 0.9f ? glm::cross(vec3(0, 1, 0), z) : glm::cross(vec3(1, 0, 0), z));
  const vec3 y = glm::cross(z, x);
  vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (const GlassVertex& v : g.vertices) {
    const vec3 s(glm::dot(v.positionM, x), glm::dot(v.positionM, y), glm::dot(v.positionM, z));
    lo = glm::min(lo, s);
    hi = glm::max(hi, s);
  }
  const float extentM = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.001f;
  const float half = 0.5f * extentM, cx = 0.5f * (lo.x + hi.x), cy = 0.5f * (lo.y + hi.y);
  const float margin = 0.01f * extentM + 1e-3f;
  const mat4 sunFromWorld = glm::inverse(frameTransform(x, y, z, vec3(0.0f)));
  // Looking down −z of the sun frame: depth = −z.
  const mat4 sunClipFromWorld =
      glm::ortho(cx - half, cx + half, cy - half, cy + half, -hi.z - margin, -lo.z + margin) * sunFromWorld;
  // u, v = (clip + 1) / 2; the third row is h = dot(p, sunDir).
  mat4 mapFromWorld = glm::translate(mat4(1.0f), vec3(0.5f, 0.5f, 0.0f)) *
                      glm::scale(mat4(1.0f), vec3(0.5f, 0.5f, 1.0f)) * sunClipFromWorld;
  for (int c = 0; c < 3; ++c) mapFromWorld[c][2] = z[c];
  mapFromWorld[3][2] = 0.0f;
  g.mapFromWorld = mapFromWorld;
  g.texelSizeM = extentM / float(n);

  GLint previousFbo = 0, viewport[4];
  glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousFbo);
  glGetIntegerv(GL_VIEWPORT, viewport);
  const GLfloat clear[4] = {1.0f, 1.0f, 1.0f, kNoPaneHeightM};
  glClearNamedFramebufferfv(g.fbo, GL_COLOR, 0, clear);
  glBindFramebuffer(GL_FRAMEBUFFER, g.fbo);
  glViewport(0, 0, GLsizei(n), GLsizei(n));
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_CULL_FACE);
  glEnable(GL_BLEND);
  glBlendEquationSeparate(GL_FUNC_ADD, GL_MAX);
  glBlendFuncSeparate(GL_ZERO, GL_SRC_COLOR, GL_ONE, GL_ONE);
  glUseProgram(g.program);
  glUniformMatrix4fv(g.sunClipFromWorld, 1, GL_FALSE, &sunClipFromWorld[0][0]);
  glUniform3fv(g.sunDir, 1, &z[0]);
  glBindVertexArray(g.vao);
  glDrawArrays(GL_TRIANGLES, 0, GLsizei(g.vertices.size()));
  glBindVertexArray(0);
  glBlendEquation(GL_FUNC_ADD);
  glBlendFunc(GL_ONE, GL_ZERO);
  glDisable(GL_BLEND);
  glEnable(GL_DEPTH_TEST);
  glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previousFbo));
  glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  g.built = true;
  g.builtSunDir = sunDirWorld;
  g.builtTexels = texels;
  return true;
}

unsigned SunGlassMap::texture() const {
  return gpu_->map;
}

const mat4& SunGlassMap::mapFromWorld() const {
  return gpu_->mapFromWorld;
}

float SunGlassMap::biasM() const {
  return 2.0f * gpu_->texelSizeM;
}

SunGlassCounts SunGlassMap::counts() const {
  const Gpu& g = *gpu_;
  if (!g.built) return {};
  return {uint32_t(g.vertices.size() / 3), g.mapTexels, g.texelSizeM};
}

}  // namespace fly::raster
