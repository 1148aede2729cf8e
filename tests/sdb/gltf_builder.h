// Test helper: writes small glTF 2.0 files from code (.gltf with an embedded or external buffer, or .glb), so
// that each importer test states its input next to its expectations.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>
#include <vector>

namespace fly::test {

// A fresh directory under the system temporary directory, removed with everything in it at destruction.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() /
            ("fly-gltf-test-" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& name) const { return path_ / name; }

 private:
  std::filesystem::path path_;
};

inline void writeBytes(const std::filesystem::path& file, const void* data, size_t size) {
  std::ofstream out(file, std::ios::binary);
  out.write(static_cast<const char*>(data), std::streamsize(size));
}

inline void writeText(const std::filesystem::path& file, const std::string& text) {
  writeBytes(file, text.data(), text.size());
}

inline std::string base64(const std::vector<uint8_t>& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    const uint32_t b0 = bytes[i];
    const uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0u;
    const uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0u;
    const uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

// An RGB PNG (ISO/IEC 15948) with 8 or 16 bits per channel, its image data in uncompressed ("stored") deflate
// blocks, so that tests can state pixel values exactly.
inline std::vector<uint8_t> png(int width, int height, const std::vector<uint16_t>& rgb, int bits = 8) {
  auto crc32 = [](const uint8_t* p, size_t n, uint32_t crc) {
    crc = ~crc;
    for (size_t i = 0; i < n; ++i) {
      crc ^= p[i];
      for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
    }
    return ~crc;
  };
  std::vector<uint8_t> out = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
  auto be32 = [](std::vector<uint8_t>& v, uint32_t x) {
    for (int k = 3; k >= 0; --k) v.push_back(uint8_t(x >> (8 * k)));
  };
  auto chunk = [&](const char* type, const std::vector<uint8_t>& data) {
    be32(out, uint32_t(data.size()));
    std::vector<uint8_t> typed(type, type + 4);
    typed.insert(typed.end(), data.begin(), data.end());
    out.insert(out.end(), typed.begin(), typed.end());
    be32(out, crc32(typed.data(), typed.size(), 0));
  };
  std::vector<uint8_t> header;
  be32(header, uint32_t(width));
  be32(header, uint32_t(height));
  header.insert(header.end(), {uint8_t(bits), 2, 0, 0, 0});  // colour type 2 = RGB
  chunk("IHDR", header);
  std::vector<uint8_t> raw;  // each row: filter type 0, then the samples (16-bit ones big-endian)
  size_t s = 0;
  for (int y = 0; y < height; ++y) {
    raw.push_back(0);
    for (int x = 0; x < width * 3; ++x, ++s) {
      if (bits == 16) raw.push_back(uint8_t(rgb[s] >> 8));
      raw.push_back(uint8_t(rgb[s] & 0xff));
    }
  }
  std::vector<uint8_t> z = {0x78, 0x01};  // zlib header: deflate, 32 KiB window
  for (size_t i = 0; i < raw.size() || i == 0; i += 65535) {
    const size_t n = std::min<size_t>(65535, raw.size() - i);
    z.push_back(i + n >= raw.size() ? 1 : 0);  // BFINAL, BTYPE = 00 (stored)
    z.insert(z.end(), {uint8_t(n), uint8_t(n >> 8), uint8_t(~n), uint8_t(~n >> 8)});
    z.insert(z.end(), raw.begin() + std::ptrdiff_t(i), raw.begin() + std::ptrdiff_t(i + n));
  }
  uint32_t a = 1, b = 0;  // Adler-32 of the uncompressed data
  for (uint8_t c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  be32(z, (b << 16) | a);
  chunk("IDAT", z);
  chunk("IEND", {});
  return out;
}

// Builds one glTF document with a single buffer.
class GltfBuilder {
 public:
  using json = nlohmann::json;

  json doc = {{"asset", {{"version", "2.0"}}}};
  std::vector<uint8_t> bin;          // the bytes of buffer 0
  json moreBuffers = json::array();  // buffers 1, 2 … as given (e.g. EXT_meshopt_compression fallbacks)

  // Appends bytes as a buffer view (4-byte aligned); returns its index.
  int view(const void* data, size_t size, size_t byteStride = 0) {
    while (bin.size() % 4) bin.push_back(0);
    const size_t offset = bin.size();
    bin.resize(offset + size);
    std::memcpy(bin.data() + offset, data, size);
    json v = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}};
    if (byteStride) v["byteStride"] = byteStride;
    return append("bufferViews", v);
  }
  template <class T>
  int view(const std::vector<T>& values, size_t byteStride = 0) {
    return view(values.data(), values.size() * sizeof(T), byteStride);
  }

  int accessor(int bufferView, int componentType, size_t count, const std::string& type,
               bool normalized = false, size_t byteOffset = 0) {
    json a = {{"componentType", componentType}, {"count", count}, {"type", type}};
    if (bufferView >= 0) a["bufferView"] = bufferView;
    if (byteOffset) a["byteOffset"] = byteOffset;
    if (normalized) a["normalized"] = true;
    return append("accessors", a);
  }

  // A view and a tightly packed accessor over `values`; `componentType` must match T.
  template <class T>
  int data(const std::vector<T>& values, int componentType, const std::string& type,
           bool normalized = false) {
    const size_t components = type == "SCALAR" ? 1 : type == "VEC2" ? 2 : type == "VEC3" ? 3 : 4;
    return accessor(view(values), componentType, values.size() / components, type, normalized);
  }
  int floats(const std::vector<float>& values, const std::string& type) { return data(values, 5126, type); }
  int indices(const std::vector<uint32_t>& values) { return data(values, 5125, "SCALAR"); }

  // A mesh of the given primitives (each {"attributes": ..., "indices": ..., "mode": ..., "material": ...}).
  int mesh(const json& primitives, const std::string& name = "") {
    json m = {{"primitives", primitives}};
    if (!name.empty()) m["name"] = name;
    return append("meshes", m);
  }
  // A single-primitive mesh over positions (and optional indices).
  int triangles(const std::vector<float>& positions, const std::vector<uint32_t>& idx = {},
                const std::string& name = "", int material = -1) {
    json p = {{"attributes", {{"POSITION", floats(positions, "VEC3")}}}};
    if (!idx.empty()) p["indices"] = indices(idx);
    if (material >= 0) p["material"] = material;
    return mesh(json::array({p}), name);
  }

  int node(const json& n) { return append("nodes", n); }
  int material(const json& m) { return append("materials", m); }
  int append(const std::string& array, const json& value) {
    doc[array].push_back(value);
    return int(doc[array].size() - 1);
  }
  void scene(const std::vector<int>& roots) {
    doc["scenes"] = json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }
  void useExtension(const std::string& name, bool required = false) {
    doc["extensionsUsed"].push_back(name);
    if (required) doc["extensionsRequired"].push_back(name);
  }

  // .gltf with the buffer as a base64 data URI.
  void writeGltf(const std::filesystem::path& file) const {
    json d = doc;
    if (!bin.empty()) {
      d["buffers"] = json::array(
          {{{"byteLength", bin.size()}, {"uri", "data:application/octet-stream;base64," + base64(bin)}}});
    }
    for (const json& extra : moreBuffers) d["buffers"].push_back(extra);
    writeText(file, d.dump(1));
  }

  // .gltf with the buffer in a .bin file next to it.
  void writeGltfWithBin(const std::filesystem::path& file) const {
    const std::filesystem::path binFile = std::filesystem::path(file).replace_extension(".bin");
    json d = doc;
    d["buffers"] = json::array({{{"byteLength", bin.size()}, {"uri", binFile.filename().string()}}});
    for (const json& extra : moreBuffers) d["buffers"].push_back(extra);
    writeText(file, d.dump(1));
    writeBytes(binFile, bin.data(), bin.size());
  }

  // .glb (glTF 2.0 §4): header, JSON chunk padded with spaces, BIN chunk padded with zeros.
  std::vector<uint8_t> glb() const {
    json d = doc;
    std::vector<uint8_t> payload = bin;
    while (payload.size() % 4) payload.push_back(0);
    if (!payload.empty()) d["buffers"] = json::array({{{"byteLength", bin.size()}}});
    for (const json& extra : moreBuffers) d["buffers"].push_back(extra);
    std::string text = d.dump();
    while (text.size() % 4) text += ' ';
    std::vector<uint8_t> out = {'g', 'l', 'T', 'F'};
    auto u32 = [&out](uint32_t v) {
      for (int k = 0; k < 4; ++k) out.push_back(uint8_t(v >> (8 * k)));
    };
    const size_t length = 12 + 8 + text.size() + (payload.empty() ? 0 : 8 + payload.size());
    u32(2);
    u32(uint32_t(length));
    u32(uint32_t(text.size()));
    u32(0x4E4F534A);  // "JSON"
    out.insert(out.end(), text.begin(), text.end());
    if (!payload.empty()) {
      u32(uint32_t(payload.size()));
      u32(0x004E4942);  // "BIN\0"
      out.insert(out.end(), payload.begin(), payload.end());
    }
    return out;
  }
  void writeGlb(const std::filesystem::path& file) const {
    const std::vector<uint8_t> bytes = glb();
    writeBytes(file, bytes.data(), bytes.size());
  }
};

}  // namespace fly::test
