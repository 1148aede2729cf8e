#include "raster/ambient_occlusion.h"

#include <epoxy/gl.h>

#include <array>
#include <stdexcept>
#include <string>
#include <utility>

#include "raster/shaders/ambient_occlusion_glsl.h"

namespace fly::raster {

AmbientOcclusion::AmbientOcclusion(SunShadows::Compile compile) : compile_(std::move(compile)) {
  depthProgram_ = compile_(
      "ssao-depth", "",
      {{GL_VERTEX_SHADER, shaders::kAoDepthVertex}, {GL_FRAGMENT_SHADER, shaders::kAoDepthFragment}});
  const std::string ao = std::string(shaders::kAoCameraPoint) + shaders::kAoCompute;
  const std::string blur = std::string(shaders::kAoCameraPoint) + shaders::kAoBlurCompute;
  aoProgram_ = compile_("ssao", "", {{GL_COMPUTE_SHADER, ao.c_str()}});
  blurProgram_ = compile_("ssao-blur", "", {{GL_COMPUTE_SHADER, blur.c_str()}});
}

AmbientOcclusion::~AmbientOcclusion() {
  glDeleteProgram(depthProgram_);
  glDeleteProgram(aoProgram_);
  glDeleteProgram(blurProgram_);
  glDeleteFramebuffers(1, &fbo_);
  const unsigned textures[] = {depth_, raw_, ao_};
  glDeleteTextures(3, textures);
}

void AmbientOcclusion::resize(uint32_t widthPx, uint32_t heightPx) {
  if (widthPx == width_ && heightPx == height_ && fbo_) return;
  glDeleteFramebuffers(1, &fbo_);
  const unsigned old[] = {depth_, raw_, ao_};
  glDeleteTextures(3, old);
  const GLsizei w = GLsizei(widthPx), h = GLsizei(heightPx);
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH_COMPONENT32F, w, h);
  // Read per pixel: kAoCompute interpolates between pixel centres itself, in full float precision.
  glTextureParameteri(depth_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(depth_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  glTextureParameteri(depth_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(depth_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  for (unsigned* t : {&raw_, &ao_}) {
    glCreateTextures(GL_TEXTURE_2D, 1, t);
    glTextureStorage2D(*t, 1, GL_R16F, w, h);
    glTextureParameteri(*t, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTextureParameteri(*t, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glCreateFramebuffers(1, &fbo_);
  glNamedFramebufferTexture(fbo_, GL_DEPTH_ATTACHMENT, depth_, 0);
  glNamedFramebufferDrawBuffer(fbo_, GL_NONE);
  if (glCheckNamedFramebufferStatus(fbo_, GL_FRAMEBUFFER) != GL_FRAMEBUFFER_COMPLETE) {
    throw std::runtime_error("the OpenGL driver cannot render into a " + std::to_string(widthPx) + "×" +
                             std::to_string(heightPx) + " depth texture (ambient occlusion)");
  }
  width_ = widthPx;
  height_ = heightPx;
}

void AmbientOcclusion::run(const mat4& clipFromCamera, const mat4& cameraFromWorld, bool orthographic,
                           uint32_t widthPx, uint32_t heightPx, float radiusM,
                           const std::function<void()>& drawDepth) {
  resize(widthPx, heightPx);
  const mat4 clipFromWorld = clipFromCamera * cameraFromWorld;
  glBindFramebuffer(GL_FRAMEBUFFER, fbo_);
  glViewport(0, 0, GLsizei(widthPx), GLsizei(heightPx));
  glClearNamedFramebufferfv(fbo_, GL_DEPTH, 0, std::array<GLfloat, 1>{1.0f}.data());
  glEnable(GL_DEPTH_TEST);
  glDepthFunc(GL_LESS);
  glDepthMask(GL_TRUE);
  glDisable(GL_CULL_FACE);
  glUseProgram(depthProgram_);
  glUniformMatrix4fv(glGetUniformLocation(depthProgram_, "uClipFromWorld"), 1, GL_FALSE,
                     &clipFromWorld[0][0]);
  drawDepth();
  glBindVertexArray(0);

  const mat4 cameraFromClip = glm::inverse(clipFromCamera);
  const GLuint groupsX = (widthPx + 7) / 8, groupsY = (heightPx + 7) / 8;
  auto common = [&](unsigned program) {
    glUseProgram(program);
    glUniformMatrix4fv(glGetUniformLocation(program, "uCameraFromClip"), 1, GL_FALSE, &cameraFromClip[0][0]);
    glUniform2i(glGetUniformLocation(program, "uSizePx"), GLint(widthPx), GLint(heightPx));
    glUniform1f(glGetUniformLocation(program, "uRadiusM"), radiusM);
  };
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  common(aoProgram_);
  glUniformMatrix4fv(glGetUniformLocation(aoProgram_, "uClipFromCamera"), 1, GL_FALSE, &clipFromCamera[0][0]);
  glUniform1i(glGetUniformLocation(aoProgram_, "uOrthographic"), orthographic ? 1 : 0);
  glBindTextureUnit(0, depth_);
  glBindImageTexture(0, raw_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
  glDispatchCompute(groupsX, groupsY, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
  common(blurProgram_);
  glBindTextureUnit(1, raw_);
  glBindImageTexture(0, ao_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_R16F);
  glDispatchCompute(groupsX, groupsY, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace fly::raster
