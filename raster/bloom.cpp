#include "raster/bloom.h"

#include <epoxy/gl.h>

#include <algorithm>
#include <string>
#include <utility>

#include "raster/shaders/bloom_glsl.h"
#include "raster/shaders/scene_glsl.h"

namespace fly::raster {

namespace {

// The levels from the first (half-resolution) one down while the short side keeps kMinCoarsestPx pixels, at
// most kMaxBloomLevels: the coarsest kernel (±1.5 of its pixels, the tent about the bilinear read) then
// reaches about a fifth of the short side from a point, so a bright spot away from the edges keeps its energy
// in the image; 1280 × 720 gets 6 levels, a glare up to ~200 pixels wide.
constexpr int kMaxBloomLevels = 8;
constexpr uint32_t kMinCoarsestPx = 8;

void dispatch(uint32_t widthPx, uint32_t heightPx) {
  glDispatchCompute((widthPx + 7) / 8, (heightPx + 7) / 8, 1);
  glMemoryBarrier(GL_TEXTURE_FETCH_BARRIER_BIT | GL_SHADER_IMAGE_ACCESS_BARRIER_BIT |
                  GL_TEXTURE_UPDATE_BARRIER_BIT);
}

}  // namespace

Bloom::Bloom(SunShadows::Compile compile) : compile_(std::move(compile)) {
  const std::string head = std::string(shaders::kLuminanceEncoding) + shaders::kBloomBright;
  const std::string down = head + shaders::kBloomDownCompute;
  const std::string up = std::string(shaders::kBloomUpsample) + shaders::kBloomUpCompute;
  const std::string composite = head + shaders::kBloomUpsample + shaders::kBloomCompositeCompute;
  firstDown_ = compile_("bloom-first", "#define FLY_BLOOM_FIRST\n", {{GL_COMPUTE_SHADER, down.c_str()}});
  down_ = compile_("bloom-down", "", {{GL_COMPUTE_SHADER, down.c_str()}});
  up_ = compile_("bloom-up", "", {{GL_COMPUTE_SHADER, up.c_str()}});
  composite_ = compile_("bloom", "", {{GL_COMPUTE_SHADER, composite.c_str()}});
}

Bloom::~Bloom() {
  for (unsigned p : {firstDown_, down_, up_, composite_}) glDeleteProgram(p);
  const unsigned textures[] = {chain_, out_};
  glDeleteTextures(2, textures);
}

void Bloom::resize(uint32_t widthPx, uint32_t heightPx) {
  if (widthPx == width_ && heightPx == height_ && chain_) return;
  const unsigned old[] = {chain_, out_};
  glDeleteTextures(2, old);
  const uint32_t w0 = (widthPx + 1) / 2, h0 = (heightPx + 1) / 2;
  levels_ = 1;
  while (levels_ < kMaxBloomLevels && std::min(w0 >> levels_, h0 >> levels_) >= kMinCoarsestPx) ++levels_;
  glCreateTextures(GL_TEXTURE_2D, 1, &chain_);
  glTextureStorage2D(chain_, levels_, GL_RGBA32F, GLsizei(w0), GLsizei(h0));
  glTextureParameteri(chain_, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_NEAREST);  // one level, bilinear
  glTextureParameteri(chain_, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTextureParameteri(chain_, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTextureParameteri(chain_, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glCreateTextures(GL_TEXTURE_2D, 1, &out_);
  glTextureStorage2D(out_, 1, GL_RG32UI, GLsizei(widthPx), GLsizei(heightPx));
  glTextureParameteri(out_, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
  glTextureParameteri(out_, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
  width_ = widthPx;
  height_ = heightPx;
}

unsigned Bloom::apply(unsigned luminance, uint32_t widthPx, uint32_t heightPx, float exposureScale,
                      const BloomSettings& settings) {
  resize(widthPx, heightPx);
  const float thresholdCdM2 = settings.thresholdExposed / exposureScale;
  auto levelSize = [&](int k) {
    return std::pair{std::max(1u, ((widthPx + 1) / 2) >> k), std::max(1u, ((heightPx + 1) / 2) >> k)};
  };
  // Down: the bright part into level 0, then each level from the one above.
  glUseProgram(firstDown_);
  glUniform1f(glGetUniformLocation(firstDown_, "uThresholdCdM2"), thresholdCdM2);
  glBindImageTexture(0, chain_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
  glBindImageTexture(1, luminance, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  dispatch(levelSize(0).first, levelSize(0).second);
  glUseProgram(down_);
  for (int k = 1; k < levels_; ++k) {
    glBindImageTexture(0, chain_, k, GL_FALSE, 0, GL_WRITE_ONLY, GL_RGBA32F);
    glBindImageTexture(1, chain_, k - 1, GL_FALSE, 0, GL_READ_ONLY, GL_RGBA32F);
    dispatch(levelSize(k).first, levelSize(k).second);
  }
  // Up: each level plus the one below it, upsampled.
  glUseProgram(up_);
  glBindTextureUnit(0, chain_);
  for (int k = levels_ - 2; k >= 0; --k) {
    glUniform1i(glGetUniformLocation(up_, "uCoarseLevel"), k + 1);
    glBindImageTexture(0, chain_, k, GL_FALSE, 0, GL_READ_WRITE, GL_RGBA32F);
    dispatch(levelSize(k).first, levelSize(k).second);
  }
  glUseProgram(composite_);
  glUniform1f(glGetUniformLocation(composite_, "uThresholdCdM2"), thresholdCdM2);
  glUniform1f(glGetUniformLocation(composite_, "uStrength"), settings.strength);
  glUniform1f(glGetUniformLocation(composite_, "uLevelCount"), float(levels_));
  glUniform1i(glGetUniformLocation(composite_, "uCoarseLevel"), 0);
  glBindTextureUnit(0, chain_);
  glBindImageTexture(1, luminance, 0, GL_FALSE, 0, GL_READ_ONLY, GL_RG32UI);
  glBindImageTexture(2, out_, 0, GL_FALSE, 0, GL_WRITE_ONLY, GL_RG32UI);
  dispatch(widthPx, heightPx);
  return out_;
}

}  // namespace fly::raster
