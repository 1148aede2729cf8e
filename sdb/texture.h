// Image textures referenced by materials, decoded to 8- or 16-bit channels.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <vector>

#include "base/math.h"
#include "sdb/ids.h"

namespace fly::sdb {

struct Texture {
  std::string name;
  std::string sourcePath;  // file it was read from, or "<embedded>" for glTF buffer views and data URIs
  int width = 0;           // pixels
  int height = 0;          // pixels
  int channels = 0;        // 1..4
  int bitsPerChannel = 8;  // 8 or 16
  std::vector<uint8_t> pixels;  // row-major from the top row, channels interleaved (16-bit: native-endian pairs)
};

// Largest width or height of an imported texture in pixels: the smallest GL_MAX_TEXTURE_SIZE OpenGL 4.5
// allows (OpenGL 4.5 core specification, table 23.53), so every texture fits every GL 4.5 implementation.
inline constexpr int kMaxTextureDimension = 16384;

// Decodes the bytes of an image file into a Texture with 4 channels (RGBA; grey is replicated, a missing
// alpha is 1) of 8 or 16 bits; `name` and `sourcePath` are left to the caller. Fails with std::runtime_error
// giving the reason when it cannot, and before allocating the pixels when the image is wider or higher than
// kMaxTextureDimension or its decoded pixels would take more than `maxBytes`. `notes` receives conversions a
// user should know of (e.g. float values clamped to [0, 1]).
using ImageDecoder = std::function<Texture(std::span<const uint8_t> encoded, size_t maxBytes,
                                           std::vector<std::string>& notes)>;

// KHR_texture_transform: uv' = T(offset) · R(rotation) · S(scale) · uv, as the extension defines it.
struct UvTransform {
  vec2 offset{0.0f};
  float rotationRad = 0.0f;  // counter-clockwise in UV space
  vec2 scale{1.0f};

  bool isIdentity() const { return offset == vec2(0.0f) && rotationRad == 0.0f && scale == vec2(1.0f); }
};

// How a texture coordinate outside [0, 1] maps into the image (glTF 2.0 §5.26 "sampler", wrapS / wrapT).
enum class WrapMode : uint8_t {
  kRepeat,          // the image tiles: u − floor(u) (glTF's default, REPEAT = 10497)
  kClampToEdge,     // the edge texels extend outwards (CLAMP_TO_EDGE = 33071)
  kMirroredRepeat,  // the image tiles, every other copy mirrored (MIRRORED_REPEAT = 33648)
};

// How a texture is sampled where one texel covers more than a pixel or sample point (glTF 2.0 §5.26
// "sampler", magFilter; undefined in the file means linear).
enum class MagFilter : uint8_t {
  kLinear,   // bilinear between the four nearest texels (LINEAR = 9729)
  kNearest,  // the texel the point falls in (NEAREST = 9728): pixel art, masks with hard edges
};

// How a texture is sampled where a pixel covers many texels (glTF 2.0 §5.26, minFilter; undefined in the file
// means trilinear). The GL engine uses it as given; the baker samples points and uses magFilter only.
enum class MinFilter : uint8_t {
  kNearest,               // NEAREST = 9728, no mipmaps
  kLinear,                // LINEAR = 9729, no mipmaps
  kNearestMipmapNearest,  // 9984
  kLinearMipmapNearest,   // 9985
  kNearestMipmapLinear,   // 9986
  kLinearMipmapLinear,    // 9987 (trilinear)
};

// A material's use of a texture. Invalid (no texture) when `texture` is 0.
struct TextureRef {
  TextureId texture;
  int texCoord = 0;  // which UV set: 0 = UV0 (TEXCOORD_0), 1 = UV1 (TEXCOORD_1)
  UvTransform transform;
  WrapMode wrapS = WrapMode::kRepeat;  // along u (the image's columns)
  WrapMode wrapT = WrapMode::kRepeat;  // along v (the image's rows)
  MagFilter magFilter = MagFilter::kLinear;
  MinFilter minFilter = MinFilter::kLinearMipmapLinear;

  explicit operator bool() const { return static_cast<bool>(texture); }
};

}  // namespace fly::sdb
