#include "base/png_metadata.h"

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

namespace fly {

namespace {

constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
constexpr double kMetresPerInch = 0.0254;

// CRC-32 of the PNG specification (ISO/IEC 15948 Annex D): polynomial 0xEDB88320 (reflected), initial and
// final value 0xFFFFFFFF, over the chunk type and data.
uint32_t crc32(std::string_view bytes) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> t{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1u) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      t[n] = c;
    }
    return t;
  }();
  uint32_t c = 0xFFFFFFFFu;
  for (const char b : bytes) c = table[(c ^ static_cast<uint8_t>(b)) & 0xFFu] ^ (c >> 8);
  return c ^ 0xFFFFFFFFu;
}

void appendBigEndian(std::string& out, uint32_t v) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<char>((v >> shift) & 0xFFu));
}

uint32_t readBigEndian(std::string_view s, size_t at) {
  uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<uint8_t>(s[at + i]);
  return v;
}

// One chunk: length, type, data, CRC (PNG §5.3).
std::string chunk(std::string_view type, std::string_view data) {
  std::string body(type);
  body += data;
  std::string out;
  appendBigEndian(out, static_cast<uint32_t>(data.size()));
  out += body;
  appendBigEndian(out, crc32(body));
  return out;
}

void checkKeyword(const std::string& k) {
  bool ok = !k.empty() && k.size() <= 79 && k.front() != ' ' && k.back() != ' ' &&
            k.find("  ") == std::string::npos;
  for (const char c : k) {
    const auto u = static_cast<uint8_t>(c);
    ok = ok && ((u >= 32 && u <= 126) || u >= 161);
  }
  if (!ok) throw std::invalid_argument("withPngMetadata: invalid PNG text keyword '" + k + "'");
}

bool isAscii(std::string_view s) {
  for (const char c : s) {
    const auto u = static_cast<uint8_t>(c);
    if (u >= 128 || (u < 32 && u != '\n')) return false;
  }
  return true;
}

void checkSignature(std::string_view png, const char* where) {
  if (png.substr(0, kSignature.size()) != kSignature) {
    throw std::invalid_argument(std::string(where) + ": not a PNG file");
  }
}

}  // namespace

std::string withPngMetadata(std::string_view png, const PngMetadata& metadata) {
  checkSignature(png, "withPngMetadata");
  // IHDR is always the first chunk, 13 bytes of data (PNG §11.2.2).
  const size_t ihdrEnd = kSignature.size() + 12 + 13;
  if (png.size() < ihdrEnd || png.substr(kSignature.size() + 4, 4) != "IHDR" ||
      readBigEndian(png, kSignature.size()) != 13) {
    throw std::invalid_argument("withPngMetadata: the PNG does not start with its IHDR chunk");
  }
  if (!(metadata.dotsPerInch >= 0.0) || !(metadata.dotsPerInch <= 1e6)) {
    throw std::invalid_argument("withPngMetadata: dots per inch must be in [0, 10^6]");
  }
  std::string out(png.substr(0, ihdrEnd));
  if (metadata.dotsPerInch > 0.0) {
    const auto perMetre = static_cast<uint32_t>(std::lround(metadata.dotsPerInch / kMetresPerInch));
    std::string data;
    appendBigEndian(data, perMetre);
    appendBigEndian(data, perMetre);
    data.push_back('\1');  // unit: the metre
    out += chunk("pHYs", data);
  }
  for (const auto& [key, value] : metadata.text) {
    checkKeyword(key);
    if (isAscii(value)) {
      out += chunk("tEXt", key + '\0' + value);
    } else {
      // iTXt: keyword, NUL, compression flag 0, method 0, empty language tag and translated keyword, text.
      out += chunk("iTXt", key + std::string("\0\0\0\0\0", 5) + value);
    }
  }
  out += png.substr(ihdrEnd);
  return out;
}

PngMetadata readPngMetadata(std::string_view png) {
  checkSignature(png, "readPngMetadata");
  PngMetadata m;
  size_t at = kSignature.size();
  while (at < png.size()) {
    if (png.size() - at < 12) throw std::invalid_argument("readPngMetadata: truncated chunk");
    const uint32_t length = readBigEndian(png, at);
    if (png.size() - at - 12 < length) throw std::invalid_argument("readPngMetadata: truncated chunk");
    const std::string_view type = png.substr(at + 4, 4);
    const std::string_view data = png.substr(at + 8, length);
    const bool crcOk = readBigEndian(png, at + 8 + length) == crc32(png.substr(at + 4, 4 + length));
    at += 12 + size_t{length};
    if (!crcOk) continue;
    if (type == "IEND") break;
    if (type == "pHYs" && length == 9 && data[8] == '\1') {
      m.dotsPerInch = readBigEndian(data, 0) * kMetresPerInch;
    } else if (type == "tEXt") {
      const size_t nul = data.find('\0');
      if (nul != std::string_view::npos) m.text.emplace_back(data.substr(0, nul), data.substr(nul + 1));
    } else if (type == "iTXt") {
      const size_t nul = data.find('\0');
      if (nul == std::string_view::npos || data.size() < nul + 3 || data[nul + 1] != '\0') continue;
      const size_t language = data.find('\0', nul + 3);
      const size_t translated = language == std::string_view::npos ? language : data.find('\0', language + 1);
      if (translated == std::string_view::npos) continue;
      m.text.emplace_back(data.substr(0, nul), data.substr(translated + 1));
    }
  }
  return m;
}

}  // namespace fly
