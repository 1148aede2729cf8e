// GLSL 4.50 sources of the sun's shadow volumes (raster/sun_shadows.h), as C++ raw strings; the renderer
// prepends "#version 450 core". Positions in metres, world frame; the sun's direction is the unit vector
// towards it.
//
// Buffers (binding points of the shader storage blocks):
//   0 positions      the scene's vertex positions, 3 floats each (rdb::RasterRdb::positionsM)
//   1 casters        per caster triangle: its vertices (xyz) and flags (w: bit k set where its edge k, from
//                    vertex k to vertex k + 1, runs from the edge's first to its second vertex; bits 3–4 its
//                    shell's closure: 0 open, 1 closed facing out, 2 closed facing in), then its edges'
//                    indices (xyz) and its shell (w: the triangles connected through shared edges)
//   2 state          per caster: 0 undecided, 1 seen in a visibility map level (kept), 2 dropped, 4 kept by
//                    the depth test (kShadowDepthTestFragment), 16 + L to be depth-tested against level L's map
//                    (dropped unless that test keeps it)
//   3 edge counts    per undirected edge: the signed number of kept triangles, turned to face the sun, that
//                    run along it from its first to its second vertex (+1) or back (−1)
//   4 caps           the kept triangles' vertex indices: those facing the sun from the start, those turned
//                    round (drawn with the other winding) from the end
//   5 edge vertices  per edge: its first and second vertex (indices of positions)
//   6 commands       the indirect draws and counters (SunShadows::Commands)
//   7 sides          per extruded side triangle: its two finite vertices; the third is the sun's antipode at
//                    infinity (−sunDir, w = 0)
//   8 map levels     the visibility map levels' regions (kShadowCommon)
//   9 shells kept    per shell: 1 when one of its triangles is kept
//  10 depth tests    a DrawArraysIndirectCommand (6 vertices per caster) and the casters that a level's
//                    classification sends to the depth test
#pragma once

namespace fly::raster::shaders {

inline constexpr const char* kShadowCommon = R"GLSL(
layout(std430, binding = 0) readonly buffer Positions { float positionsM[]; };
vec3 flyPosition(uint v) { return vec3(positionsM[3u * v], positionsM[3u * v + 1u], positionsM[3u * v + 2u]); }
struct Caster {
  uvec4 vertices;  // w: flags
  uvec4 edges;
};
layout(std430, binding = 1) readonly buffer Casters { Caster casters[]; };
// SunShadows::Commands: facing caps (DrawElementsIndirect) 0–4, turned caps 5–9, sides (DrawArraysIndirect)
// 10–13, the counters (14: triangles seen in the visibility maps, 15: silhouette edges), the near-plane flag
// and the selected draws (16–34), and 35: triangles kept by the depth test.
layout(std430, binding = 6) coherent buffer Commands { uint commands[]; };

// The visibility map's levels: level 0 covers the casters' bounds (uSunClipFromWorld); level k + 1 the square
// around the triangles level k left undecided, with texels half as large as level k's. Per level its region
// of level 0's image plane, in level 0's texels × 256 (integers, for atomicMin and atomicMax): min x, min y,
// max x, max y; empty (min > max) when level k left nothing undecided.
layout(std430, binding = 8) coherent buffer MapLevels { ivec4 levelRegions[]; };
uniform mat4 uSunClipFromWorld;  // level 0: world → the orthographic view from the sun
uniform int uMapTexels;          // texels per side of level 0
uniform int uLevelTexels;        // texels per side of level uLevel (its texel: half the last level's)
uniform int uLevel;

// Level uLevel's square: xy its corner and z its side, in level 0's texels; false when the level is empty.
bool flyLevelRegion(out vec3 region) {
  ivec4 r = levelRegions[uLevel];
  if (r.x > r.z || r.y > r.w) return false;
  vec2 lo = vec2(r.xy) / 256.0, hi = vec2(r.zw) / 256.0;
  float side = uLevel == 0 ? hi.x - lo.x : max(hi.x - lo.x, hi.y - lo.y) * (1.0 + 8.0 / float(uMapTexels)) + 1.0 / 64.0;
  region = vec3(0.5 * (lo + hi) - 0.5 * side, side);
  return true;
}
// Caster states (buffer 2).
const uint kUndecided = 0u, kSeen = 1u, kDropped = 2u, kKeptByDepth = 4u, kDepthTestAtLevel0 = 16u;
bool flyKept(uint s) { return s == kUndecided || s == kSeen || s == kKeptByDepth; }
// The depth test's reach around a footprint, in texels of the level (kShadowDepthTestFragment).
const float kDepthTestReachTexels = 1.4143;
// Footprints of at most this many texel centres are depth-tested in the classification's own loop (no draw).
const int kDepthTestInlineTexels = 64;
layout(std430, binding = 10) coherent buffer DepthTests {
  uint depthTestDraw[4];  // count (6 per caster), instances, first, base instance
  uint depthTestCasters[];
};
// The level's map: caster indices and their depth from the sun in [0, 1]; the indices are not cleared, so a
// texel shows a caster only where its depth is below 1 (drawn this level).
layout(binding = 0) uniform usampler2D uVisibilityIds;
layout(binding = 1) uniform sampler2D uVisibilityDepth;
uint flyMapCaster(ivec2 p) {
  return texelFetch(uVisibilityDepth, p, 0).x < 1.0 ? texelFetch(uVisibilityIds, p, 0).x : 0xffffffffu;
}
// The depth test at the texel centre c of the level (kShadowDepthTestVertex says what and why) of the caster
// with vertices w0, w1, w2 in the level (xy texels, z depth): whether it keeps the caster.
vec2 flyNearestOnSegment(vec2 p, vec2 a, vec2 b) {
  vec2 ab = b - a;
  float len2 = dot(ab, ab);
  return a + ab * (len2 > 0.0 ? clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0);
}
float flyCross2(vec2 a, vec2 b) { return a.x * b.y - a.y * b.x; }
bool flyDepthTestKeeps(vec2 c, vec3 w0, vec3 w1, vec3 w2) {
  vec2 a = w0.xy, b = w1.xy, d = w2.xy;
  float det = flyCross2(b - a, d - a);
  // The caster's point q nearest c in the image plane.
  vec2 q = c;
  bool inside = det != 0.0;
  if (inside) {
    float s = flyCross2(d - b, c - b) / det, t = flyCross2(a - d, c - d) / det;
    inside = s >= 0.0 && t >= 0.0 && s + t <= 1.0;
  }
  if (!inside) {
    vec2 q0 = flyNearestOnSegment(c, a, b), q1 = flyNearestOnSegment(c, b, d), q2 = flyNearestOnSegment(c, d, a);
    float d0 = distance(c, q0), d1 = distance(c, q1), d2 = distance(c, q2);
    q = d0 <= d1 && d0 <= d2 ? q0 : (d1 <= d2 ? q1 : q2);
  }
  if (distance(c, q) > kDepthTestReachTexels) return false;
  float nearestVertex = min(w0.z, min(w1.z, w2.z));
  float nearest = nearestVertex;
  if (abs(det) > 1e-6) {
    // The plane's depth z(q) and its gradient in the image plane (texels).
    vec2 gradient = vec2((w1.z - w0.z) * (d.y - a.y) - (w2.z - w0.z) * (b.y - a.y),
                         (w2.z - w0.z) * (b.x - a.x) - (w1.z - w0.z) * (d.x - a.x)) / det;
    float zq = w0.z + dot(gradient, q - a);
    nearest = max(nearestVertex, zq - 2.0 * kDepthTestReachTexels * length(gradient));
  }
  float shown = texelFetch(uVisibilityDepth, ivec2(c), 0).x;  // 1 where the map shows nothing
  return !(shown < nearest - 1e-6);
}
// p in level 0: xy in texels, z the depth from the sun in [0, 1].
vec3 flyBaseWindow(vec3 p) {
  vec3 c = (uSunClipFromWorld * vec4(p, 1.0)).xyz;  // orthographic: w = 1
  return vec3((c.xy * 0.5 + 0.5) * float(uMapTexels), c.z * 0.5 + 0.5);
}
// The same point in the level of `region`: xy in its texels.
vec3 flyLevelWindow(vec3 base, vec3 region) {
  return vec3((base.xy - region.xy) / region.z * float(uLevelTexels), base.z);
}
)GLSL";

// Zeroes the per-build buffers, one invocation per index: the casters' states (binding 2), the edges' counts
// (3) and the shells' flags (9). (A compute pass: on NVIDIA's driver glClearBufferData is several times
// slower.)
inline constexpr const char* kShadowResetCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uCasterCount, uEdgeCount, uShellCount;
layout(std430, binding = 2) writeonly buffer State { uint state[]; };
layout(std430, binding = 3) writeonly buffer EdgeCounts { int edgeCount[]; };
layout(std430, binding = 9) writeonly buffer ShellKept { uint shellKept[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < uCasterCount) state[i] = 0u;
  if (i < uEdgeCount) edgeCount[i] = 0;
  if (i < uShellCount) shellKept[i] = 0u;
}
)GLSL";

// A visibility map level: every caster triangle drawn orthographically from the sun with its index as its
// value (R32UI; where the depth stays 1, none): one indexed draw of the casters' vertex indices in caster order, so a
// caster's index is its gl_PrimitiveID, over the scene's positions (shared vertices transformed once).
inline constexpr const char* kShadowVisibilityVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
void main() {
  vec3 region;
  if (!flyLevelRegion(region)) {
    gl_Position = vec4(2.0, 2.0, 2.0, 1.0);  // outside the view: an empty level draws nothing
    return;
  }
  vec3 w = flyLevelWindow(flyBaseWindow(aPositionM), region);
  gl_Position = vec4(w.xy / float(uLevelTexels) * 2.0 - 1.0, w.z * 2.0 - 1.0, 1.0);
}
)GLSL";

inline constexpr const char* kShadowVisibilityFragment = R"GLSL(
layout(location = 0) out uint oCaster;
void main() { oCaster = uint(gl_PrimitiveID); }
)GLSL";

// Marks the casters a level shows as seen (kept), one invocation per texel. State per caster: 0 undecided,
// 1 seen (kept), 2 dropped (it cannot be seen, or is certain to be hidden, or is significant and unseen).
inline constexpr const char* kShadowMarkCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(std430, binding = 2) buffer State { uint state[]; };
void main() {
  vec3 region;
  if (!flyLevelRegion(region)) return;
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  if (p.x >= uLevelTexels || p.y >= uLevelTexels) return;
  uint id = flyMapCaster(p);
  if (id != 0xffffffffu) state[id] = 1u;
}
)GLSL";

// One invocation per undecided caster after a level's map (raster/sun_shadows.h): one facing the way a closed
// mesh hides is dropped; one wholly behind what the map shows over its footprint is dropped; one whose projected
// inradius reaches t/√2 (t this level's texel) would have been seen were it significant, so it goes to the
// depth test against this level's map; the rest stay undecided and widen the next level's region (after the
// last level they go to the depth test too).
inline constexpr const char* kShadowClassifyCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uCasterCount;
uniform vec3 uSunDirWorld;  // unit, towards the sun
uniform vec3 uSunXWorld;    // the sun's image plane: unit, perpendicular to uSunDirWorld and each other
uniform vec3 uSunYWorld;
uniform float uBaseTexelM;  // level 0's texel side t₀, metres
uniform bool uLastLevel;  // what stays undecided goes to the depth test
layout(std430, binding = 2) buffer State { uint state[]; };

// Whether the triangle lies wholly behind surfaces the level shows over all of its footprint: between four
// neighbouring texel centres that all show one triangle, that triangle covers the square they span (it is
// convex) at depths no farther than the largest of the four (it is planar); a triangle whose footprint those
// squares cover, and whose nearest vertex is farther from the sun than each square's farthest corner, is
// hidden. Footprints over more than 4 × 4 squares are not tested.
bool flyHiddenBehindMap(vec3 w0, vec3 w1, vec3 w2) {
  vec2 lo = min(w0.xy, min(w1.xy, w2.xy)), hi = max(w0.xy, max(w1.xy, w2.xy));
  float nearest = min(w0.z, min(w1.z, w2.z));
  ivec2 a = ivec2(floor(lo - 0.5)), b = ivec2(floor(hi - 0.5));  // squares from centre a to centre b + 1
  if (a.x < 0 || a.y < 0 || b.x + 1 >= uLevelTexels || b.y + 1 >= uLevelTexels) return false;
  if (b.x - a.x > 3 || b.y - a.y > 3) return false;
  for (int y = a.y; y <= b.y; ++y) {
    for (int x = a.x; x <= b.x; ++x) {
      uint id = flyMapCaster(ivec2(x, y));
      if (id == 0xffffffffu) return false;
      float farthest = 0.0;
      for (int k = 0; k < 4; ++k) {
        ivec2 c = ivec2(x + (k & 1), y + (k >> 1));
        if (flyMapCaster(c) != id) return false;
        farthest = max(farthest, texelFetch(uVisibilityDepth, c, 0).x);
      }
      if (!(nearest > farthest + 1e-6)) return false;
    }
  }
  return true;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uCasterCount || state[i] != 0u) return;
  vec3 region;
  if (!flyLevelRegion(region)) return;
  Caster c = casters[i];
  vec3 p0 = flyPosition(c.vertices.x), p1 = flyPosition(c.vertices.y), p2 = flyPosition(c.vertices.z);
  vec3 e1 = p1 - p0, e2 = p2 - p0;
  float area2 = dot(cross(e1, e2), uSunDirWorld);  // twice the signed area of its projection
  uint closure = (c.vertices.w >> 3u) & 3u;
  if (area2 == 0.0 || !(closure == 0u || (closure == 1u) == (area2 > 0.0))) {
    state[i] = 2u;
    return;
  }
  vec2 a = vec2(dot(e1, uSunXWorld), dot(e1, uSunYWorld));
  vec2 b = vec2(dot(e2, uSunXWorld), dot(e2, uSunYWorld));
  float perimeter = length(a) + length(b) + length(b - a);
  float texelM = uBaseTexelM * region.z / float(uLevelTexels);
  // inradius = 2 · area / perimeter, against t/√2 widened by 0.1 % (rounding must not drop a triangle on the
  // boundary: keeping more is always safe)
  vec3 b0 = flyBaseWindow(p0), b1 = flyBaseWindow(p1), b2 = flyBaseWindow(p2);
  vec3 w0 = flyLevelWindow(b0, region), w1 = flyLevelWindow(b1, region), w2 = flyLevelWindow(b2, region);
  if (flyHiddenBehindMap(w0, w1, w2)) {
    state[i] = kDropped;
    return;
  }
  bool significantIfSeen = !(abs(area2) < texelM * 0.70710678 * 1.001 * perimeter);
  if (significantIfSeen || uLastLevel) {
    // To the depth test against this level's map, unless part of the footprint's reach lies outside the
    // level, where the map says nothing: then it is kept.
    vec2 lo = min(w0.xy, min(w1.xy, w2.xy)) - kDepthTestReachTexels;
    vec2 hi = max(w0.xy, max(w1.xy, w2.xy)) + kDepthTestReachTexels;
    if (!(all(greaterThanEqual(lo, vec2(0.0))) && all(lessThanEqual(hi, vec2(float(uLevelTexels)))))) {
      state[i] = kKeptByDepth;
      return;
    }
    // The texel centres (x + ½, y + ½) in [lo, hi]: a few are tested here, many by the rasteriser.
    ivec2 first = ivec2(ceil(lo - 0.5)), last = ivec2(floor(hi - 0.5));
    if ((last.x - first.x + 1) * (last.y - first.y + 1) <= kDepthTestInlineTexels) {
      bool keep = false;
      for (int y = first.y; y <= last.y && !keep; ++y) {
        for (int x = first.x; x <= last.x && !keep; ++x) keep = flyDepthTestKeeps(vec2(x, y) + 0.5, w0, w1, w2);
      }
      state[i] = keep ? kKeptByDepth : kDropped;
    } else {
      state[i] = kDepthTestAtLevel0 + uint(uLevel);
      depthTestCasters[atomicAdd(depthTestDraw[0], 6u) / 6u] = i;
    }
    return;
  }
  vec2 lo = min(b0.xy, min(b1.xy, b2.xy)) * 256.0, hi = max(b0.xy, max(b1.xy, b2.xy)) * 256.0;
  atomicMin(levelRegions[uLevel + 1].x, int(floor(lo.x)));
  atomicMin(levelRegions[uLevel + 1].y, int(floor(lo.y)));
  atomicMax(levelRegions[uLevel + 1].z, int(ceil(hi.x)));
  atomicMax(levelRegions[uLevel + 1].w, int(ceil(hi.y)));
}
)GLSL";

// The depth test of the casters a level's classification sent to it (state 16 + level), drawn over that
// level's map (an indirect draw of 6 vertices per caster the classification listed): the square around its
// footprint widened by kDepthTestReachTexels (two triangles), and per texel centre c within that reach of the footprint the
// fragment stage keeps the caster (state 4) unless the surface the map shows at c is nearer the sun than the
// caster can be anywhere within the reach of c: its plane's depth at its point q nearest c, less the plane's
// slope times twice the reach (every point of it within the reach of c lies within twice the reach of q), and
// no nearer than its nearest vertex. A caster the map does not show, hidden at every texel centre around it,
// is dropped; one that shows through a gap at least a texel wide, or whose sun-lit sliver borders what lies
// beyond it (a floor the sun reaches past a wall's edge), is kept. What this cannot see: a caster visible only
// through a gap narrower than the texels between two nearer surfaces.
inline constexpr const char* kShadowDepthTestVertex = R"GLSL(
flat out uint vCaster;
flat out vec3 vW0, vW1, vW2;  // the caster's vertices in the level: xy in texels, z the depth from the sun
void main() {
  uint i = depthTestCasters[uint(gl_VertexID) / 6u], k = uint(gl_VertexID) % 6u;
  vCaster = i;
  vec3 region;
  flyLevelRegion(region);  // not empty: its classification listed this caster
  Caster c = casters[i];
  vW0 = flyLevelWindow(flyBaseWindow(flyPosition(c.vertices.x)), region);
  vW1 = flyLevelWindow(flyBaseWindow(flyPosition(c.vertices.y)), region);
  vW2 = flyLevelWindow(flyBaseWindow(flyPosition(c.vertices.z)), region);
  vec2 lo = min(vW0.xy, min(vW1.xy, vW2.xy)) - kDepthTestReachTexels;
  vec2 hi = max(vW0.xy, max(vW1.xy, vW2.xy)) + kDepthTestReachTexels;
  uint corner = k < 3u ? k : k - 2u;  // (0, 1, 2) and (1, 2, 3) of the square's corners
  vec2 p = vec2((corner & 1u) != 0u ? hi.x : lo.x, (corner & 2u) != 0u ? hi.y : lo.y);
  gl_Position = vec4(p / float(uLevelTexels) * 2.0 - 1.0, 0.0, 1.0);
}
)GLSL";

inline constexpr const char* kShadowDepthTestFragment = R"GLSL(
layout(std430, binding = 2) coherent buffer State { uint state[]; };
flat in uint vCaster;
flat in vec3 vW0, vW1, vW2;
void main() {
  if (state[vCaster] == kKeptByDepth) return;
  if (flyDepthTestKeeps(gl_FragCoord.xy, vW0, vW1, vW2)) state[vCaster] = kKeptByDepth;
}
)GLSL";

// One invocation per caster: marks the shells that have a kept triangle (seen, or kept by the depth test).
inline constexpr const char* kShadowShellsCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uCasterCount;
layout(std430, binding = 2) readonly buffer State { uint state[]; };
layout(std430, binding = 9) writeonly buffer ShellKept { uint shellKept[]; };
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i < uCasterCount && flyKept(state[i])) shellKept[casters[i].edges.w] = 1u;
}
)GLSL";

// One invocation per caster: the kept ones (seen, or kept by the depth test, or of a closed shell
// with a kept triangle and facing the way the sun can see it; or, without pruning, every one facing the way
// the sun can see it: of an open shell either way) are turned to face the sun, add their edges' signed uses
// and are appended to the caps.
inline constexpr const char* kShadowKeepCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uCasterCount;
uniform uint uCapCapacity;  // indices in the caps buffer: 3 × casters
uniform vec3 uSunDirWorld;  // unit, towards the sun
uniform int uPrune;         // 1: visibility map; 0: every triangle the sun can see (the classic method)
uniform int uMapped;        // 1: the visibility map's states are set (always with uPrune)
layout(std430, binding = 2) readonly buffer State { uint state[]; };
layout(std430, binding = 3) buffer EdgeCounts { int edgeCount[]; };
layout(std430, binding = 4) writeonly buffer Caps { uint capIndices[]; };
layout(std430, binding = 9) readonly buffer ShellKept { uint shellKept[]; };
// Whether caster i is kept, and whether it faces the sun.
bool flyKeep(uint i, out bool facing) {
  facing = false;
  if (i >= uCasterCount) return false;
  Caster c = casters[i];
  vec3 p0 = flyPosition(c.vertices.x);
  float area2 = dot(cross(flyPosition(c.vertices.y) - p0, flyPosition(c.vertices.z) - p0), uSunDirWorld);
  if (area2 == 0.0) return false;  // edge-on: its shadow prism has no volume
  facing = area2 > 0.0;
  // Which way the sun can see it: a triangle of an open shell either way (a one-sided ceiling whose back the
  // sun sees blocks it as the baker's surfaces do), one of a closed shell only from outside the shell.
  uint closure = (c.vertices.w >> 3u) & 3u;
  bool seeable = closure == 0u || (closure == 1u) == facing;
  // The classic method: every triangle facing the sun (a closed shell's terminator), and of those facing away
  // the ones the sun can see from behind: a closed shell's that faces in, an open shell's that the map keeps
  // (seen, or kept by the depth test: the sun reaches its back through a gap).
  if (uPrune == 0) return seeable && (facing || closure != 0u || uMapped == 0 || flyKept(state[i]));
  // A closed shell that casts at all casts with every triangle that faces the way the sun can see it: its
  // silhouette is then the shell's terminator, not the edge of what the map happened to show.
  // One facing the way its closed shell hides it shows in the map only where it meets a seeable one at the
  // shell's rim or on a coplanar face (a tie of depths): the sun never sees more of it than that edge.
  if (!seeable) return false;
  bool wholeShell = closure != 0u && shellKept[c.edges.w] != 0u;
  return flyKept(state[i]) || wholeShell;
}

// The workgroup's appends, summed in shared memory so that each workgroup adds to the global counters once.
shared uint sFacing, sTurned, sSeen, sKeptByDepth, sFacingBase, sTurnedBase;

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (gl_LocalInvocationIndex == 0u) {
    sFacing = 0u;
    sTurned = 0u;
    sSeen = 0u;
    sKeptByDepth = 0u;
  }
  barrier();
  bool facing;
  bool keep = flyKeep(i, facing);
  uint local = 0u;
  if (keep) {
    Caster c = casters[i];
    int turn = facing ? 1 : -1;
    for (uint k = 0u; k < 3u; ++k) {
      int along = ((c.vertices.w >> k) & 1u) != 0u ? 1 : -1;
      atomicAdd(edgeCount[c.edges[k]], along * turn);
    }
    local = facing ? atomicAdd(sFacing, 3u) : atomicAdd(sTurned, 3u);
    if (uPrune != 0) {
      uint s = state[i];
      if (s == kSeen) atomicAdd(sSeen, 1u);
      if (s == kKeptByDepth) atomicAdd(sKeptByDepth, 1u);
    }
  }
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    sFacingBase = sFacing > 0u ? atomicAdd(commands[0], sFacing) : 0u;
    sTurnedBase = sTurned > 0u ? atomicAdd(commands[5], sTurned) : 0u;
    if (sSeen > 0u) atomicAdd(commands[14], sSeen);
    if (sKeptByDepth > 0u) atomicAdd(commands[35], sKeptByDepth);
  }
  barrier();
  if (!keep) return;
  Caster c = casters[i];
  uint at = facing ? sFacingBase + local : uCapCapacity - 3u - (sTurnedBase + local);
  capIndices[at] = c.vertices.x;
  capIndices[at + 1u] = c.vertices.y;
  capIndices[at + 2u] = c.vertices.z;
}
)GLSL";

// One invocation per edge: an edge with a non-zero count is a silhouette edge, extruded |count| times away
// from the sun as the triangle (its two vertices, the point at infinity), wound so that it faces out of the
// volume: for a kept triangle turned to face the sun, its edge a → b gives (b, a, ∞).
inline constexpr const char* kShadowEdgesCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uEdgeCount;
uniform uint uCapCapacity;
layout(std430, binding = 3) readonly buffer EdgeCounts { int edgeCount[]; };
layout(std430, binding = 5) readonly buffer EdgeVertices { uvec2 edgeVertices[]; };
layout(std430, binding = 7) writeonly buffer Sides { uvec2 sides[]; };
void main() {
  uint e = gl_GlobalInvocationID.x;
  if (e == 0u) commands[7] = uCapCapacity - commands[5];  // the turned caps' first index
  if (e >= uEdgeCount) return;
  int count = edgeCount[e];
  if (count == 0) return;
  uint n = uint(abs(count));
  atomicAdd(commands[15], 1u);
  uint at = atomicAdd(commands[10], 3u * n) / 3u;
  uvec2 v = edgeVertices[e];
  uvec2 side = count > 0 ? v.yx : v.xy;
  for (uint j = 0u; j < n; ++j) sides[at + j] = side;
}
)GLSL";

// The front caps: the kept triangles with the scene's own vertex attribute and the scene vertex stages'
// expression, both invariant, so that a cap lies at exactly the depth of the surface it is part of (the
// z-fail test counts equal depth as behind: a lit surface does not shadow itself).
inline constexpr const char* kShadowCapVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
uniform mat4 uClipFromWorld;
invariant gl_Position;
void main() { gl_Position = uClipFromWorld * vec4(aPositionM, 1.0); }
)GLSL";

// The extruded sides: vertex 0 and 1 from the sides buffer, vertex 2 at infinity away from the sun.
inline constexpr const char* kShadowSideVertex = R"GLSL(
layout(std430, binding = 7) readonly buffer Sides { uvec2 sides[]; };
uniform mat4 uClipFromWorld;
uniform vec3 uSunDirWorld;
void main() {
  uint t = uint(gl_VertexID) / 3u;
  uint k = uint(gl_VertexID) % 3u;
  uvec2 s = sides[t];
  gl_Position = k == 2u ? uClipFromWorld * vec4(-uSunDirWorld, 0.0)
                        : uClipFromWorld * vec4(flyPosition(k == 0u ? s.x : s.y), 1.0);
}
)GLSL";

// Per frame, one invocation per cap slot: whether the camera's near-plane rectangle (uNearCornersM, already
// enlarged) may lie inside the prism of the kept triangle there — the points at or below it, away from the
// sun. Conservative: the rectangle's and the triangle's extents across the sun's direction overlap (with a
// margin for rounding) and some of the rectangle is no higher towards the sun than the triangle's highest
// point. A yes anywhere sets commands[16], and the stencil pass is z-fail.
inline constexpr const char* kShadowNearCompute = R"GLSL(
layout(local_size_x = 64) in;
uniform uint uCasterCount;
uniform uint uCapCapacity;
uniform vec3 uSunDirWorld;
uniform vec3 uNearCornersM[4];
layout(std430, binding = 4) readonly buffer Caps { uint capIndices[]; };
void main() {
  uint slot = gl_GlobalInvocationID.x;
  if (slot >= uCasterCount) return;
  uint at = 3u * slot;
  if (at + 3u > commands[0] && at < uCapCapacity - commands[5]) return;  // neither a facing nor a turned cap
  vec3 z = uSunDirWorld;
  vec3 x = normalize(abs(z.y) < 0.9 ? cross(vec3(0.0, 1.0, 0.0), z) : cross(vec3(1.0, 0.0, 0.0), z));
  vec3 y = cross(z, x);
  // Extents in the sun's frame (x, y across its direction, z towards it) of the triangle (t) and the
  // rectangle (q), and the largest coordinate, for the rounding margin.
  vec3 tMin = vec3(3.4e38), tMax = vec3(-3.4e38), qMin = vec3(3.4e38), qMax = vec3(-3.4e38);
  float scale = 0.0;
  for (uint k = 0u; k < 7u; ++k) {
    vec3 p = k < 3u ? flyPosition(capIndices[at + k]) : uNearCornersM[k - 3u];
    vec3 s = vec3(dot(p, x), dot(p, y), dot(p, z));
    if (k < 3u) {
      tMin = min(tMin, s);
      tMax = max(tMax, s);
    } else {
      qMin = min(qMin, s);
      qMax = max(qMax, s);
    }
    scale = max(scale, max(abs(s.x), max(abs(s.y), abs(s.z))));
  }
  float margin = 1e-5 * scale + 1e-3 * length(qMax - qMin);
  if (any(lessThan(tMax.xy + margin, qMin.xy)) || any(greaterThan(tMin.xy - margin, qMax.xy))) return;
  if (qMin.z > tMax.z + margin) return;
  atomicOr(commands[16], 1u);
}
)GLSL";

// Per frame, one invocation after kShadowNearCompute: the draws of the method taken (commands 17–34, see
// SunShadows::Commands), the other's counts 0; and the flag cleared for the next frame.
inline constexpr const char* kShadowSelectCompute = R"GLSL(
layout(local_size_x = 1) in;
uniform bool uForceZFail;
void main() {
  // Constant indices only (NVIDIA's compiler refuses computed ones into this buffer: "lvalue too complex").
  bool zFail = uForceZFail || commands[16] != 0u;
  uint capsFacing = zFail ? commands[0] : 0u, capsTurned = zFail ? commands[5] : 0u;
  uint sidesZFail = zFail ? commands[10] : 0u, sidesZPass = zFail ? 0u : commands[10];
  commands[17] = capsFacing;
  commands[18] = commands[1];
  commands[19] = commands[2];
  commands[20] = commands[3];
  commands[21] = commands[4];
  commands[22] = capsTurned;
  commands[23] = commands[6];
  commands[24] = commands[7];
  commands[25] = commands[8];
  commands[26] = commands[9];
  commands[27] = sidesZFail;
  commands[28] = commands[11];
  commands[29] = commands[12];
  commands[30] = commands[13];
  commands[31] = sidesZPass;
  commands[32] = commands[11];
  commands[33] = commands[12];
  commands[34] = commands[13];
  commands[16] = 0u;
}
)GLSL";

// The volumes write only stencil.
inline constexpr const char* kShadowVolumeFragment = R"GLSL(
void main() {}
)GLSL";

}  // namespace fly::raster::shaders
