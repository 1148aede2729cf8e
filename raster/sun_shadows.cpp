#include "raster/sun_shadows.h"

#include <epoxy/gl.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
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
  uint32_t facingCount = 0, facingInstances = 1, facingFirst = 0, facingBaseVertex = 0,
           facingBaseInstance = 0;
  uint32_t turnedCount = 0, turnedInstances = 1, turnedFirst = 0, turnedBaseVertex = 0,
           turnedBaseInstance = 0;
  uint32_t sideCount = 0, sideInstances = 1, sideFirst = 0, sideBaseInstance = 0;
  uint32_t visible = 0, silhouetteEdges = 0;
  // Per frame (drawStencil): 1 when the camera's near-plane rectangle may lie in a volume; then the draws it
  // issues: facing caps, turned caps and sides for z-fail, sides for z-pass — copies of the above with the
  // counts of the method not taken set to 0 (shadow_glsl.h, kShadowSelectCompute).
  uint32_t nearInVolume = 0;
  uint32_t selected[18] = {};
  uint32_t keptByDepth = 0;  // triangles the visibility maps do not show, kept by the depth test
};
static_assert(sizeof(Commands) == 36 * sizeof(uint32_t));
// Visibility map levels: the whole map, then twice the square around what the previous level left undecided.
constexpr int kMapLevels = 3;

constexpr GLintptr kFacingOffset = 0, kTurnedOffset = 5 * sizeof(uint32_t),
                   kSidesOffset = 10 * sizeof(uint32_t);
constexpr GLintptr kSelectedFacingOffset = 17 * sizeof(uint32_t), kSelectedTurnedOffset = 22 * sizeof(uint32_t),
                   kSelectedZFailSidesOffset = 27 * sizeof(uint32_t),
                   kSelectedZPassSidesOffset = 31 * sizeof(uint32_t);

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

bool castsSunShadows(const rdb::RasterMaterial& m) {
  return !(maxComponent(m.transmission) > 0.0f) && m.alphaMode != rdb::RasterAlphaMode::kBlend;
}

struct SunShadows::Gpu {
  GLuint positions = 0;  // the renderer's
  GLuint casters = 0, state = 0, edgeCounts = 0, caps = 0, edgeVertices = 0, commands = 0, sides = 0,
         levels = 0;
  GLuint capVao = 0;     // the caps: the scene's positions, the caps' indices
  GLuint pulledVao = 0;  // draws that pull their vertices from buffers (no attributes)
  GLuint casterVao = 0;  // the visibility map: the scene's positions, the casters' vertex indices in order
  GLuint casterIndices = 0;
  GLuint visibility = 0, visibilityDepth = 0, visibilityFbo = 0;
  GLuint depthTestFbo = 0;  // no attachments, the map's size: the depth test's fragments

  uint32_t visibilityTexels = 0;
  GLuint resetProgram = 0, visibilityProgram = 0, markProgram = 0, classifyProgram = 0, depthTestProgram = 0,
         shellsProgram = 0, keepProgram = 0,
         edgesProgram = 0, capProgram = 0, sideProgram = 0, nearProgram = 0, selectProgram = 0;
  uint32_t casterCount = 0, edgeCount = 0, shellCount = 0;
  // Cut-out (alpha MASK) casters: seen through their holes, their caps matter to z-pass too, so a scene with
  // them always takes z-fail.
  bool maskCasters = false;
  // Some caster lies in an open shell: the classic method draws the visibility map for such triangles that
  // face away from the sun.
  bool openShells = false;
  GLuint shellKept = 0;  // per shell: 1 when one of its triangles is kept
  GLuint depthTests = 0;  // the depth test's indirect draw and casters (shadow_glsl.h, binding 10)
  GLint capClipFromWorld = -1, sideClipFromWorld = -1, sideSunDir = -1;  // drawVolumes' uniforms
  Bounds3 boundsM;                                                       // of the casters
  bool built = false;
  bool profiling = false;
  std::vector<std::pair<std::string, GLuint>> stamps;  // GL_TIMESTAMP queries of the last build, in order
  void stamp(std::string name) {
    if (!profiling) return;
    GLuint q = 0;
    glCreateQueries(GL_TIMESTAMP, 1, &q);
    glQueryCounter(q, GL_TIMESTAMP);
    stamps.emplace_back(std::move(name), q);
  }
  void clearStamps() {
    for (auto& [name, q] : stamps) glDeleteQueries(1, &q);
    stamps.clear();
  }
  vec3 builtSunDir{0.0f};
  SunShadowSettings builtSettings;
  float texelSizeM = 0.0f;

  ~Gpu() {
    clearStamps();
    const GLuint buffers[] = {casters,  state, edgeCounts, caps,     edgeVertices,
                              commands, sides, levels,     shellKept, depthTests};
    glDeleteBuffers(GLsizei(std::size(buffers)), buffers);
    glDeleteVertexArrays(1, &capVao);
    glDeleteVertexArrays(1, &pulledVao);
    glDeleteVertexArrays(1, &casterVao);
    glDeleteBuffers(1, &casterIndices);
    glDeleteTextures(1, &visibility);
    glDeleteTextures(1, &visibilityDepth);
    glDeleteFramebuffers(1, &visibilityFbo);
    glDeleteFramebuffers(1, &depthTestFbo);
    for (GLuint p : {resetProgram, visibilityProgram, markProgram, classifyProgram, depthTestProgram, shellsProgram,
                     keepProgram, edgesProgram, capProgram, sideProgram, nearProgram, selectProgram}) {
      glDeleteProgram(p);
    }
  }
};

SunShadows::SunShadows(Compile compile) : gpu_(std::make_unique<Gpu>()), compile_(std::move(compile)) {
  glCreateVertexArrays(1, &gpu_->capVao);
  glCreateVertexArrays(1, &gpu_->pulledVao);
  glCreateVertexArrays(1, &gpu_->casterVao);
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
  g.maskCasters = false;
  for (const rdb::RasterMesh& mesh : r.meshes) {
    if (!castsSunShadows(r.materials[mesh.material])) continue;
    g.maskCasters |= r.materials[mesh.material].alphaMode == rdb::RasterAlphaMode::kMask;
    for (uint32_t i = mesh.firstIndex; i + 2 < mesh.firstIndex + mesh.indexCount; i += 3) {
      Caster c;
      c.vertices = uvec4(r.indices[i], r.indices[i + 1], r.indices[i + 2], 0u);
      for (uint32_t k = 0; k < 3; ++k) {
        const uint32_t a = canonical[c.vertices[k]], b = canonical[c.vertices[(k + 1) % 3]];
        const uint32_t lo = std::min(a, b), hi = std::max(a, b);
        const auto [it, added] =
            edgeIndex.try_emplace(uint64_t(lo) << 32 | hi, uint32_t(edgeVertices.size()));
        if (added) edgeVertices.push_back(uvec2(lo, hi));
        c.edges[k] = it->second;
        if (a == lo) c.vertices.w |= 1u << k;
      }
      for (int k = 0; k < 3; ++k) g.boundsM.extend(r.positionsM[c.vertices[k]]);
      casters.push_back(c);
    }
  }
  // Shells: the triangles connected through shared (welded) edges (union–find). A shell is closed when each
  // of its edges is used exactly twice, once each way; it faces out when its signed volume is positive.
  std::vector<uint32_t> parent(casters.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  auto root = [&](uint32_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  std::vector<uint32_t> firstUser(edgeVertices.size(), ~0u);
  std::vector<uint32_t> forward(edgeVertices.size(), 0), backward(edgeVertices.size(), 0);
  for (uint32_t i = 0; i < casters.size(); ++i) {
    for (uint32_t k = 0; k < 3; ++k) {
      const uint32_t e = casters[i].edges[k];
      ((casters[i].vertices.w >> k) & 1u ? forward : backward)[e] += 1;
      if (firstUser[e] == ~0u) {
        firstUser[e] = i;
      } else {
        parent[root(i)] = root(firstUser[e]);
      }
    }
  }
  std::vector<uint32_t> shellOf(casters.size()), shellIndex(casters.size(), ~0u);
  uint32_t shells = 0;
  for (uint32_t i = 0; i < casters.size(); ++i) {
    uint32_t& s = shellIndex[root(i)];
    if (s == ~0u) s = shells++;
    shellOf[i] = s;
  }
  std::vector<char> closed(shells, 1);
  std::vector<double> signedVolume(shells, 0.0);
  const dvec3 origin = dvec3(0.5f * (g.boundsM.min + g.boundsM.max));
  for (uint32_t i = 0; i < casters.size(); ++i) {
    const Caster& c = casters[i];
    for (uint32_t k = 0; k < 3; ++k) {
      if (forward[c.edges[k]] != 1 || backward[c.edges[k]] != 1) closed[shellOf[i]] = 0;
    }
    const dvec3 p0 = dvec3(r.positionsM[c.vertices.x]) - origin,
                p1 = dvec3(r.positionsM[c.vertices.y]) - origin,
                p2 = dvec3(r.positionsM[c.vertices.z]) - origin;
    signedVolume[shellOf[i]] += glm::dot(p0, glm::cross(p1, p2)) / 6.0;
  }
  g.openShells = false;
  for (uint32_t i = 0; i < casters.size(); ++i) {
    const uint32_t s = shellOf[i];
    casters[i].edges.w = s;
    if (closed[s] && signedVolume[s] != 0.0) {
      casters[i].vertices.w |= signedVolume[s] > 0.0 ? kClosedOut : kClosedIn;
    } else {
      g.openShells = true;
    }
  }
  g.shellCount = shells;
  storeEmpty(g.shellKept, size_t(shells) * sizeof(uint32_t));
  storeEmpty(g.depthTests, (4 + casters.size()) * sizeof(uint32_t), GL_DYNAMIC_STORAGE_BIT);
  g.casterCount = uint32_t(casters.size());
  g.edgeCount = uint32_t(edgeVertices.size());
  store(g.casters, casters);
  store(g.edgeVertices, edgeVertices);
  storeEmpty(g.state, casters.size() * sizeof(uint32_t));
  storeEmpty(g.levels, kMapLevels * sizeof(glm::ivec4), GL_DYNAMIC_STORAGE_BIT);
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
  std::vector<uint32_t> casterIndices;
  casterIndices.reserve(3 * casters.size());
  for (const Caster& c : casters) casterIndices.insert(casterIndices.end(), {c.vertices.x, c.vertices.y, c.vertices.z});
  store(g.casterIndices, casterIndices);
  glVertexArrayVertexBuffer(g.casterVao, 0, positions, 0, sizeof(vec3));
  glVertexArrayAttribFormat(g.casterVao, 0, 3, GL_FLOAT, GL_FALSE, 0);
  glVertexArrayAttribBinding(g.casterVao, 0, 0);
  glEnableVertexArrayAttrib(g.casterVao, 0);
  glVertexArrayElementBuffer(g.casterVao, g.casterIndices);
}

bool SunShadows::build(const vec3& sunDirWorld, const SunShadowSettings& settings) {
  Gpu& g = *gpu_;
  if (g.built && g.builtSunDir == sunDirWorld && g.builtSettings == settings) return false;
  if (!g.keepProgram) {
    const std::string common = shaders::kShadowCommon;
    g.resetProgram = compile_("shadow-reset", "", {{GL_COMPUTE_SHADER, shaders::kShadowResetCompute}});
    g.keepProgram = compile_("shadow-keep", common, {{GL_COMPUTE_SHADER, shaders::kShadowKeepCompute}});
    g.edgesProgram = compile_("shadow-edges", common, {{GL_COMPUTE_SHADER, shaders::kShadowEdgesCompute}});
    g.capProgram = compile_("shadow-caps", "",
                            {{GL_VERTEX_SHADER, shaders::kShadowCapVertex},
                             {GL_FRAGMENT_SHADER, shaders::kShadowVolumeFragment}});
    g.sideProgram = compile_("shadow-sides", common,
                             {{GL_VERTEX_SHADER, shaders::kShadowSideVertex},
                              {GL_FRAGMENT_SHADER, shaders::kShadowVolumeFragment}});
    g.nearProgram = compile_("shadow-near", common, {{GL_COMPUTE_SHADER, shaders::kShadowNearCompute}});
    g.selectProgram = compile_("shadow-select", common, {{GL_COMPUTE_SHADER, shaders::kShadowSelectCompute}});
    g.capClipFromWorld = glGetUniformLocation(g.capProgram, "uClipFromWorld");
    g.sideClipFromWorld = glGetUniformLocation(g.sideProgram, "uClipFromWorld");
    g.sideSunDir = glGetUniformLocation(g.sideProgram, "uSunDirWorld");
  }
  g.clearStamps();
  g.stamp("start");
  g.built = true;
  g.builtSunDir = sunDirWorld;
  g.builtSettings = settings;
  const Commands initial;
  glNamedBufferSubData(g.commands, 0, sizeof initial, &initial);
  if (g.casterCount == 0) return true;  // nothing casts (glass, blended surfaces only): no volumes
  const bool prune = settings.mode == SunShadowMode::kVisibilityMap;
  // The classic method keeps every triangle that faces the sun; of those that face away, an open shell's need
  // the sun to reach their backs, which the visibility map decides (shadow_glsl.h, flyKeep).
  const bool mapped = prune || g.openShells;
  // The sun's image plane and the orthographic view fitted to the casters' bounds, square texels.
  const vec3 z = glm::normalize(sunDirWorld);
  const vec3 x =
      glm::normalize(std::abs(z.y) < 0.9f ? glm::cross(vec3(0, 1, 0), z) : glm::cross(vec3(1, 0, 0), z));
  const vec3 y = glm::cross(z, x);
  const vec3 centre = 0.5f * (g.boundsM.min + g.boundsM.max);
  const mat4 sunFromWorld = glm::inverse(frameTransform(x, y, z, centre));
  vec3 lo(std::numeric_limits<float>::infinity()), hi(-std::numeric_limits<float>::infinity());
  for (int corner = 0; corner < 8; ++corner) {
    const vec3 p((corner & 1) ? g.boundsM.max.x : g.boundsM.min.x,
                 (corner & 2) ? g.boundsM.max.y : g.boundsM.min.y,
                 (corner & 4) ? g.boundsM.max.z : g.boundsM.min.z);
    const vec3 s = vec3(sunFromWorld * vec4(p, 1.0f));
    lo = glm::min(lo, s);
    hi = glm::max(hi, s);
  }
  GLint maxTexturePx = 0;
  glGetIntegerv(GL_MAX_TEXTURE_SIZE, &maxTexturePx);
  const uint32_t texels =
      std::clamp<uint32_t>(settings.visibilityMapTexels, 16u, uint32_t(std::min(maxTexturePx, 16384)));
  const float extentM = std::max({hi.x - lo.x, hi.y - lo.y, 1e-6f}) * 1.001f;
  g.texelSizeM = extentM / float(texels);

  const GLuint ssbos[] = {g.positions,    g.casters,  g.state, g.edgeCounts, g.caps,
                          g.edgeVertices, g.commands, g.sides, g.levels,     g.shellKept};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, GLsizei(std::size(ssbos)), ssbos);
  glUseProgram(g.resetProgram);
  glUniform1ui(glGetUniformLocation(g.resetProgram, "uCasterCount"), g.casterCount);
  glUniform1ui(glGetUniformLocation(g.resetProgram, "uEdgeCount"), g.edgeCount);
  glUniform1ui(glGetUniformLocation(g.resetProgram, "uShellCount"), g.shellCount);
  glDispatchCompute((std::max({g.casterCount, g.edgeCount, g.shellCount}) + 63) / 64, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);

  if (mapped) {
    if (!g.visibilityProgram) {
      const std::string common = shaders::kShadowCommon;
      g.visibilityProgram = compile_("shadow-visibility", common,
                                     {{GL_VERTEX_SHADER, shaders::kShadowVisibilityVertex},
                                      {GL_FRAGMENT_SHADER, shaders::kShadowVisibilityFragment}});
      g.markProgram = compile_("shadow-mark", common, {{GL_COMPUTE_SHADER, shaders::kShadowMarkCompute}});
      g.classifyProgram =
          compile_("shadow-classify", common, {{GL_COMPUTE_SHADER, shaders::kShadowClassifyCompute}});
      g.depthTestProgram = compile_("shadow-depth-test", common,
                                    {{GL_VERTEX_SHADER, shaders::kShadowDepthTestVertex},
                                     {GL_FRAGMENT_SHADER, shaders::kShadowDepthTestFragment}});
      g.shellsProgram =
          compile_("shadow-shells", common, {{GL_COMPUTE_SHADER, shaders::kShadowShellsCompute}});
    }
    if (g.visibilityTexels != texels) {
      glDeleteTextures(1, &g.visibility);
      glDeleteTextures(1, &g.visibilityDepth);
      glDeleteFramebuffers(1, &g.visibilityFbo);
      glDeleteFramebuffers(1, &g.depthTestFbo);
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
        throw std::runtime_error("the OpenGL driver cannot render a " + std::to_string(texels) +
                                 "² R32UI visibility map");
      }
      glCreateFramebuffers(1, &g.depthTestFbo);
      glNamedFramebufferParameteri(g.depthTestFbo, GL_FRAMEBUFFER_DEFAULT_WIDTH, GLint(texels));
      glNamedFramebufferParameteri(g.depthTestFbo, GL_FRAMEBUFFER_DEFAULT_HEIGHT, GLint(texels));
      g.visibilityTexels = texels;
    }
    const float half = 0.5f * extentM, cx = 0.5f * (lo.x + hi.x), cy = 0.5f * (lo.y + hi.y);
    const float margin = 0.01f * extentM + 1e-3f;
    // Looking down −z of the sun frame (from the sun): depth = −z, from −hi.z to −lo.z.
    const mat4 sunClipFromWorld =
        glm::ortho(cx - half, cx + half, cy - half, cy + half, -hi.z - margin, -lo.z + margin) * sunFromWorld;
    // Level 0 is the whole map; the others are empty until a level widens them.
    std::array<glm::ivec4, kMapLevels> regions;
    regions.fill(glm::ivec4(std::numeric_limits<int>::max(), std::numeric_limits<int>::max(),
                            std::numeric_limits<int>::min(), std::numeric_limits<int>::min()));
    regions[0] = glm::ivec4(0, 0, int(texels) * 256, int(texels) * 256);
    glNamedBufferSubData(g.levels, 0, sizeof regions, regions.data());
    glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 10, g.depthTests);
    g.stamp("setup");
    for (GLuint program : {g.visibilityProgram, g.markProgram, g.classifyProgram, g.depthTestProgram}) {
      glProgramUniformMatrix4fv(program, glGetUniformLocation(program, "uSunClipFromWorld"), 1, GL_FALSE,
                                &sunClipFromWorld[0][0]);
      glProgramUniform1i(program, glGetUniformLocation(program, "uMapTexels"), GLint(texels));
    }
    auto classifyLoc = [&](const char* n) { return glGetUniformLocation(g.classifyProgram, n); };
    glProgramUniform1ui(g.classifyProgram, classifyLoc("uCasterCount"), g.casterCount);
    glProgramUniform3fv(g.classifyProgram, classifyLoc("uSunDirWorld"), 1, &z[0]);
    glProgramUniform3fv(g.classifyProgram, classifyLoc("uSunXWorld"), 1, &x[0]);
    glProgramUniform3fv(g.classifyProgram, classifyLoc("uSunYWorld"), 1, &y[0]);
    glProgramUniform1f(g.classifyProgram, classifyLoc("uBaseTexelM"), g.texelSizeM);
    GLint previousFbo = 0, viewport[4];
    glGetIntegerv(GL_DRAW_FRAMEBUFFER_BINDING, &previousFbo);
    glGetIntegerv(GL_VIEWPORT, viewport);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LESS);
    glDepthMask(GL_TRUE);
    glDisable(GL_CULL_FACE);
    const float farDepth = 1.0f;
    // Classifies what the level leaves undecided, then depth-tests what it sends there (depth writes off).
    auto classifyAndTest = [&](const std::string& at, bool last) {
      const uint32_t noDraw[4] = {0, 1, 0, 0};
      glNamedBufferSubData(g.depthTests, 0, sizeof noDraw, noDraw);
      glUseProgram(g.classifyProgram);
      glUniform1i(classifyLoc("uLastLevel"), last ? 1 : 0);
      glBindTextureUnit(0, g.visibility);
      glBindTextureUnit(1, g.visibilityDepth);
      glDispatchCompute((g.casterCount + 63) / 64, 1, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT | GL_COMMAND_BARRIER_BIT);
      g.stamp("classify" + at);
      glDisable(GL_DEPTH_TEST);
      glBindFramebuffer(GL_FRAMEBUFFER, g.depthTestFbo);
      glBindVertexArray(g.pulledVao);
      glUseProgram(g.depthTestProgram);
      glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.depthTests);
      glDrawArraysIndirect(GL_TRIANGLES, nullptr);
      glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previousFbo));
      glEnable(GL_DEPTH_TEST);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      g.stamp("depth test" + at);
    };
    float side = float(texels);  // the level's square, in level 0's texels
    uint32_t levelTexels = texels;  // the level's texels per side: its square in the map's corner
    glEnable(GL_SCISSOR_TEST);
    for (GLint level = 0; level < kMapLevels; ++level) {
      for (GLuint program : {g.visibilityProgram, g.markProgram, g.classifyProgram, g.depthTestProgram}) {
        glProgramUniform1i(program, glGetUniformLocation(program, "uLevel"), level);
        glProgramUniform1i(program, glGetUniformLocation(program, "uLevelTexels"), GLint(levelTexels));
      }
      glViewport(0, 0, GLsizei(levelTexels), GLsizei(levelTexels));
      glScissor(0, 0, GLsizei(levelTexels), GLsizei(levelTexels));
      const std::string at = " " + std::to_string(level);
      // The map's textures must not stay bound for sampling while they are drawn into.
      glBindTextureUnit(0, 0);
      glBindTextureUnit(1, 0);
      glClearNamedFramebufferfv(g.visibilityFbo, GL_DEPTH, 0, &farDepth);  // the indices need no clear
      g.stamp("clear" + at);
      glBindFramebuffer(GL_FRAMEBUFFER, g.visibilityFbo);
      glUseProgram(g.visibilityProgram);
      glBindVertexArray(g.casterVao);
      glDrawElements(GL_TRIANGLES, GLsizei(3 * g.casterCount), GL_UNSIGNED_INT, nullptr);
      glBindFramebuffer(GL_FRAMEBUFFER, GLuint(previousFbo));
      g.stamp("map" + at);
      glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
      glUseProgram(g.markProgram);
      glBindTextureUnit(0, g.visibility);
      glBindTextureUnit(1, g.visibilityDepth);
      glDispatchCompute((levelTexels + 7) / 8, (levelTexels + 7) / 8, 1);
      glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
      g.stamp("mark" + at);
      const bool last = level + 1 == kMapLevels;
      classifyAndTest(at, last);
      if (last) break;
      // The next level's square (waiting for the GPU: once per rebuild and level), drawn with texels half as
      // large as this level's, so in fewer texels per side where the square is smaller. A level pays only where
      // it refines: when its square is not at most half this one's side (it would need more texels than
      // level 0), what is undecided takes the depth test on this level's map instead.
      glm::ivec4 next;
      glMemoryBarrier(GL_BUFFER_UPDATE_BARRIER_BIT);
      glGetNamedBufferSubData(g.levels, GLintptr((level + 1) * sizeof next), sizeof next, &next);
      if (next.x > next.z || next.y > next.w) break;  // nothing undecided
      const float nextSide = float(std::max(next.z - next.x, next.w - next.y)) / 256.0f *
                                 (1.0f + 8.0f / float(texels)) + 1.0f / 64.0f;
      if (nextSide > 0.5f * side) {
        classifyAndTest(at + " (final)", true);
        break;
      }
      levelTexels = std::clamp(uint32_t(std::ceil(2.0f * float(levelTexels) * nextSide / side)), 16u, texels);
      side = nextSide;
    }
    glDisable(GL_SCISSOR_TEST);
    glViewport(viewport[0], viewport[1], viewport[2], viewport[3]);
    glUseProgram(g.shellsProgram);
    glUniform1ui(glGetUniformLocation(g.shellsProgram, "uCasterCount"), g.casterCount);
    glDispatchCompute((g.casterCount + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
    g.stamp("shells");
  }

  const GLuint capCapacity = 3 * g.casterCount;
  glUseProgram(g.keepProgram);
  auto loc = [&](const char* n) { return glGetUniformLocation(g.keepProgram, n); };
  glUniform1ui(loc("uCasterCount"), g.casterCount);
  glUniform1ui(loc("uCapCapacity"), capCapacity);
  glUniform3fv(loc("uSunDirWorld"), 1, &z[0]);
  glUniform1i(loc("uPrune"), prune ? 1 : 0);
  glUniform1i(loc("uMapped"), mapped ? 1 : 0);
  glDispatchCompute((g.casterCount + 63) / 64, 1, 1);
  glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  g.stamp("keep");
  glUseProgram(g.edgesProgram);
  glUniform1ui(glGetUniformLocation(g.edgesProgram, "uEdgeCount"), g.edgeCount);
  glUniform1ui(glGetUniformLocation(g.edgesProgram, "uCapCapacity"), capCapacity);
  glDispatchCompute(std::max(1u, (g.edgeCount + 63) / 64), 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT | GL_ELEMENT_ARRAY_BARRIER_BIT |
                  GL_VERTEX_ATTRIB_ARRAY_BARRIER_BIT | GL_BUFFER_UPDATE_BARRIER_BIT);
  g.stamp("edges");
  return true;
}

void SunShadows::setProfiling(bool on) { gpu_->profiling = on; }

std::vector<std::pair<std::string, double>> SunShadows::buildStagesMs() const {
  std::vector<std::pair<std::string, double>> stages;
  GLuint64 previous = 0;
  for (const auto& [name, q] : gpu_->stamps) {
    GLuint64 ns = 0;
    glGetQueryObjectui64v(q, GL_QUERY_RESULT, &ns);
    if (!stages.empty() || previous != 0) stages.emplace_back(name, 1e-6 * double(ns - previous));
    previous = ns;
  }
  return stages;
}

void SunShadows::drawStencil(const mat4& clipFromWorld) {
  Gpu& g = *gpu_;
  // z-pass (the volumes' faces in front of the surface, no caps) is right and cheaper whenever the camera's
  // near-plane rectangle lies in no volume; otherwise z-fail with caps. The GPU decides per frame, from a
  // conservative test of the rectangle (enlarged by 2 %) against every kept triangle's prism, and writes the
  // draws of the method taken; the CPU issues both with their stencil operations, one of them empty.
  const mat4 worldFromClip = glm::inverse(clipFromWorld);
  vec3 corners[4];
  vec3 centre(0.0f);
  bool finite = true;
  for (int k = 0; k < 4; ++k) {
    const vec4 p = worldFromClip * vec4(k & 1 ? 1.0f : -1.0f, k & 2 ? 1.0f : -1.0f, -1.0f, 1.0f);
    corners[k] = vec3(p) / p.w;
    finite = finite && isFinite(corners[k]);
    centre += 0.25f * corners[k];
  }
  for (vec3& c : corners) c = centre + 1.02f * (c - centre);
  const GLuint ssbos[] = {g.positions, g.casters};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 2, ssbos);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 4, g.caps);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 6, g.commands);
  const bool forceZFail = g.maskCasters || !finite;
  if (!forceZFail && g.casterCount > 0) {
    glUseProgram(g.nearProgram);
    glUniform1ui(glGetUniformLocation(g.nearProgram, "uCasterCount"), g.casterCount);
    glUniform1ui(glGetUniformLocation(g.nearProgram, "uCapCapacity"), 3 * g.casterCount);
    glUniform3fv(glGetUniformLocation(g.nearProgram, "uSunDirWorld"), 1, &g.builtSunDir[0]);
    glUniform3fv(glGetUniformLocation(g.nearProgram, "uNearCornersM"), 4, &corners[0][0]);
    glDispatchCompute((g.casterCount + 63) / 64, 1, 1);
    glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT);
  }
  glUseProgram(g.selectProgram);
  glUniform1i(glGetUniformLocation(g.selectProgram, "uForceZFail"), forceZFail ? 1 : 0);
  glDispatchCompute(1, 1, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT | GL_SHADER_STORAGE_BARRIER_BIT);

  glDepthMask(GL_FALSE);
  glColorMask(GL_FALSE, GL_FALSE, GL_FALSE, GL_FALSE);
  glDepthFunc(GL_LESS);
  glEnable(GL_STENCIL_TEST);
  glStencilMask(0xff);
  glStencilFunc(GL_ALWAYS, 0, 0xff);
  // z-fail: faces behind the surface, back +1, front −1.
  glStencilOpSeparate(GL_BACK, GL_KEEP, GL_INCR_WRAP, GL_KEEP);
  glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_DECR_WRAP, GL_KEEP);
  drawVolumes(clipFromWorld, kSelectedFacingOffset, kSelectedTurnedOffset, kSelectedZFailSidesOffset);
  // z-pass: faces in front of the surface, front +1 (entering a volume), back −1.
  glStencilOpSeparate(GL_FRONT, GL_KEEP, GL_KEEP, GL_INCR_WRAP);
  glStencilOpSeparate(GL_BACK, GL_KEEP, GL_KEEP, GL_DECR_WRAP);
  // Not depth-clamped: with the clamp, faces between the eye and the near plane would count too, and z-pass
  // would need the eye, not the near plane, outside every volume; their parts beyond the scene never count.
  drawSides(clipFromWorld, kSelectedZPassSidesOffset, false);
  glColorMask(GL_TRUE, GL_TRUE, GL_TRUE, GL_TRUE);
  glDepthMask(GL_TRUE);
}

void SunShadows::drawVolumes(const mat4& clipFromWorld, intptr_t facingOffset, intptr_t turnedOffset,
                             intptr_t sidesOffset) {
  Gpu& g = *gpu_;
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.commands);
  glBindVertexArray(g.capVao);
  glUseProgram(g.capProgram);
  glUniformMatrix4fv(g.capClipFromWorld, 1, GL_FALSE, &clipFromWorld[0][0]);
  // The caps are drawn as the scene was (clipped at the near plane, no depth clamp: a GPU may take another
  // depth path with the clamp on) and pushed back by a few depth steps (polygon offset), so that a lit
  // surface's own cap counts as behind it even where a driver's invariant positions differ in the last bits
  // (seen on NVIDIA's): only surfaces within that offset behind a caster's front face, in contact with it,
  // could lose their shadow.
  glEnable(GL_POLYGON_OFFSET_FILL);
  glPolygonOffset(1.0f, 4.0f);
  glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(facingOffset));
  // The turned caps keep the scene's vertex order (and so its exact depths); their other winding faces the
  // sun.
  glFrontFace(GL_CW);
  glDrawElementsIndirect(GL_TRIANGLES, GL_UNSIGNED_INT, reinterpret_cast<const void*>(turnedOffset));
  glFrontFace(GL_CCW);
  glDisable(GL_POLYGON_OFFSET_FILL);
  drawSides(clipFromWorld, sidesOffset, true);
}

void SunShadows::drawSides(const mat4& clipFromWorld, intptr_t sidesOffset, bool depthClamp) {
  Gpu& g = *gpu_;
  const GLuint ssbos[] = {g.positions, g.casters};
  glBindBuffersBase(GL_SHADER_STORAGE_BUFFER, 0, 2, ssbos);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, 7, g.sides);
  glBindBuffer(GL_DRAW_INDIRECT_BUFFER, g.commands);
  glBindVertexArray(g.pulledVao);
  glUseProgram(g.sideProgram);
  glUniformMatrix4fv(g.sideClipFromWorld, 1, GL_FALSE, &clipFromWorld[0][0]);
  glUniform3fv(g.sideSunDir, 1, &g.builtSunDir[0]);
  // The sides reach the point at infinity away from the sun (w = 0): for z-fail depth-clamped, so that none of
  // it is clipped at the far plane.
  if (depthClamp) glEnable(GL_DEPTH_CLAMP);
  glDrawArraysIndirect(GL_TRIANGLES, reinterpret_cast<const void*>(sidesOffset));
  glDisable(GL_DEPTH_CLAMP);
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
  drawVolumes(clipFromWorld, kFacingOffset, kTurnedOffset, kSidesOffset);
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
  c.keptByDepthTest = cmd.keptByDepth;
  c.keptTriangles = (cmd.facingCount + cmd.turnedCount) / 3;
  c.silhouetteEdges = cmd.silhouetteEdges;
  c.sideTriangles = cmd.sideCount / 3;
  c.lastFrameZFail = cmd.selected[0] != 0 || cmd.selected[5] != 0 || cmd.selected[10] != 0;
  return c;
}

}  // namespace fly::raster
