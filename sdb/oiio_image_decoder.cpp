#include "sdb/oiio_image_decoder.h"

#include <OpenImageIO/filesystem.h>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace fly::sdb {

namespace {

// The file extension that names the format to OpenImageIO, from the file's signature.
const char* formatExtension(std::span<const uint8_t> b) {
  auto starts = [&](std::initializer_list<uint8_t> sig, size_t at = 0) {
    return b.size() >= at + sig.size() && std::equal(sig.begin(), sig.end(), b.begin() + std::ptrdiff_t(at));
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return "png";
  if (starts({0xff, 0xd8, 0xff})) return "jpg";
  if (starts({'R', 'I', 'F', 'F'}) && starts({'W', 'E', 'B', 'P'}, 8)) return "webp";
  if (starts({0x76, 0x2f, 0x31, 0x01})) return "exr";
  if (starts({'#', '?'})) return "hdr";
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42})) return "tif";
  return nullptr;
}

std::string oiioError(const OIIO::ImageInput* in) {
  std::string e = in ? in->geterror() : OIIO::geterror();
  while (!e.empty() && (e.back() == '\n' || e.back() == '.')) e.pop_back();
  return e.empty() ? "OpenImageIO gave no reason" : e;
}

// Opens `encoded` for reading through `proxy`; std::runtime_error when it cannot.
std::unique_ptr<OIIO::ImageInput> openImage(const char* extension,
                                            OIIO::Filesystem::IOMemReader& proxy, OIIO::ImageSpec& spec) {
  auto in = OIIO::ImageInput::create(extension);
  if (!in) throw std::runtime_error("OpenImageIO has no reader for it: " + oiioError(nullptr));
  if (!in->supports("ioproxy") || !in->set_ioproxy(&proxy)) {
    throw std::runtime_error(std::string("OpenImageIO's reader for ") + in->format_name() +
                             " cannot read from memory");
  }
  // Colour as stored, not multiplied by alpha (OpenImageIO's default for PNG): glTF's base colour and its
  // alpha are separate quantities (glTF 2.0 §3.9.2; an OPAQUE material ignores alpha altogether).
  OIIO::ImageSpec config;
  config.attribute("oiio:UnassociatedAlpha", 1);
  if (!in->open(std::string("memory.") + extension, spec, config))
    throw std::runtime_error("it cannot be decoded: " + oiioError(in.get()));
  if (spec.width <= 0 || spec.height <= 0 || spec.nchannels <= 0 || spec.depth > 1) {
    throw std::runtime_error("it has no pixels (" + std::to_string(spec.width) + " × " +
                             std::to_string(spec.height) + " px, " + std::to_string(spec.nchannels) +
                             " channels)");
  }
  return in;
}

}  // namespace

FloatRgbImage decodeFloatImageOiio(std::span<const uint8_t> encoded, size_t maxBytes) {
  const char* extension = formatExtension(encoded);
  if (!extension || (std::strcmp(extension, "hdr") != 0 && std::strcmp(extension, "exr") != 0)) {
    throw std::runtime_error(std::string("it is ") + (extension ? std::string("a .") + extension + " image" : "no image") +
                             ", not a Radiance HDR or OpenEXR one");
  }
  OIIO::Filesystem::IOMemReader proxy(encoded.data(), encoded.size());
  OIIO::ImageSpec spec;
  auto in = openImage(extension, proxy, spec);
  const size_t pixels = size_t(spec.width) * size_t(spec.height);
  const int used = std::min(spec.nchannels, 3);
  if (spec.width > kMaxTextureDimension || spec.height > kMaxTextureDimension ||
      pixels * size_t(used + 3) * sizeof(float) > maxBytes) {
    throw std::runtime_error("it is " + std::to_string(spec.width) + " × " + std::to_string(spec.height) +
                             " px, over the budget (at most " + std::to_string(kMaxTextureDimension) +
                             " px a side and " + std::to_string(maxBytes) + " bytes of decoded pixels)");
  }
  std::vector<float> file(pixels * size_t(used));
  if (!in->read_image(0, 0, 0, used, OIIO::TypeDesc::FLOAT, file.data()))
    throw std::runtime_error("it cannot be decoded: " + oiioError(in.get()));
  FloatRgbImage image;
  image.width = spec.width;
  image.height = spec.height;
  image.rgb.resize(pixels * 3);
  for (size_t p = 0; p < pixels; ++p) {
    for (int c = 0; c < 3; ++c) image.rgb[3 * p + size_t(c)] = file[p * size_t(used) + size_t(used == 3 ? c : 0)];
  }
  return image;
}

Texture decodeImageOiio(std::span<const uint8_t> encoded, size_t maxBytes, std::vector<std::string>& notes) {
  const char* extension = formatExtension(encoded);
  if (!extension) throw std::runtime_error("it is not a PNG, JPEG, WebP, HDR, EXR or TIFF image");
  OIIO::Filesystem::IOMemReader proxy(encoded.data(), encoded.size());
  OIIO::ImageSpec spec;
  auto in = openImage(extension, proxy, spec);
  const int width = spec.width, height = spec.height, fileChannels = spec.nchannels;
  const OIIO::TypeDesc::BASETYPE base = OIIO::TypeDesc::BASETYPE(spec.format.basetype);
  const bool isFloat =
      base == OIIO::TypeDesc::HALF || base == OIIO::TypeDesc::FLOAT || base == OIIO::TypeDesc::DOUBLE;
  const int bits = base == OIIO::TypeDesc::UINT8 || base == OIIO::TypeDesc::INT8 ? 8 : 16;
  const size_t bytesPerSample = size_t(bits / 8);
  const size_t pixels = size_t(width) * size_t(height);
  if (width > kMaxTextureDimension || height > kMaxTextureDimension ||
      pixels * 4 * bytesPerSample > maxBytes) {
    throw std::runtime_error("it is " + std::to_string(width) + " × " + std::to_string(height) +
                             " px, over the import budget (at most " + std::to_string(kMaxTextureDimension) +
                             " px a side and " + std::to_string(maxBytes) + " bytes of decoded pixels left)");
  }
  const int used = std::min(fileChannels, 4);
  Texture t;
  t.width = width;
  t.height = height;
  t.channels = 4;
  t.bitsPerChannel = bits;
  t.pixels.resize(pixels * 4 * bytesPerSample);

  // Reads the first `used` channels as `type`, then spreads them to RGBA.
  auto expand = [&](auto* rgba, const auto* file, auto one) {
    for (size_t p = 0; p < pixels; ++p) {
      const auto* s = file + p * size_t(used);
      auto* d = rgba + 4 * p;
      if (used <= 2) {
        d[0] = d[1] = d[2] = s[0];
        d[3] = used == 2 ? s[1] : one;
      } else {
        d[0] = s[0];
        d[1] = s[1];
        d[2] = s[2];
        d[3] = used == 4 ? s[3] : one;
      }
    }
  };
  if (isFloat) {
    std::vector<float> file(pixels * size_t(used));
    if (!in->read_image(0, 0, 0, used, OIIO::TypeDesc::FLOAT, file.data())) {
      throw std::runtime_error("it cannot be decoded: " + oiioError(in.get()));
    }
    size_t clamped = 0;
    float largest = 0.0f;
    std::vector<uint16_t> quantised(file.size());
    for (size_t k = 0; k < file.size(); ++k) {
      float v = file[k];
      if (!(v >= 0.0f && v <= 1.0f)) {
        ++clamped;
        if (v > largest) largest = v;
        v = std::isnan(v) ? 0.0f : std::clamp(v, 0.0f, 1.0f);
      }
      quantised[k] = uint16_t(std::lround(v * 65535.0f));
    }
    auto* rgba = reinterpret_cast<uint16_t*>(t.pixels.data());
    expand(rgba, quantised.data(), uint16_t(65535));
    if (clamped) {
      std::ostringstream s;
      s << clamped << " of its " << file.size() << " float values lie outside [0, 1] (the largest is "
        << largest << ") and were clamped, since textures hold values in [0, 1]";
      notes.push_back(s.str());
    }
  } else if (bits == 8) {
    std::vector<uint8_t> file(pixels * size_t(used));
    if (!in->read_image(0, 0, 0, used, OIIO::TypeDesc::UINT8, file.data())) {
      throw std::runtime_error("it cannot be decoded: " + oiioError(in.get()));
    }
    expand(t.pixels.data(), file.data(), uint8_t(255));
  } else {
    std::vector<uint16_t> file(pixels * size_t(used));
    if (!in->read_image(0, 0, 0, used, OIIO::TypeDesc::UINT16, file.data())) {
      throw std::runtime_error("it cannot be decoded: " + oiioError(in.get()));
    }
    expand(reinterpret_cast<uint16_t*>(t.pixels.data()), file.data(), uint16_t(65535));
  }
  return t;
}

}  // namespace fly::sdb
