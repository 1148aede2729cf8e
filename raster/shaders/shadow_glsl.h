// GLSL 4.50 sources of the sun's shadow volumes (raster/sun_shadows.h), as C++ raw strings; the renderer
// prepends "#version 450 core". Positions in metres, world frame; the sun's direction is the unit vector
// towards it.
//
// Buffers (binding points of the shader storage blocks):
//   0 positions      the scene's vertex positions, 3 floats each (rdb::RasterRdb::positionsM)
//   1 casters        per caster triangle: its vertices (xyz) and flags (w: bit k set where its edge k, from
//                    vertex k to vertex k + 1, runs from the edge's first to its second vertex; bits 3–4 the
//                    mesh's closure: 0 open, 1 closed facing out, 2 closed facing in), then its edges' indices
//   2 visible        per caster: 1 where the visibility map shows it
//   3 edge counts    per undirected edge: the signed number of kept triangles, turned to face the sun, that run
//                    along it from its first to its second vertex (+1) or back (−1)
//   4 caps           the kept triangles' vertex indices: those facing the sun from the start, those turned
//                    round (drawn with the other winding) from the end
//   5 edge vertices  per edge: its first and second vertex (indices of positions)
//   6 commands       the indirect draws and counters (SunShadows::Commands)
//   7 sides          per extruded side triangle: its two finite vertices; the third is the sun's antipode at
//                    infinity (−sunDir, w = 0)
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
// 10–13, then the counters: triangles seen in the visibility map, silhouette edges.
layout(std430, binding = 6) coherent buffer Commands { uint commands[]; };
)GLSL";

// The visibility map: every caster triangle drawn orthographically from the sun with its index as its value
// (R32UI; 0xffffffff where none). Vertices are pulled by gl_VertexID: 3 per caster.
inline constexpr const char* kShadowVisibilityVertex = R"GLSL(
uniform mat4 uSunClipFromWorld;
flat out uint vCaster;
void main() {
  uint t = uint(gl_VertexID) / 3u;
  uint k = uint(gl_VertexID) % 3u;
  gl_Position = uSunClipFromWorld * vec4(flyPosition(casters[t].vertices[k]), 1.0);
  vCaster = t;
}
)GLSL";

inline constexpr const char* kShadowVisibilityFragment = R"GLSL(
flat in uint vCaster;
layout(location = 0) out uint oCaster;
void main() { oCaster = vCaster; }
)GLSL";

// Marks the casters the visibility map shows, one invocation per texel.
inline constexpr const char* kShadowMarkCompute = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, r32ui) uniform readonly uimage2D uVisibility;
layout(std430, binding = 2) buffer Visible { uint visible[]; };
void main() {
  ivec2 p = ivec2(gl_GlobalInvocationID.xy);
  ivec2 size = imageSize(uVisibility);
  if (p.x >= size.x || p.y >= size.y) return;
  uint id = imageLoad(uVisibility, p).x;
  if (id != 0xffffffffu) visible[id] = 1u;
}
)GLSL";

// One invocation per caster: decides whether it is kept (raster/sun_shadows.h: seen in the visibility map, or
// too small to be sure to be seen, able to be seen and not wholly behind what the map shows; or, without
// pruning, facing the sun), turns it to face the sun, adds its edges' signed uses and appends it to the caps.
inline constexpr const char* kShadowKeepCompute = R"GLSL(
layout(local_size_x = 64) in;
layout(binding = 0) uniform usampler2D uVisibilityIds;  // the map: caster index, 0xffffffff for none
layout(binding = 1) uniform sampler2D uVisibilityDepth;  // its depth, [0, 1] from the sun
uniform mat4 uSunClipFromWorld;
uniform int uMapTexels;
uniform uint uCasterCount;
uniform uint uCapCapacity;     // indices in the caps buffer: 3 × casters
uniform vec3 uSunDirWorld;     // unit, towards the sun
uniform vec3 uSunXWorld;       // the sun's image plane: unit, perpendicular to uSunDirWorld and each other
uniform vec3 uSunYWorld;
uniform float uSmallInradiusM;  // a triangle whose projection's inradius is below this may be missed (t/√2)
uniform int uPrune;             // 1: visibility map; 0: every sun-facing triangle (the classic method)
layout(std430, binding = 2) readonly buffer Visible { uint visible[]; };
layout(std430, binding = 3) buffer EdgeCounts { int edgeCount[]; };
layout(std430, binding = 4) writeonly buffer Caps { uint capIndices[]; };

// Whether the triangle lies wholly behind surfaces the map shows over all of its footprint: between four
// neighbouring texel centres that all show one triangle, that triangle covers the square they span (it is
// convex) at depths no farther than the largest of the four (it is planar); a triangle whose footprint those
// squares cover, and whose nearest vertex is farther from the sun than each square's farthest corner, is
// hidden. Footprints over more than 4 × 4 squares are not tested (the triangle is kept).
bool flyHiddenBehindMap(vec3 p0, vec3 p1, vec3 p2) {
  vec3 w0 = (uSunClipFromWorld * vec4(p0, 1.0)).xyz * 0.5 + 0.5;  // orthographic: w = 1
  vec3 w1 = (uSunClipFromWorld * vec4(p1, 1.0)).xyz * 0.5 + 0.5;
  vec3 w2 = (uSunClipFromWorld * vec4(p2, 1.0)).xyz * 0.5 + 0.5;
  float n = float(uMapTexels);
  vec2 lo = min(w0.xy, min(w1.xy, w2.xy)) * n, hi = max(w0.xy, max(w1.xy, w2.xy)) * n;
  float nearest = min(w0.z, min(w1.z, w2.z));
  ivec2 a = ivec2(floor(lo - 0.5)), b = ivec2(floor(hi - 0.5));  // squares from centre a to centre b + 1
  if (a.x < 0 || a.y < 0 || b.x + 1 >= uMapTexels || b.y + 1 >= uMapTexels) return false;
  if (b.x - a.x > 3 || b.y - a.y > 3) return false;
  for (int y = a.y; y <= b.y; ++y) {
    for (int x = a.x; x <= b.x; ++x) {
      uint id = texelFetch(uVisibilityIds, ivec2(x, y), 0).x;
      if (id == 0xffffffffu) return false;
      float farthest = 0.0;
      for (int k = 0; k < 4; ++k) {
        ivec2 c = ivec2(x + (k & 1), y + (k >> 1));
        if (texelFetch(uVisibilityIds, c, 0).x != id) return false;
        farthest = max(farthest, texelFetch(uVisibilityDepth, c, 0).x);
      }
      if (!(nearest > farthest + 1e-6)) return false;
    }
  }
  return true;
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uCasterCount) return;
  Caster c = casters[i];
  vec3 p0 = flyPosition(c.vertices.x);
  vec3 e1 = flyPosition(c.vertices.y) - p0;
  vec3 e2 = flyPosition(c.vertices.z) - p0;
  // Twice the signed area of the triangle's projection onto the sun's image plane.
  float area2 = dot(cross(e1, e2), uSunDirWorld);
  if (area2 == 0.0) return;  // edge-on: its shadow prism has no volume
  bool facing = area2 > 0.0;
  bool kept;
  if (uPrune != 0) {
    bool seen = visible[i] != 0u;
    if (seen) atomicAdd(commands[14], 1u);
    vec2 a = vec2(dot(e1, uSunXWorld), dot(e1, uSunYWorld));
    vec2 b = vec2(dot(e2, uSunXWorld), dot(e2, uSunYWorld));
    float perimeter = length(a) + length(b) + length(b - a);
    bool small = abs(area2) < uSmallInradiusM * perimeter;  // inradius = 2 · area / perimeter
    uint closure = (c.vertices.w >> 3u) & 3u;
    bool canBeSeen = closure == 0u || (closure == 1u) == facing;
    kept = seen || (small && canBeSeen && !flyHiddenBehindMap(p0, p0 + e1, p0 + e2));
  } else {
    kept = facing;
  }
  if (!kept) return;
  int turn = facing ? 1 : -1;
  for (uint k = 0u; k < 3u; ++k) {
    int along = ((c.vertices.w >> k) & 1u) != 0u ? 1 : -1;
    atomicAdd(edgeCount[c.edges[k]], along * turn);
  }
  uint at;
  if (facing) {
    at = atomicAdd(commands[0], 3u);
  } else {
    at = uCapCapacity - 3u - atomicAdd(commands[5], 3u);
  }
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

// The volumes write only stencil.
inline constexpr const char* kShadowVolumeFragment = R"GLSL(
void main() {}
)GLSL";

}  // namespace fly::raster::shaders
