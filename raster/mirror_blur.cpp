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

void setRegion(int location, const Region& r) { glUniform4i(location, r.lo[0], r.lo[1], r.hi[0], r.hi[1]); }

void dispatch(uint32_t width, uint32_t height) { glDispatchCompute((width + 7) / 8, (height + 7) / 8, 1); }

// Makes the dispatches' image stores visible to the next ones' image loads and texel fetches.
void barrier() { glMemoryBarrier(GL_SHADER_IMAGE_ACCESS_BARRIER_BIT | GL_TEXTURE_FETCH_BARRIER_BIT); }

}  // namespace

std::vector<vec2> mirrorBlurTaps(const vec2& wideAxis, float aspect) {
  const float variance =
      0.25f * kMirrorBlurVarianceRatio * (std::max(aspect, 1.0f) * std::max(aspect, 1.0f) - 1.0f);  // texels²
  if (!(variance > 1e-6f) || !(glm::dot(wideAxis, wideAxis) > 0.0f)) return {vec2(0.0f)};
  const int n = std::clamp(int(std::ceil(std::sqrt(12.0f * variance + 1.0f))), 2, kMaxMirrorTaps);
  const float spacing = std::sqrt(12.0f * variance / float(n * n - 1));
  const vec2 axis = glm::normalize(wideAxis);
  std::vector<vec2> taps;
  for (int i = 0; i < n; ++i) taps.push_back((float(i) - 0.5f * float(n - 1)) * spacing * axis);
  return taps;
}

MirrorBlur::MirrorBlur(SunShadows::Compile compile) : compile_(std::move(compile)) {
  const std::string split = std::string(shaders::kLuminanceEncoding) + shaders::kMirrorBlurSplit;
  const std::string up = std::string(shaders::kMirrorBlurUpsample) + shaders::kMirrorBlurUp;
  split_ = compile_("mirror-blur-split", "", {{GL_COMPUTE_SHADER, split.c_str()}});
  down_ = compile_("mirror-blur-down", "", {{GL_COMPUTE_SHADER, shaders::kMirrorBlurDown}});
  up_ = compile_("mirror-blur-up", "", {{GL_COMPUTE_SHADER, up.c_str()}});
  splitRect_ = glGetUniformLocation(split_, "uRect");
  splitWorldFromClip_ = glGetUniformLocation(split_, "uWorldFromClip");
  splitPlane_ = glGetUniformLocation(split_, "uPlane");
  splitEye_ = glGetUniformLocation(split_, "uEye");
  splitAlpha_ = glGetUniformLocation(split_, "uAlpha");
  splitPxPerTan_ = glGetUniformLocation(split_, "uPxPerTan");
  splitTargetPx_ = glGetUniformLocation(split_, "uTargetPx");
  downRegion_ = glGetUniformLocation(down_, "uRegion");
  downFinerRegion_ = glGetUniformLocation(down_, "uFinerRegion");
  downLevel_ = glGetUniformLocation(down_, "uLevel");
  downCoarsest_ = glGetUniformLocation(down_, "uCoarsest");
  upRegion_ = glGetUniformLocation(up_, "uRegion");
  upCoarseRegion_ = glGetUniformLocation(up_, "uCoarseRegion");
  upLevel_ = glGetUniformLocation(up_, "uLevel");
  upTapCount_ = glGetUniformLocation(up_, "uMirrorTapCount");
  upTaps_ = glGetUniformLocation(up_, "uMirrorTaps");
}

MirrorBlur::~MirrorBlur() {
  for (unsigned p : {split_, down_, up_}) glDeleteProgram(p);
  for (Reflector& r : reflectors_) {
    const unsigned textures[] = {r.pyramid, r.passing};
    glDeleteTextures(2, textures);
  }
  glDeleteTextures(1, &depth_);
}

void MirrorBlur::ensure(unsigned& texture, uint32_t& width, uint32_t& height, int& levels, uint32_t widthPx,
                        uint32_t heightPx, int wantLevels, bool depthStencil) {
  if (texture && width >= widthPx && height >= heightPx && levels >= wantLevels) {
    const uint32_t unit = 1u << (wantLevels - 1);
    if (width % unit == 0 && height % unit == 0) return;
  }
  const int n = std::max(levels, wantLevels);
  const uint32_t unit = 1u << (n - 1);
  const uint32_t w = (std::max(width, widthPx) + unit - 1) / unit * unit;
  const uint32_t h = (std::max(height, heightPx) + unit - 1) / unit * unit;
  glDeleteTextures(1, &texture);
  glCreateTextures(GL_TEXTURE_2D, 1, &texture);
  glTextureStorage2D(texture, n, depthStencil ? GL_DEPTH24_STENCIL8 : GL_RGBA32F, GLsizei(w), GLsizei(h));
  if (depthStencil) glTextureParameteri(texture, GL_DEPTH_STENCIL_TEXTURE_MODE, GL_DEPTH_COMPONENT);
  // Read by texelFetch and image loads only.
  glTextureParameteri(texture, GL_TEXTURE_MIN_FILTER, n > 1 ? GL_NEAREST_MIPMAP_NEAREST : GL_NEAREST);
  glTextureParameteri(texture, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  width = w;
  height = h;
  levels = n;
}

void MirrorBlur::split(uint32_t k, unsigned image, unsigned depth, const MirrorRect& rect, uint32_t widthPx,
                       uint32_t heightPx, const MirrorLobe& lobe) {
  // The levels the widest spread needs (λ = log2(2r), r the sky's spread), at least level 0.
  const float widestPx = lobe.pxPerTan > 0.0f ? 2.0f * lobe.alpha * lobe.pxPerTan : 0.25f * float(heightPx);
  const int maxLevels = int(std::floor(std::log2(double(std::max(widthPx, heightPx))))) + 1;
  const int levels = std::clamp(int(std::ceil(std::log2(std::max(2.0f * widestPx, 1.0f)))) + 1, 1, maxLevels);
  if (reflectors_.size() <= k) reflectors_.resize(k + 1);
  Reflector& out = reflectors_[k];
  ensure(out.pyramid, out.width, out.height, out.levels, widthPx, heightPx, levels, false);
  ensure(out.passing, out.passingWidth, out.passingHeight, out.passingLevels, widthPx, heightPx, levels, false);
  ensure(depth_, depthWidth_, depthHeight_, depthLevels_, widthPx, heightPx, 1, true);
  glCopyImageSubData(depth, GL_RENDERBUFFER, 0, rect.x, rect.y, 0, depth_, GL_TEXTURE_2D, 0, rect.x, rect.y, 0,
                     rect.width, rect.height, 1);
  out.taps = mirrorBlurTaps(lobe.wideAxis, lobe.aspect);
  out.rect = rect;
  out.blurLevels = levels;
  out.pending = true;

  glUseProgram(split_);
  glUniform4i(splitRect_, rect.x, rect.y, rect.width, rect.height);
  glUniformMatrix4fv(splitWorldFromClip_, 1, GL_FALSE, &lobe.worldFromClip[0][0]);
  glUniform4fv(splitPlane_, 1, &lobe.planeWorld[0]);
  glUniform4fv(splitEye_, 1, &lobe.eye[0]);
  glUniform1f(splitAlpha_, lobe.alpha);
  glUniform1f(splitPxPerTan_, lobe.pxPerTan);
  glUniform2f(splitTargetPx_, float(widthPx), float(heightPx));
  glBindImageTexture(0, image, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  glBindTextureUnit(0, depth_);
  glBindImageTexture(1, out.pyramid, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(2, out.passing, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  dispatch(uint32_t(rect.width), uint32_t(rect.height));
  barrier();
}

void MirrorBlur::finish() {
  int levels = 0;
  for (const Reflector& r : reflectors_) levels = r.pending ? std::max(levels, r.blurLevels) : levels;

  glUseProgram(down_);
  for (int level = 1; level < levels; ++level) {
    for (const Reflector& out : reflectors_) {
      if (!out.pending || level >= out.blurLevels) continue;
      const Region r = regionAt(out.rect, level);
      setRegion(downRegion_, r);
      setRegion(downFinerRegion_, regionAt(out.rect, level - 1));
      glUniform1f(downLevel_, float(level));
      glUniform1i(downCoarsest_, level == out.blurLevels - 1);
      glBindImageTexture(1, out.pyramid, level, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(2, out.passing, level, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
      glBindImageTexture(3, out.passing, level - 1, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
      dispatch(r.width(), r.height());
    }
    barrier();
  }

  glUseProgram(up_);
  for (int level = levels - 2; level >= 1; --level) {
    for (const Reflector& out : reflectors_) {
      if (!out.pending || level > out.blurLevels - 2) continue;
      const Region r = regionAt(out.rect, level);
      setRegion(upRegion_, r);
      setRegion(upCoarseRegion_, regionAt(out.rect, level + 1));
      glUniform1i(upLevel_, level);
      glUniform1i(upTapCount_, GLint(out.taps.size()));
      glUniform2fv(upTaps_, GLsizei(out.taps.size()), &out.taps[0][0]);
      glBindTextureUnit(1, out.pyramid);
      glBindImageTexture(1, out.pyramid, level, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
      dispatch(r.width(), r.height());
    }
    barrier();
  }
  for (Reflector& out : reflectors_) {
    if (!out.pending) continue;
    const Region fine = regionAt(out.rect, 0), coarse = regionAt(out.rect, 1);
    const int fineRegion[4] = {fine.lo[0], fine.lo[1], fine.hi[0], fine.hi[1]};
    const int region[4] = {coarse.lo[0], coarse.lo[1], coarse.hi[0], coarse.hi[1]};
    const int none[4] = {0, 0, 0, 0};
    std::copy_n(fineRegion, 4, out.fineRegion);
    std::copy_n(out.blurLevels > 1 ? region : none, 4, out.coarseRegion);
    out.pending = false;
  }
}

}  // namespace fly::raster
