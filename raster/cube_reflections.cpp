#include "raster/cube_reflections.h"

#include <epoxy/gl.h>

#include <cmath>
#include <string>

#include "raster/shaders/scene_glsl.h"

namespace fly::raster {
namespace {

// One face's luminance image (kLuminanceEncoding) into layer `uFace` of the source cube's level 0; alpha:
// with reflection fog (uFogDistanceM > 0) its share t = min(d / D, 1) of the texel, d the distance from the
// centre to what the texel shows (from the face's depth; nothing: t = 1), else 1 (not read).
constexpr const char* kDecodeFace = R"GLSL(
layout(local_size_x = 8, local_size_y = 8) in;
layout(binding = 0, rg32ui) uniform readonly uimage2D uLuminance;
layout(binding = 1, rgba32f) uniform writeonly imageCube uCube;
layout(binding = 2) uniform sampler2D uDepth;
uniform int uSize;
uniform int uFace;
uniform float uFogDistanceM;
uniform mat4 uWorldFromClip;
uniform vec3 uCentreM;
void main() {
  ivec2 id = ivec2(gl_GlobalInvocationID.xy);
  if (id.x >= uSize || id.y >= uSize) return;
  float a = 1.0;
  if (uFogDistanceM > 0.0) {
    float z = texelFetch(uDepth, id, 0).r;
    a = 1.0;
    if (z < 1.0) {
      vec4 q = uWorldFromClip * vec4((vec2(id) + 0.5) / float(uSize) * 2.0 - 1.0, z * 2.0 - 1.0, 1.0);
      a = min(distance(q.xyz / q.w, uCentreM) / uFogDistanceM, 1.0);
    }
  }
  imageStore(uCube, ivec3(id, uFace), vec4(flyDecodeLuminance(imageLoad(uLuminance, id).xy), a));
}
)GLSL";

}  // namespace

CubeReflections::CubeReflections(EnvironmentLight::Compile compile, const EnvironmentSettings& settings)
    : compile_(std::move(compile)), settings_(settings) {}

CubeReflections::~CubeReflections() { glDeleteProgram(decode_); }

View CubeReflections::faceView(uint32_t face, const vec3& centreM, float nearM) {
  // The face's direction at (s, t) is F + s S + t T (OpenGL 4.5 core, table 8.19, inverted): the camera's
  // right is S, its up T and its back −F (S × T = −F on every face: a rotation).
  static const vec3 kF[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  static const vec3 kS[6] = {{0, 0, -1}, {0, 0, 1}, {1, 0, 0}, {1, 0, 0}, {1, 0, 0}, {-1, 0, 0}};
  static const vec3 kT[6] = {{0, -1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {0, -1, 0}, {0, -1, 0}};
  View v;
  v.worldFromCamera = mat4(vec4(kS[face], 0.0f), vec4(kT[face], 0.0f), vec4(-kF[face], 0.0f), vec4(centreM, 1.0f));
  v.yfovRad = float(kPi / 2.0);
  v.znearM = nearM;
  v.zfarM = 1e30f;
  return v;
}

void CubeReflections::capture(uint32_t k, const vec3& centreM, float nearM, float fogDistanceM,
                              const std::function<Face(const View&)>& drawFace) {
  if (maps_.size() <= k) maps_.resize(k + 1);
  if (!maps_[k]) maps_[k] = std::make_unique<EnvironmentLight>(compile_, settings_);
  EnvironmentLight& maps = *maps_[k];
  if (!decode_) {
    decode_ = compile_("cube-reflection-face", std::string(shaders::kLuminanceEncoding),
                       {{GL_COMPUTE_SHADER, kDecodeFace}});
  }
  const GLuint cube = maps.sourceCube();
  for (uint32_t face = 0; face < 6; ++face) {
    const Face drawn = drawFace(faceView(face, centreM, nearM));
    glUseProgram(decode_);
    glUniform1i(glGetUniformLocation(decode_, "uSize"), GLint(settings_.cubePx));
    glUniform1i(glGetUniformLocation(decode_, "uFace"), GLint(face));
    const bool fog = std::isfinite(fogDistanceM) && drawn.depth != 0;
    glUniform1f(glGetUniformLocation(decode_, "uFogDistanceM"), fog ? fogDistanceM : -1.0f);
    if (fog) {
      glUniformMatrix4fv(glGetUniformLocation(decode_, "uWorldFromClip"), 1, GL_FALSE, &drawn.worldFromClip[0][0]);
      glUniform3fv(glGetUniformLocation(decode_, "uCentreM"), 1, &centreM[0]);
      glBindTextureUnit(2, drawn.depth);
    }
    glBindImageTexture(0, drawn.luminance, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
    glBindImageTexture(1, cube, 0, GL_TRUE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glDispatchCompute((settings_.cubePx + 7) / 8, (settings_.cubePx + 7) / 8, 1);
    glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
  }
  maps.buildFromSource();
}

}  // namespace fly::raster
