#include "raster/sun_shadows.h"

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <unordered_map>
#include <vector>

#include "raster/shaders/shadow_glsl.h"

namespace fly::raster {

namespace {

using glm::uvec2;
using glm::uvec4;

// The commands buffer (raster/shaders/shadow_glsl.h): two DrawElementsIndirectCommand (facing caps, turned
// caps), one DrawArraysIndirectCommand (sides), two counters.
struct Commands {
  uint32_t facingCount = 0, facingInstances = 1, facingFirst = 0, facingBaseVertex = 0, facingBaseInstance = 0;
  uint32_t turnedCount = 0, turnedInstances = 1, turnedFirst = 0, turnedBaseVertex = 0, turnedBaseInstance = 0;
  uint32_t sideCount = 0, sideInstances = 1, sideFirst = 0, sideBaseInstance = 0;
  uint32_t visible = 0, silhouetteEdges = 0;
};
static_assert(sizeof(Commands) == 16 * sizeof(uint32_t));
constexpr GLintptr kFacingOffset = 0, kTurnedOffset = 5 * sizeof(uint32_t), kSidesOffset = 10 * sizeof(uint32_t);

// Caster flags (shadow_glsl.h): bits 0–2 edge directions, bits 3–4 the mesh's closure.
constexpr uint32_t kClosedOut = 1u << 3, kClosedIn = 2u << 3;

template <class T>
void store(GLuint& buffer, const std::vector<T>& data) {
  glDeleteBuffers(1, &buffer);
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(1, data.size()) * sizeof(T)),
                       data.empty() ? nullptr : data.data(), 0);
}

void storeEmpty(GLuint& buffer, size_t bytes, GLbitfield flags = 0) {
  glDeleteBuffers(1, &buffer);
  glCreateBuffers(1, &buffer);
  glNamedBufferStorage(buffer, GLsizeiptr(std::max<size_t>(4, bytes)), nullptr, flags);
}

struct PositionKey {
  uint32_t x, y, z;
  bool operator==(const PositionKey&) const = default;
};
struct PositionHash {
  size_t operator()(const PositionKey& k) const {
    return size_t(k.x) * 73856093u ^ size_t(k.y) * 19349663u ^ size_t(k.z) * 83492791u;
  }
};

PositionKey keyOf(const vec3& p) {
  PositionKey k;
  std::memcpy(&k.x, &p.x, 4);
  std::memcpy(&k.y, &p.y, 4);
  std::memcpy(&k.z, &p.z, 4);
  return k;
}

}  // namespace

struct SunShadows::Gpu {
  GLuint positions = 0;  // the renderer's
  GLuint casters = 0, visible = 0, edgeCounts = 0, caps = 0, edgeVertices = 0, commands = 0, sides = 0;
  GLuint capVao = 0;
  GLuint visibility = 0, visibilityDepth = 0, visibilityFbo = 0;
  uint32_t visibilityTexels = 0;
  GLuint visibilityProgram = 0, markProgram = 0, keepProgram = 0, edgesProgram = 0, capProgram = 0,
         sideProgram = 0;
  uint32_t casterCount = 0, edgeCount = 0;
  Bounds3 boundsM;  // of the casters
  bool built = false;
  vec3 builtSunDir{0.0f};
  SunShadowSettings builtSettings;
  float texelSizeM = 0.0f;

  ~Gpu() {
    const GLuint buffers[] = {casters, visible, edgeCounts, caps, edgeVertices, commands, sides};
    glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
    glDeleteVertexArrays(1, &capVao);
    glDeleteTextures(1, &visibility);
    glDeleteTextures(1, &visibilityDepth);
    glDeleteFramebuffers(1, &visibilityFbo);
    for (GLuint p : {visibilityProgram, markProgram, keepProgram, edgesProgram, capProgram, sideProgram}) {
      glDeleteProgram(p);
    }
  }
};

SunShadows::SunShadows(Compile compile) : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)) {
  glCreateVertexArrays(1, &gpu_->capVao);
}

SunShadows::~SunShadows() = default;

void SunShadows::setGeometry(const rdb::RasterRdb& r, unsigned positions) {
  Gpu& g = *gpu_;
  g.positions = positions;
  g.built = false;
  // Equal positions welded: one canonical vertex per position, so that split vertices (normals, UV seams)
  // share their edges.
  std::vector<uint32_t> canonical(r.positionsM.size());
  {
    std::unordered_map<PositionKey, uint32_t, PositionHash> first;
    first.reserve(r.positionsM.size());
    for (uint32_t v = 0; v < r.positionsM.size(); ++v) {
      canonical[v] = first.try_emplace(keyOf(r.positionsM[v]), v).first->second;
    }
  }
  std::unordered_map<uint64_t, uint32_t> edgeIndex;
  edgeIndex.reserve(r.indices.size());
  std::vector<uvec2> edgeVertices;
  struct Caster {
    uvec4 vertices, edges;
  };
  std::vector<Caster> casters;
  casters.reserve(r.indices.size() / 3);
  g.boundsM = Bounds3{};
  std::vector<uint64_t> uses;  // per mesh: edge index << 1 | direction, to test closure
  for (const rdb::RasterMesh& mesh : r.meshes) {
    const rdb::RasterMaterial& m = r.materials[mesh.material];
    if (maxComponent(m.transmission) > 0.0f || m.alphaMode == rdb::RasterAlphaMode::kBlend) continue;
    const size_t firstCaster = casters.size();
    uses.clear();
    double signedVolume = 0.0;
    const dvec3 origin(r.positionsM[r.indices[mesh.firstIndex]]);
    for (uint32_t i = mesh.firstIndex; i + 2 < mesh.firstIndex + mesh.indexCount; i += 3) {
      Caster c;
      c.vertices = uvec4(r.indices[i], r.indices[i + 1], r.indices[i + 2], 0u);
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t a = canonical[c.vertices[k]], b = canonical[c.vertices[(k + 1) % 3]];
        const uint32_t lo = std::min(a, b), hi = std::max(a, b);
        const auto [it, added] = edgeIndex.try_emplace(uint64_t(lo) << 32 | hi, uint32_t(edgeVertices.size()));
        if (added) edgeVertices.push_back(uvec2(lo, hi));
        c.edges[k] = it->second;
        if (a == lo) c.vertices.w |= 1u << k;
        uses.push_back(uint64_t(it->second) << 1 | (a == lo ? 1u : 0u));
      }
      const dvec3 p0 = dvec3(r.positionsM[c.vertices.x]) - origin, p1 = dvec3(r.positionsM[c.vertices.y]) - origin,
                  p2 = dvec3(r.positionsM[c.vertices.z]) - origin;
      signedVolume += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
      for (int k = 0; k < 3; ++k) g.boundsM.extend(r.positionsM[c.vertices[k]]);
      casters.push_back(c);
    }
    // Closed: every edge used exactly twice, once each way (sorted, the uses pair up as 2e, 2e + 1).
    std::sort(uses.begin(), uses.end());
    bool closed = !uses.empty() && uses.size() % 2 == 0;
    for (size_t u = 0; closed && u < uses.size(); u += 2) {
      closed = (uses[u] >> 1) == (uses[u + 1] >> 1) && (uses[u] & 1u) == 0 && (uses[u + 1] & 1u) == 1 &&
               (u + 2 >= uses.size() || (uses[u + 2] >> 1) != (uses[u] >> 1));
    }
    if (closed && signedVolume != 0.0) {
      const uint32_t closure = signedVolume > 0.0 ? kClosedOut : kClosedIn;
      for (size_t c = firstCaster; c < casters.size(); ++c) casters[c].vertices.w |= closure;
    }
  }
  g.casterCount = uint32_t(casters.size());
  g.edgeCount = uint32_t(edgeVertices.size());
  store(g.casters, casters);
  store(g.edgeVertices, edgeVertices);
  storeEmpty(g.visible, casters.size() * sizeof(uint32_t));
  storeEmpty(g.edgeCounts, edgeVertices.size() * sizeof(int32_t));
  storeEmpty(g.caps, casters.size() * 3 * sizeof(uint32_t));
  // Each kept triangle adds at most 3 to the counts' absolute sum: at most 3 sides per caster.
  storeEmpty(g.sides, casters.size() * 3 * sizeof(uvec2));
  storeEmpty(g.commands, sizeof(Commands), GL_DYNAMIC_STORAGE_BIT);
  glVertexArrayVertexBuffer(g.capVao, 0, positions, 0, sizeof(vec3));
  glVertexArrayAttribFormat(g.capVao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(g.capVao, 0, 0);
  glEnableVertexArrayAttrib(g.capVao, 0);
  glVertexArrayElementBuffer(g.capVao, g.caps);
}

bool SunShadows::build(const vec3& sunDirWorld, const SunShadowSettings& settings) {
  Gpu& g = *gpu_;
  if (g.built && g.builtSunDir == sunDirWorld && g.builtSettings == settings) return false;
  if (!g.keepProgram) {
    const std::string common = shaders::kShadowCommon;
    g.keepProgram = compile_("shadow-keep", common, {{GL_COMPUTE_SHADER, shaders::kShadowKeepCompute}});
    g.edgesProgram = compile_("shadow-edges", common, {{GL_COMPUTE_SHADER, shaders::kShadowEdgesCompute}});
    g.capProgram = compile_("shadow-caps", "", {{GL_VERTEX_SHADER, shaders::kShadowCapVertex},
                                                {GL_FRAGMENT_SHADER, shaders::kShadowVolumeFragment}});
    g.sideProgram = compile_("shadow-sides", common, {{GL_VERTEX_SHADER, shaders::kShadowSideVertex},
                                                      {GL_FRAGMENT_SHADER, shaders::kShadowVolumeFragment}});
  }
  const bool prune = settings.mode == SunShadowMode::kVisibilityMap;
  // The sun's image plane and the orthographic view fitted to the casters' bounds, square texels.
  const vec3 z = glm::normalize(sunDirWorld);
  const vec3 x = glm::normalize(std::abs(z.y) < 0.9f ? glm::cross(vec3(0, 1, 0), z) : glm::cross(vec3(1, 0, 0), z));
  const vec3 y = glm::cross(z, x);
  const vec3 centre = 0.5f * (g.boundsM.min + g.boundsM.max);
  const mat4 sunFromWorld = glm::inverse(frameTransform(x, y, z, centre));
  vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 p((corner & 1) ? g.boundsM.max.x : g.boundsM.min.x, (corner & 2) ? g.boundsM.max.y : g.boundsM.min.y,
                 (corner & 4) ? g.boundsM.max.z : g.boundsM.min.z);
    const vec3 s = vec3(sunFromWorld * vec4(p, 1.0f));
    lo = glm::min(lo, s);
    hi = glm::max(hi, s);
  }
  GLint maxTexturePx = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexturePx);
  const uint32_t texels = std::clamp<uint32_t>(settings.visibilityMapTexels, 16u, uint32_t(std::min(maxTexturePx, 16384)));
  const float extentM = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.001f;
  g.texelSizeM = extentM / float(texels);

  mat4 sunClipFromWorld(1.0f);
  const Commands initial;
  glNamedBufferSubData(g.commands, 0, sizeof initial, &initial);
  const GLint zeroInt = 0;
  glClearNamedBufferData(g.edgeCounts, GL_R32I, GL_RED_INTEGER, GL_INT, &zeroInt);
  const GLuint ssbos[] = {g.positions, g.casters, g.visible, g.edgeCounts, g.caps, g.edgeVertices, g.commands,
                          g.sides};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, GLsizei(std::size(ssbos)), ssbos);

  if (prune) {
    if (!g.visibilityProgram) {
      g.visibilityProgram =
          compile_("shadow-visibility", shaders::kShadowCommon,
                   {{GL_VERTEX_SHADER, shaders::kShadowVisibilityVertex},
                    {GL_FRAGMENT_SHADER, shaders::kShadowVisibilityFragment}});
      g.markProgram = compile_("shadow-mark", "", {{GL_COMPUTE_SHADER, shaders::kShadowMarkCompute}});
    }
    if (g.visibilityTexels != texels) {
      glDeleteTextures(1, &g.visibility);
      glDeleteTextures(1, &g.visibilityDepth);
      glDeleteFramebuffers(1, &g.visibilityFbo);
      glCreateTextures(GL_TEXTURE_2D, 1, &g.visibility);
      glTextureStorage2D(g.visibility, 1, GL_R32UI, GLsizei(texels), GLsizei(texels));
      glCreateTextures(GL_TEXTURE_2D, 1, &g.visibilityDepth);
      glTextureStorage2D(g.visibilityDepth, 1, GL_DEPTH_COMPONENT32F, GLsizei(texels), GLsizei(texels));
      for (GLuint t : {g.visibility, g.visibilityDepth}) {  // read with texelFetch; complete without mipmaps
        glTextureParameteri(t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTextureParameteri(t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
      }
      glCreateFramebuffers(1, &g.visibilityFbo);
      glNamedFramebufferTexture(g.visibilityFbo, GL_COLOR_ATTACHMENT0, g.visibility, 0);
      glNamedFramebufferTexture(g.visibilityFbo, GL_DEPTH_ATTACHMENT, g.visibilityDepth, 0);
      if (glCheckNamedFramebufferStatus(g.visibilityFbo, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
        throw std::runtime_error("the OpenGL driver cannot render a " + std::to_string(texels) + "² R32UI visibility map");
      }
      g.visibilityTexels = texels;
    }
    const uint32_t none = 0xffffffffu;
    glClearNamedBufferData(g.visible, GL_R32UI, GL_RED_INTEGER, GL_UNSIGNED_INT, &zeroInt);
    glClearNamedFramebufferuiv(g.visibilityFbo, GL_COLOR, 0, &none);
    const float farDepth = 1.0f;
    glClearNamedFramebufferfv(g.visibilityFbo, GL_DEPTH, 0, &farDepth);
    const float half = 0.5f * extentM, cx = 0.5f * (lo.x + hi.x), cy = 0.5f * (lo.y + hi.y);
    const float margin = 0.01f * extentM + 1e-3f;
    // Looking down −z of the sun frame (from the sun): depth = −z, from −hi.z to −lo.z.
    sunClipFromWorld =
        glm::ortho(cx - half, cx + half, cy - half, cy + half, -hi.z - margin, -lo.z + margin) * sunFromWorld;
    GLint previousFbo = 0, viewport[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousFbo);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glBindFramebuffer(GL_FRAMEBUFFER, g.visibilityFbo);
    glViewport(0, 0, GLsizei(texels), GLsizei(texels));
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    glUseProgram(g.visibilityProgram);
    glUniformMatrix4fv(glGetUniformLocation(g.visibilityProgram, "uSunClipFromWorld"), 1, GL_FALSE,
                       &sunClipFromWorld[0][0]);
    glBindVertexArray(g.capVao);
    glDrawArrays(GL_TRIANGLES, 0, GLsizei(3 * g.casterCount));
    glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previousFbo));
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT);
    glUseProgram(g.markProgram);
    glBindImageTexture(0, g.visibility, 0, GL_FALSE, 0, GL_READ_ONLY, GL_R32UI);
    glDispatchCompute((texels + 7) / 8, (texels + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
    glBindTextureUnit(0, g.visibility);
    glBindTextureUnit(1, g.visibilityDepth);
  }

  const GLuint capCapacity = 3 * g.casterCount;
  glUseProgram(g.keepProgram);
  auto loc = [&](const char* n) { return glGetUniformLocation(g.keepProgram, n); };
  glUniform1ui(loc("uCasterCount"), g.casterCount);
  glUniform1ui(loc("uCapCapacity"), capCapacity);
  glUniform3fv(loc("uSunDirWorld"), 1, &z[0]);
  glUniform3fv(loc("uSunXWorld"), 1, &x[0]);
  glUniform3fv(loc("uSunYWorld"), 1, &y[0]);
  // t/√2, widened by 0.1 % so that rounding in the inradius never drops a triangle on the boundary (keeping
  // more is always safe).
  glUniform1f(loc("uSmallInradiusM"), g.texelSizeM / std::sqrt(2.0f) * 1.001f);
  glUniform1i(loc("uPrune"), prune ? 1 : 0);
  glUniformMatrix4fv(loc("uSunClipFromWorld"), 1, GL_FALSE, &sunClipFromWorld[0][0]);
  glUniform1i(loc("uMapTexels"), GLint(texels));
  glDispatchCompute((g.casterCount + 63) / 64, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  glUseProgram(g.edgesProgram);
  glUniform1ui(glGetUniformLocation(g.edgesProgram, "uEdgeCount"), g.edgeCount);
  glUniform1ui(glGetUniformLocation(g.edgesProgram, "uCapCapacity"), capCapacity);
  glDispatchCompute(std::max(1u, (g.edgeCount + 63) / 64), 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT |
                  GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  g.built = true;
  g.builtSunDir = sunDirWorld;
  g.builtSettings = settings;
  return true;
}

void SunShadows::drawStencil(const mat4& clipFromWorld) {
  glEnable(GL_DEPTH_CLAMP);
  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDepthFunc(GL_LESS);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xff);
  glStencilFunc(GL_ALWAYS, 0, 0xff);
  glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
  glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
  drawVolumes(clipFromWorld);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
  glDisable(GL_DEPTH_CLAMP);
}

void SunShadows::drawVolumes(const mat4& clipFromWorld) {
  Gpu& g = *gpu_;
  const GLuint ssbos[] = {g.positions, g.casters};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 2, ssbos);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, g.sides);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.commands);
  glBindVertexArray(g.capVao);
  glUseProgram(g.capProgram);
  glUniformMatrix4fv(glGetUniformLocation(g.capProgram, "uClipFromWorld"), 1, GL_FALSE, &clipFromWorld[0][0]);
  glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(kFacingOffset));
  // The turned caps keep the scene's vertex order (and so its exact depths); their other winding faces the sun.
  glFrontFace(GL_CW);
  glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(kTurnedOffset));
  glFrontFace(GL_CCW);
  glUseProgram(g.sideProgram);
  glUniformMatrix4fv(glGetUniformLocation(g.sideProgram, "uClipFromWorld"), 1, GL_FALSE, &clipFromWorld[0][0]);
  glUniform3fv(glGetUniformLocation(g.sideProgram, "uSunDirWorld"), 1, &g.builtSunDir[0]);
  glDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(kSidesOffset));
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, 0);
}

uint64_t SunShadows::measureFill(const mat4& clipFromWorld) {
  GLuint query = 0;
  glCreateQueries(GL_SAMPLES_PASSED, 1, &query);
  glDisable(GL_DEPTH_TEST);
  glDisable(GL_STENCIL_TEST);
  glEnable(GL_DEPTH_CLAMP);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glBeginQuery(GL_SAMPLES_PASSED, query);
  drawVolumes(clipFromWorld);
  glEndQuery(GL_SAMPLES_PASSED);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDisable(GL_DEPTH_CLAMP);
  glEnable(GL_DEPTH_TEST);
  GLuint64 samples = 0;
  glGetQueryObjectui64v(query, GL_QUERY_RESULT, &samples);
  glDeleteQueries(1, &query);
  return samples;
}

SunShadowCounts SunShadows::counts() const {
  const Gpu& g = *gpu_;
  SunShadowCounts c;
  c.casterTriangles = g.casterCount;
  c.texelSizeM = g.texelSizeM;
  if (!g.built) return c;
  Commands cmd;
  glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
  glGetNamedBufferSubData(g.commands, 0, sizeof cmd, &cmd);
  c.visibleTriangles = cmd.visible;
  c.keptTriangles = (cmd.facingCount + cmd.turnedCount) / 3;
  c.silhouetteEdges = cmd.silhouetteEdges;
  c.sideTriangles = cmd.sideCount / 3;
  return c;
}

}  // namespace fly::raster
