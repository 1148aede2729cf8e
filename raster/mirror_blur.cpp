#include "raster/mirror_blur.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "raster/shaders/mirror_blur_glsl.h"
#include "raster/shaders/scene_glsl.h"

namespace fly::raster {

namespace {

// A level's texels covering the pixels [lo, hi) of level 0: lo.xy, hi.xy exclusive.
struct Region {
  int lo[2], hi[2];
  uint32_t width() const { return uint32_t(hi[0] - lo[0]); }
  uint32_t height() const { return uint32_t(hi[1] - lo[1]); }
};

Region regionAt(const MirrorRect& r, int level) {
  const int s = 1 << level;
  auto floorDiv = [s](int v) { return v / s; };  // v ≥ 0
  auto ceilDiv = [s](int v) { return (v + s - 1) / s; };
  return {{floorDiv(r.x), floorDiv(r.y)}, {ceilDiv(r.x + r.width), ceilDiv(r.y + r.height)}};
}

void setRegion(unsigned program, const char* name, const Region& r) {
  glUniform4i(glGetUniformLocation(program, name), r.lo[0], r.lo[1], r.hi[0], r.hi[1]);
}

void dispatch(uint32_t width, uint32_t height) {
  glDispatchCompute((width + 7) / 8, (height + 7) / 8, 1);
  glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT);
}

}  // namespace

MirrorBlur::MirrorBlur(SunShadows::Compile compile) : compile_(std::move(compile)) {
  const std::string split = std::string(shaders::kLuminanceEncoding) + shaders::kMirrorBlurSplit;
  const std::string up = std::string(shaders::kMirrorBlurUpsample) + shaders::kMirrorBlurUp;
  split_ = compile_("mirror-blur-split", "", {{GL_COMPUTE_SHADER, split.c_str()}});
  down_ = compile_("mirror-blur-down", "", {{GL_COMPUTE_SHADER, shaders::kMirrorBlurDown}});
  up_ = compile_("mirror-blur-up", "", {{GL_COMPUTE_SHADER, up.c_str()}});
}

MirrorBlur::~MirrorBlur() {
  for (unsigned p : {split_, down_, up_}) glDeleteProgram(p);
  for (Reflector& r : reflectors_) glDeleteTextures(1, &r.pyramid);
  const unsigned textures[] = {passing_, depth_};
  glDeleteTextures(2, textures);
}

void MirrorBlur::resize(uint32_t widthPx, uint32_t heightPx) {
  if (widthPx == width_ && heightPx == height_ && passing_) return;
  for (Reflector& r : reflectors_) glDeleteTextures(1, &r.pyramid);
  reflectors_.clear();
  const unsigned old[] = {passing_, depth_};
  glDeleteTextures(2, old);
  levels_ = int(std::floor(std::log2(double(std::max(widthPx, heightPx))))) + 1;
  glCreateTextures(GL_TEXTURE_2D, 1, &passing_);
  glTextureStorage2D(passing_, levels_, GL_RGBA32F, GLsizei(widthPx), GLsizei(heightPx));
  glCreateTextures(GL_TEXTURE_2D, 1, &depth_);
  glTextureStorage2D(depth_, 1, GL_DEPTH24_STENCIL8, GLsizei(widthPx), GLsizei(heightPx));
  glTextureParameteri(depth_, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  glTextureParameteri(depth_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(depth_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  width_ = widthPx;
  height_ = heightPx;
}

void MirrorBlur::blur(uint32_t k, unsigned image, unsigned depth, const MirrorRect& rect, uint32_t widthPx,
                      uint32_t heightPx, const MirrorLobe& lobe) {
  resize(widthPx, heightPx);
  if (reflectors_.size() <= k) reflectors_.resize(k + 1);
  Reflector& out = reflectors_[k];
  if (!out.pyramid) {
    glCreateTextures(GL_TEXTURE_2D, 1, &out.pyramid);
    glTextureStorage2D(out.pyramid, levels_, GL_RGBA32F, GLsizei(widthPx), GLsizei(heightPx));
    glTextureParameteri(out.pyramid, GL_TEXTURE_MIN_FILTER, GL_NEAREST_MIPMAP_NEAREST);  // read by texelFetch
    glTextureParameteri(out.pyramid, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  }
  glCopyImageSubData(depth, GL_RENDERBUFFER, 0, rect.x, rect.y, 0, depth_, GL_TEXTURE_2D, 0, rect.x, rect.y, 0,
                     rect.width, rect.height, 1);
  // The levels the widest spread needs (λ = log2(2r), r the sky's spread), at least level 0.
  const float widestPx = lobe.pxPerTan > 0.0f ? 2.0f * lobe.alpha * lobe.pxPerTan : 0.25f * float(heightPx);
  const int levels = std::clamp(int(std::ceil(std::log2(std::max(2.0f * widestPx, 1.0f)))) + 1, 1, levels_);

  glUseProgram(split_);
  glUniform4i(glGetUniformLocation(split_, "uRect"), rect.x, rect.y, rect.width, rect.height);
  glUniformMatrix4fv(glGetUniformLocation(split_, "uWorldFromClip"), 1, GL_FALSE, &lobe.worldFromClip[0][0]);
  glUniform4fv(glGetUniformLocation(split_, "uPlane"), 1, &lobe.planeWorld[0]);
  glUniform4fv(glGetUniformLocation(split_, "uEye"), 1, &lobe.eye[0]);
  glUniform1f(glGetUniformLocation(split_, "uAlpha"), lobe.alpha);
  glUniform1f(glGetUniformLocation(split_, "uPxPerTan"), lobe.pxPerTan);
  glUniform2f(glGetUniformLocation(split_, "uTargetPx"), float(widthPx), float(heightPx));
  glBindImageTexture(0, image, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  glBindTextureUnit(0, depth_);
  glBindImageTexture(1, out.pyramid, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(2, passing_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatch(uint32_t(rect.width), uint32_t(rect.height));

  glUseProgram(down_);
  for (int level = 1; level < levels; ++level) {
    const Region r = regionAt(rect, level);
    setRegion(down_, "uRegion", r);
    setRegion(down_, "uFinerRegion", regionAt(rect, level - 1));
    glUniform1f(glGetUniformLocation(down_, "uLevel"), float(level));
    glUniform1i(glGetUniformLocation(down_, "uCoarsest"), level == levels - 1);
    glBindImageTexture(1, out.pyramid, level, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(2, passing_, level, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(3, passing_, level - 1, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    dispatch(r.width(), r.height());
  }

  glUseProgram(up_);
  glBindTextureUnit(1, out.pyramid);
  for (int level = levels - 2; level >= 1; --level) {
    const Region r = regionAt(rect, level);
    setRegion(up_, "uRegion", r);
    setRegion(up_, "uCoarseRegion", regionAt(rect, level + 1));
    glUniform1i(glGetUniformLocation(up_, "uLevel"), level);
    glBindImageTexture(1, out.pyramid, level, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    dispatch(r.width(), r.height());
  }
  const Region coarse = regionAt(rect, 1);
  const int region[4] = {coarse.lo[0], coarse.lo[1], coarse.hi[0], coarse.hi[1]};
  const int none[4] = {0, 0, 0, 0};
  std::copy_n(levels > 1 ? region : none, 4, out.coarseRegion);
}

}  // namespace fly::raster
