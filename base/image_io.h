// Image files: OpenEXR for physical values (32-bit float, lossless), PNG for display-referred 8-bit images.
// Every write is atomic (base/file_io.h writeFileAtomic): readers see the old file or the whole new one.
// Target fly_image_io, kept out of fly_base so that the GL engine never links OpenEXR (docs/architecture.md).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "base/png_metadata.h"

namespace fly {

// A linear RGB float image: Rec.709 primaries, photometric scale (luminance in cd/m², docs/architecture.md, "Units and frames").
struct ImageRgbF {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // row-major from the top row, 3 floats per pixel; size 3·width·height
};

// String attributes of an EXR header, in the order given: ("units", "cd/m^2"), ("fly:sky", "cie:12") …
using ExrAttributes = std::vector<std::pair<std::string, std::string>>;

// Writes `image` as a scan-line OpenEXR file with FLOAT (32-bit) R, G, B channels, ZIP-compressed (lossless),
// so that every value reads back bit-exactly. `attributes` become string attributes of the header.
// Preconditions (std::invalid_argument, the caller's bug): width, height ≥ 1, width·height ≤ 2^28,
// rgb.size() == 3·width·height, every value finite (no NaN or Inf may reach an output), attribute names
// non-empty and not OpenEXR's own ("channels", "compression" …). Writing fails with std::runtime_error naming
// the path.
void writeExr(const std::filesystem::path& path, const ImageRgbF& image,
              const ExrAttributes& attributes = {});

// Reads the R, G and B channels of an OpenEXR file (HALF, FLOAT or UINT, converted to float) and, when
// `attributes` is not null, its string attributes. A missing, empty, corrupt or non-RGB file, one over
// 2^28 pixels, or one with NaN or Inf in R, G or B is an InputError naming the path.
ImageRgbF readExr(const std::filesystem::path& path, ExrAttributes* attributes = nullptr);

// Writes 8-bit pixels (already encoded for display, e.g. sRGB) as PNG. `pixels`: row-major from the top row,
// `channels` bytes per pixel (1 grey, 2 grey+alpha, 3 RGB, 4 RGBA), width·height·channels bytes in all.
// Preconditions (std::invalid_argument): width, height ≥ 1, width·height ≤ 2^28, channels in 1..4, pixels
// not null. `metadata` (text and print resolution) is written into the file (base/png_metadata.h). Writing
// fails with std::runtime_error naming the path.
void writePng(const std::filesystem::path& path, int width, int height, int channels, const uint8_t* pixels,
              const PngMetadata& metadata = {});

// An 8-bit image as a PNG holds it: row-major from the top row, `channels` bytes per pixel (1..4).
struct ImageU8 {
  int width = 0;
  int height = 0;
  int channels = 0;
  std::vector<uint8_t> pixels;
};

// Reads a PNG file as stored (16-bit samples are reduced to 8 bits); InputError naming the path for a
// missing, empty or corrupt file or one that is not a PNG.
ImageU8 readPng(const std::filesystem::path& path);

}  // namespace fly
