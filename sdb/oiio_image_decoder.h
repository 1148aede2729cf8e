// An ImageDecoder (texture.h) through OpenImageIO: PNG, JPEG, WebP, Radiance HDR, OpenEXR and TIFF. Target
// fly_sdb_images, kept out of fly_sdb so that the GL engine, which links fly_sdb, never links OpenImageIO
// (docs/architecture.md). The fly program installs it for every glTF import (gltf_import.h setImageDecoder).
//
// Conversions: 8-bit samples stay 8-bit; 16- and 32-bit integer samples become 16-bit; float samples (HDR,
// EXR, float TIFF) are clamped to [0, 1] and rounded to 16 bits, because sdb::Texture holds 8- or 16-bit
// values, and every glTF texture slot reads values in [0, 1] (baseColor and emissive as sRGB-encoded values,
// the others as linear ones), which is how the file's numbers are taken: they are not re-encoded. Clamped
// values (and NaN, taken as 0) are counted in a note. Channels beyond the fourth are dropped.
#pragma once

#include "sdb/texture.h"

namespace fly::sdb {

Texture decodeImageOiio(std::span<const uint8_t> encoded, size_t maxBytes, std::vector<std::string>& notes);

// The same decoder in a shared module (target fly_oiio_module, sdb/oiio_image_decoder_module.cpp), which the
// fly program loads with dlopen on the first texture it decodes (cli/image_decoder_module.h): OpenImageIO
// brings some 260 shared libraries, whose loading and relocation cost every run about 0.7 s at start-up,
// textured or not. The module's one exported symbol, kOiioDecoderModuleSymbol, is a function of C linkage
// that returns decodeImageOiio.
using DecodeImageFunction = Texture (*)(std::span<const uint8_t> encoded, size_t maxBytes,
                                        std::vector<std::string>& notes);
inline constexpr const char* kOiioDecoderModuleSymbol = "flyOiioImageDecoder";

// A float image as decoded: RGB per pixel (grey replicated, channels beyond the third dropped), rows from the
// top, the file's values unchanged.
struct FloatRgbImage {
  int width = 0, height = 0;  // pixels
  std::vector<float> rgb;     // 3 per pixel
};
// Decodes a Radiance HDR or OpenEXR file's bytes (values as stored: no clamping, no encoding). Fails with
// std::runtime_error giving the reason: another format, an undecodable file, or one over kMaxTextureDimension
// a side or `maxBytes` of decoded floats. The module's second entry, kOiioFloatModuleSymbol, returns it.
FloatRgbImage decodeFloatImageOiio(std::span<const uint8_t> encoded, size_t maxBytes);
using DecodeFloatImageFunction = FloatRgbImage (*)(std::span<const uint8_t> encoded, size_t maxBytes);
inline constexpr const char* kOiioFloatModuleSymbol = "flyOiioFloatImageDecoder";

}  // namespace fly::sdb
