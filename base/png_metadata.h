// Settings and print resolution carried inside a PNG file (ISO/IEC 15948, the PNG specification): text
// chunks (tEXt for Latin-1-safe ASCII values, iTXt for UTF-8) and the physical pixel size (pHYs), inserted
// after the image header of an encoded PNG, whatever encoder wrote it (cairo, stb_image_write).
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fly {

struct PngMetadata {
  // Keyword, value pairs in the order written. Keywords are 1–79 printable Latin-1 characters without
  // leading, trailing or double spaces (PNG §11.3.4.2): "Software", "fly:command", "fly:sky" …; values are
  // UTF-8.
  std::vector<std::pair<std::string, std::string>> text;
  // Print resolution, dots (pixels) per inch; 0 = none written (pHYs stores pixels per metre, rounded).
  double dotsPerInch = 0.0;
};

// `png` (a whole PNG file) with the metadata's chunks inserted after IHDR. std::invalid_argument when `png`
// is not a PNG that starts with IHDR, a keyword is not valid, or dotsPerInch is negative, not finite or over
// 10^6 dpi.
std::string withPngMetadata(std::string_view png, const PngMetadata& metadata);

// The text chunks (tEXt, iTXt uncompressed) and pHYs resolution of a PNG file, in file order; chunks with a
// bad CRC or compressed text are skipped. std::invalid_argument when `png` is not a PNG or is truncated.
PngMetadata readPngMetadata(std::string_view png);

}  // namespace fly
