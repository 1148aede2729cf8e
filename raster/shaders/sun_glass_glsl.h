// GLSL 4.50 sources of the sun's transmittance map through clear glass (raster/sun_glass.h), as C++ raw
// strings; the renderer prepends "#version 450 core" and, for the scene programs, their #defines. Positions
// in metres, world frame; the sun's direction is the unit vector towards it.
#pragma once

namespace fly::raster::shaders {

// The map's pass: each clear-glass vertex (SunGlassMap's vertex buffer) with its material's T inputs; the
// fragment writes (T(θ_sun), h), blended into the map (RGB multiplied, A the largest). Compiled after
// shaders::kGlassPane (scene_glsl.h).
inline constexpr const char* kSunGlassMapVertex = R"GLSL(
layout(location = 0) in vec3 aPositionM;
layout(location = 1) in vec3 aNormal;
layout(location = 2) in vec4 aTransmission;  // rgb transmission colour, w Schlick's F0 (< 0: uniform reflection)
layout(location = 3) in vec3 aReflection;    // rgb reflection colour
uniform mat4 uSunClipFromWorld;
uniform vec3 uSunDirWorld;
out vec3 vTransmittance;
out float vHeightM;
void main() {
  gl_Position = uSunClipFromWorld * vec4(aPositionM, 1.0);
  // The pane's transmittance along the sun's rays, from either face (as kSceneVertex's towards the eye).
  vTransmittance =
      flyPaneTransmittance(aTransmission.rgb, aReflection, aTransmission.w, dot(normalize(aNormal), uSunDirWorld));
  vHeightM = dot(aPositionM, uSunDirWorld);
}
)GLSL";

inline constexpr const char* kSunGlassMapFragment = R"GLSL(
in vec3 vTransmittance;
in float vHeightM;
layout(location = 0) out vec4 oMap;
void main() { oMap = vec4(vTransmittance, vHeightM); }
)GLSL";

// The scene programs' lookup (FLY_SUN_GLASS), prepended to their stages: the T of the clear glass between p
// and the sun (1 where none lies between).
inline constexpr const char* kSunGlassLookup = R"GLSL(
#ifdef FLY_SUN_GLASS
layout(binding = 8) uniform sampler2D uSunGlass;  // rgb: product of the panes' T; a: highest pane's h (m)
uniform mat4 uSunGlassFromWorld;                  // world → (u, v across the map, h = dot(p, sunDir) in m)
uniform float uSunGlassBiasM;
vec3 flySunGlass(vec3 p) {
  vec3 q = (uSunGlassFromWorld * vec4(p, 1.0)).xyz;
  if (!(q.x >= 0.0 && q.x < 1.0 && q.y >= 0.0 && q.y < 1.0)) return vec3(1.0);
  vec4 t = texelFetch(uSunGlass, ivec2(q.xy * vec2(textureSize(uSunGlass, 0))), 0);
  return q.z < t.a - uSunGlassBiasM ? t.rgb : vec3(1.0);
}
#endif
)GLSL";

}  // namespace fly::raster::shaders
