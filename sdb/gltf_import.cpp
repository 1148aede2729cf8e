// glTF 2.0 import (what is converted: gltf_import.h).
//
// Material approximation: glTF metallic-roughness → the realistic material
// ------------------------------------------------------------------------
// glTF's material is a mix of two BRDFs (glTF 2.0 specification, Appendix B "BRDF Implementation"):
//   material        = mix(dielectric_brdf, metal_brdf, metallic)
//   dielectric_brdf = fresnel_mix(ior, base = diffuse_brdf(baseColor), layer = specular_brdf(α = roughness²))
//   metal_brdf      = conductor_fresnel(f0 = baseColor, bsdf = specular_brdf(α = roughness²))
// The realistic material (material.h) has one Lambertian diffuse term and one reflection lobe whose amount is
// either Fresnel (reflectionColor × Schlick(F0(ior))) or uniform (reflectionColor); its energy rule takes
// reflection first, then transmission, then diffuse. The conversion:
//  - reflectionGlossiness = roughness: both are the perceptual parameter whose square is the GGX width α. The
//    green (roughness) channel of metallicRoughnessTexture becomes reflectionGlossinessTexture.
//  - metalness: where the blue channel of metallicRoughnessTexture varies, the material is the dielectric
//    below (metallic = 0) and the blue channel becomes metalnessTexture with metalnessFactor = metallicFactor:
//    each texel m mixes it with a uniform reflector of the base colour (Material::metalnessTexture): glTF's
//    mix at normal incidence, R0 = mix(F0_dielectric, baseColor × texel, m), exactly; towards grazing angles
//    the dielectric's share rises as Schlick's F and the metal's stays at its colour (as a metal below).
//    Where the blue channel is constant (or there is no texture: 1), metallic = metallicFactor × its value
//    and the material is a dielectric or a metal as a whole:
//  - metallic < 0.5 (dielectric): reflectionModel = Fresnel with ior from KHR_materials_ior (default 1.5);
//    reflectionColor = min(specularColorFactor, 1) × specularFactor (KHR_materials_specular: the dielectric
//    F0 is min(F0(ior) × specularColor, 1) × specular, so at normal incidence fly's reflectionColor × F0(ior)
//    is the same); diffuseColor = (1 − metallic) × baseColor, the dielectric lobe's weight in the mix. The
//    metal share of the reflection (metallic × baseColor) is lost.
//  - metallic ≥ 0.5 (metal): reflectionModel = uniform; reflectionColor = mix(F0_dielectric, baseColor,
//    metallic), the mix's reflectance at normal incidence (F0_dielectric as above); diffuseColor =
//    (1 − metallic) × baseColor. For metallic = 1 this is glTF's conductor at normal incidence (reflection =
//    baseColor, no diffuse); the Schlick rise towards white at grazing angles is lost.
//  - baseColorTexture → diffuseTexture (sRGB), and for a metal also → reflectionTexture (sRGB,
//    Material::reflectionTextureSrgb): the reflection per texel is mix(F0_dielectric, baseColor, metallic) ×
//    texel, which is glTF's mix(F0_dielectric, baseColor × texel, metallic) exactly for metallic = 1 and
//    within (1 − metallic) × F0_dielectric ≤ 0.02 of it otherwise.
//  - KHR_materials_transmission: transmissionColor = baseColor × transmissionFactor × (1 − metallic) (the
//  BTDF
//    replaces the diffuse lobe of the dielectric part only); the red channel of transmissionTexture becomes
//    transmissionTexture; transmissionGlossiness = roughness (the same microfacets reflect and refract).
//  - KHR_materials_volume: attenuationColor and attenuationDistance are Beer–Lambert parameters with the same
//    meaning as scatteringColor and scatteringDistanceM. thicknessFactor is not needed: fly traces the
//    geometry.
//  - alphaMode, alphaCutoff and baseColorFactor's alpha → Material::alphaMode, alphaCutoff and opacity; the
//    alpha channel of baseColorTexture (diffuseTexture) and of COLOR_0 multiply the coverage per point.
//  - emissionLuminance = emissiveFactor × KHR_materials_emissive_strength, in cd/m² (docs/architecture.md, "Units and
//    frames"); without the extension emissiveFactor is a display colour (Material::emissionDisplay);
//    emissiveTexture → emissionTexture (sRGB).
//  - normalTexture → bumpTexture with bumpScale = normalTexture.scale.
//  - occlusionTexture is ignored: the baker computes occlusion from the geometry.
//  - doubleSided → Material::doubleSided and Mesh::twoSided.
//  - KHR_materials_clearcoat → applyClearCoat and KHR_materials_sheen → applySheen (material_layers.h, where
//    the approximations are stated); when the coat is the lobe, clearcoatTexture (red) → reflectionTexture
//    and clearcoatRoughnessTexture (green) → reflectionGlossinessTexture.
//  - KHR_materials_anisotropy → reflectionGlossiness, anisotropyU / V and the rotation, as constants or as
//    textures converted per texel from anisotropyTexture and metallicRoughnessTexture's roughness
//    (gltf_anisotropy.h, where the mapping and its one limit, a width ratio of at most 10, are stated).
//  - A primitive without a material gets fly's default material (Material{}, a light grey paint, named
//    "default") rather than glTF's default (§3.9.6: a white rough metal), which would act as a blurred mirror
//    in a bake.
// Sources: glTF 2.0 specification §3.9 "Materials" and Appendix B
// (https://registry.khronos.org/glTF/specs/2.0/glTF-2.0.html); the Khronos extension specifications
// KHR_materials_transmission, KHR_materials_volume, KHR_materials_ior, KHR_materials_specular,
// KHR_materials_emissive_strength, KHR_materials_clearcoat, KHR_materials_sheen, KHR_materials_anisotropy,
// KHR_materials_variants, KHR_texture_transform, KHR_lights_punctual, KHR_draco_mesh_compression and
// KHR_texture_basisu
// (https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Khronos), EXT_meshopt_compression and
// EXT_texture_webp (https://github.com/KhronosGroup/glTF/tree/main/extensions/2.0/Vendor).
//
// Textures are decoded by the installed ImageDecoder (setImageDecoder; the fly program's reads PNG, JPEG,
// WebP, HDR, EXR and TIFF through OpenImageIO) or else by tinygltf's stb_image loader (PNG and JPEG, the
// formats glTF 2.0 §3.8.2 allows), into RGBA with 8 or 16 bits per channel. A single channel that a material
// parameter reads (roughness = green, metalness = blue, transmission and clear coat = red) is copied into a
// one-channel (grey) texture of its own.
//
// Import budget (GltfImportOptions::maxDecodedBytes, kMaxTextureDimension): every accessor, decoded meshopt
// view and image is charged its decoded size from what the file declares (accessor counts, image headers)
// before it is decoded, so a file that claims more fails with an InputError instead of an allocation.
//
// The import is all or nothing: everything is converted and checked first, then added to the Scene, so an
// InputError leaves the scene as it was.
#include "sdb/gltf_import.h"

#include <tiny_gltf.h>

#include "sdb/draco_decode.h"
#include "sdb/gltf_anisotropy.h"
#include "sdb/gltf_files.h"
#include "sdb/material_layers.h"
#include "sdb/meshopt_decode.h"

#include <algorithm>
#include <array>
#include <bit>
#include <cctype>
#include <cerrno>
#include <climits>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <numeric>
#include <optional>
#include <regex>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string_view>
#include <utility>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "base/error.h"
#include "base/file_io.h"
#include "base/log.h"

namespace fly::sdb {

namespace {

namespace fs = std::filesystem;

static_assert(std::endian::native == std::endian::little,
              "glTF buffers are little-endian (glTF 2.0 §3.6.2.2)");

// Extensions whose content the importer converts (see the comment block above and gltf_import.h).
// KHR_mesh_quantization only widens the component types allowed for attributes, which readAccessor handles.
// KHR_materials_variants: the default materials (those without a variant) are imported.
constexpr std::array<std::string_view, 15> kSupportedExtensions = {"EXT_meshopt_compression",
                                                                   "KHR_draco_mesh_compression",
                                                                   "KHR_lights_punctual",
                                                                   "KHR_materials_anisotropy",
                                                                   "KHR_materials_clearcoat",
                                                                   "KHR_materials_emissive_strength",
                                                                   "KHR_materials_ior",
                                                                   "KHR_materials_sheen",
                                                                   "KHR_materials_specular",
                                                                   "KHR_materials_transmission",
                                                                   "KHR_materials_variants",
                                                                   "KHR_materials_volume",
                                                                   "KHR_mesh_quantization",
                                                                   "KHR_texture_transform",
                                                                   "EXT_texture_webp"};

const ImageDecoder& installedImageDecoder();

// EXT_texture_webp needs an image decoder that reads WebP (the fly program installs one).
bool isSupportedExtension(const std::string& name) {
  if (name == "EXT_texture_webp" && !installedImageDecoder()) return false;
  return std::find(kSupportedExtensions.begin(), kSupportedExtensions.end(), name) !=
         kSupportedExtensions.end();
}

// What fly does with extensions it does not convert, and what a user whose file requires one can do.
struct UnsupportedExtension {
  std::string_view name;
  std::string_view ignored;  // what is lost when the file only uses it (a warning)
  std::string_view hint;     // how to get a file fly reads when the file requires it
};
constexpr std::array<UnsupportedExtension, 8> kUnsupportedExtensions = {{
    {"EXT_texture_webp",
     "its WebP textures are not decoded (no image decoder that reads WebP is installed); "
     "the fallback PNG or JPEG images are used where the file gives them",
     "use the fly program, which decodes WebP through OpenImageIO, or convert the textures to PNG or JPEG"},
    {"KHR_texture_basisu",
     "its KTX2 (Basis Universal) textures are not decoded; the fallback PNG or JPEG "
     "images are used where the file gives them",
     "convert the KTX2 textures to PNG or JPEG (e.g. with KTX-Software's `ktx extract`) and refer to those"},
    {"KHR_materials_unlit",
     "unlit materials are shaded as lit, with their base colour as the diffuse colour "
     "(fly computes physical light, and an unlit surface has none)",
     "export the materials as ordinary metallic-roughness materials"},
    {"KHR_materials_iridescence", "the thin-film iridescence is ignored", "export the file without it"},
    {"KHR_materials_dispersion", "dispersion is ignored (one ior for all wavelengths)",
     "export the file without it"},
    {"KHR_materials_diffuse_transmission", "diffuse transmission is ignored (the surface is opaque there)",
     "export the file without it"},
    {"EXT_mesh_gpu_instancing", "the instances are not imported (only each node's own mesh)",
     "export the file with instancing resolved into ordinary nodes (e.g. glTF-Transform's `flatten`/"
     "`uninstance`)"},
    {"KHR_materials_pbrSpecularGlossiness",
     "specular-glossiness materials are read as their fallback "
     "metallic-roughness ones",
     "convert the materials to metallic-roughness (e.g. glTF-Transform's `metalrough`)"},
}};

const UnsupportedExtension* findUnsupported(const std::string& name) {
  for (const UnsupportedExtension& e : kUnsupportedExtensions) {
    if (e.name == name) return &e;
  }
  return nullptr;
}

const char* const kHintInvalid =
    "the file does not follow the glTF 2.0 specification; check it with the Khronos glTF Validator "
    "(https://github.khronos.org/glTF-Validator) or export it again";
const char* const kHintTruncated =
    "the file or its binary data was cut off or does not belong to it; copy or export it again";

std::string str(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// "'Wall'" for a named element, "" for an unnamed one.
std::string quotedName(const std::string& name) {
  return name.empty() ? std::string() : " '" + name + "'";
}

// Saturating a + b × c on sizes from the file, so that range checks cannot overflow.
size_t satMulAdd(size_t a, size_t b, size_t c) {
  size_t product = 0;
  size_t sum = 0;
  if (__builtin_mul_overflow(b, c, &product) || __builtin_add_overflow(a, product, &sum)) return SIZE_MAX;
  return sum;
}

// RFC 3986 percent-decoding of a relative URI (glTF 2.0, "URIs"), e.g. "my%20wall.png" → "my wall.png".
std::string percentDecode(const std::string& uri) {
  std::string out;
  for (size_t i = 0; i < uri.size(); ++i) {
    if (uri[i] == '%' && i + 2 < uri.size() && std::isxdigit(static_cast<unsigned char>(uri[i + 1])) &&
        std::isxdigit(static_cast<unsigned char>(uri[i + 2]))) {
      out += static_cast<char>(std::stoi(uri.substr(i + 1, 2), nullptr, 16));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

uint32_t readU32(const std::string& bytes, size_t offset) {
  uint32_t v = 0;
  std::memcpy(&v, bytes.data() + offset, 4);
  return v;
}


// Keeps an image's encoded bytes instead of decoding them while tinygltf parses. Images are decoded later,
// only when a material uses them, after their buffer view has been checked against its buffer: tinygltf hands
// an embedded image's loader a pointer into the buffer without checking the view's range, so those bytes are
// not touched here.
bool keepEncodedImage(tinygltf::Image* image, const int, std::string*, std::string*, int, int,
                      const unsigned char* bytes, int size, void*) {
  if (image->bufferView < 0 && size > 0) image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

// Image file formats, told by their signatures.
enum class ImageFormat { kPng, kJpeg, kWebp, kExr, kHdr, kTiff, kKtx2, kDds, kUnknown };

ImageFormat imageFormat(std::span<const uint8_t> b) {
  auto starts = [&](std::initializer_list<uint8_t> sig, size_t at = 0) {
    return b.size() >= at + sig.size() && std::equal(sig.begin(), sig.end(), b.begin() + std::ptrdiff_t(at));
  };
  if (starts({0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'})) return ImageFormat::kPng;
  if (starts({0xff, 0xd8, 0xff})) return ImageFormat::kJpeg;
  if (starts({'R', 'I', 'F', 'F'}) && starts({'W', 'E', 'B', 'P'}, 8)) return ImageFormat::kWebp;
  if (starts({0x76, 0x2f, 0x31, 0x01})) return ImageFormat::kExr;
  if (starts({'#', '?'})) return ImageFormat::kHdr;
  if (starts({'I', 'I', 42, 0}) || starts({'M', 'M', 0, 42})) return ImageFormat::kTiff;
  if (starts({0xab, 'K', 'T', 'X', ' ', '2', '0', 0xbb, '\r', '\n', 0x1a, '\n'})) return ImageFormat::kKtx2;
  if (starts({'D', 'D', 'S', ' '})) return ImageFormat::kDds;
  return ImageFormat::kUnknown;
}

const char* formatName(ImageFormat f) {
  switch (f) {
    case ImageFormat::kPng:
      return "a PNG image";
    case ImageFormat::kJpeg:
      return "a JPEG image";
    case ImageFormat::kWebp:
      return "a WebP image";
    case ImageFormat::kExr:
      return "an OpenEXR image";
    case ImageFormat::kHdr:
      return "a Radiance HDR image";
    case ImageFormat::kTiff:
      return "a TIFF image";
    case ImageFormat::kKtx2:
      return "a KTX2 texture";
    case ImageFormat::kDds:
      return "a DDS texture";
    case ImageFormat::kUnknown:
      break;
  }
  return "not an image format fly knows";
}

struct ImageSize {
  uint32_t width = 0;
  uint32_t height = 0;
  int bitsPerChannel = 8;  // as decoded: 16 for 16-bit PNGs, 8 otherwise
  // The fewest bytes a complete encoding of the declared image can take, so that a file that is much
  // smaller (cut off, or a header alone) fails before its pixels are allocated:
  //   PNG: its filtered scanlines, height · (1 + ⌈width · samples · bit depth / 8⌉) bytes (ISO/IEC 15948
  //        §7.2, §9.2; interlaced images have more), are zlib data, and deflate codes at most 258 bytes in
  //        a length/distance pair of ≥ 2 bits (RFC 1951 §3.2.5): at most 1032 bytes out per byte in.
  //   JPEG: the component of the largest sampling factors covers the image in ⌈width/8⌉ · ⌈height/8⌉
  //        blocks, and every block's DC coefficient takes a Huffman code of ≥ 1 bit (ITU-T T.81 §F.1.2.1,
  //        §G.1.2.1 for progressive DC scans): at least one byte per 8 blocks.
  uint64_t minEncodedBytes = 0;
};

uint32_t be16(const uint8_t* p) {
  return uint32_t(p[0]) << 8 | p[1];
}
uint32_t be32(const uint8_t* p) {
  return be16(p) << 16 | be16(p + 2);
}

// The pixel size a PNG (its IHDR chunk, ISO/IEC 15948 §11.2.2) or a JPEG (its SOFn segment, ITU-T T.81
// §B.2.2) declares, read without decoding; nullopt when the header is missing or cut off.
std::optional<ImageSize> imageSize(std::span<const uint8_t> b, ImageFormat format) {
  if (format == ImageFormat::kPng) {
    if (b.size() < 26 || std::memcmp(b.data() + 12, "IHDR", 4) != 0) return std::nullopt;
    ImageSize size{be32(b.data() + 16), be32(b.data() + 20), b[24] == 16 ? 16 : 8};
    const uint8_t colourType = b[25];  // 0 grey, 2 RGB, 3 palette, 4 grey + alpha, 6 RGBA
    const uint64_t samples = colourType == 2 ? 3 : colourType == 4 ? 2 : colourType == 6 ? 4 : 1;
    const uint64_t rowBytes = 1 + (uint64_t(size.width) * samples * std::max<uint8_t>(b[24], 1) + 7) / 8;
    size.minEncodedBytes = uint64_t(size.height) * rowBytes / 1032;
    return size;
  }
  size_t p = 2;  // after SOI
  while (p + 4 <= b.size()) {
    if (b[p] != 0xff) return std::nullopt;
    const uint8_t marker = b[p + 1];
    if (marker == 0xff) {  // fill byte
      ++p;
      continue;
    }
    const size_t length = be16(b.data() + p + 2);
    const bool sof = marker >= 0xc0 && marker <= 0xcf && marker != 0xc4 && marker != 0xc8 && marker != 0xcc;
    if (sof) {
      if (p + 9 > b.size()) return std::nullopt;
      ImageSize size{be16(b.data() + p + 7), be16(b.data() + p + 5), 8};
      size.minEncodedBytes = ((uint64_t(size.width) + 7) / 8) * ((uint64_t(size.height) + 7) / 8) / 8;
      return size;
    }
    if (marker == 0xda || length < 2) return std::nullopt;  // scan data before any frame header
    p += 2 + length;
  }
  return std::nullopt;
}

ImageDecoder& imageDecoderSlot() {
  static ImageDecoder decoder;
  return decoder;
}

const ImageDecoder& installedImageDecoder() {
  return imageDecoderSlot();
}

// The parts of a texture reference (glTF textureInfo), wherever it appears.
struct TexInfo {
  int index = -1;
  int texCoord = 0;
  const tinygltf::Value* transform = nullptr;  // KHR_texture_transform object, if any
};

TexInfo texInfo(int index, int texCoord, const tinygltf::ExtensionMap& extensions) {
  TexInfo t{index, texCoord, nullptr};
  auto it = extensions.find("KHR_texture_transform");
  if (it != extensions.end()) t.transform = &it->second;
  return t;
}

// Which channels of an image a material parameter reads.
enum class Channels { kAll, kRed, kGreen, kBlue };

// Placeholder ids used while converting: the entity's index in the importer's pending list + 1. commit()
// replaces them with the ids the Scene gives.
template <class IdT>
IdT pendingId(size_t index) {
  return IdT{static_cast<uint32_t>(index + 1)};
}

class Importer {
 public:
  Importer(Scene& scene, const fs::path& file, const GltfImportOptions& options)
      : scene_(scene), options_(options), file_(file), fileStr_(file.string()) {}

  GltfImportResult run() {
    if (options_.parent && !scene_.nodes().count(options_.parent)) {
      throw std::invalid_argument("importGltf: parent node " + std::to_string(options_.parent.value) +
                                  " does not exist");
    }
    load();
    checkExtensions();
    warnUnsupportedContent();
    convertNodes();
    commit();
    return std::move(result_);
  }

 private:
  // --- Reporting.
  [[noreturn]] void fail(const std::string& jsonPath, const std::string& message,
                         const std::string& hint = kHintInvalid) const {
    throw InputError(SourceLocation{fileStr_, 0, 0, jsonPath}, message, hint);
  }

  void warn(const std::string& message) {
    const std::string text = fileStr_ + ": " + message;
    log::warn(text);
    result_.warnings.push_back(text);
  }

  std::string name(const std::string& gltfName, const char* kind, size_t index) const {
    return options_.namePrefix + (gltfName.empty() ? kind + std::to_string(index) : gltfName);
  }

  // --- The import budget (GltfImportOptions::maxDecodedBytes), charged before each allocation.
  void charge(uint64_t bytes, const std::string& path, const std::string& what) const {
    if (bytes > budgetLeft_) {
      fail(path,
           what + " would take " + bytesText(bytes) + " decoded, more than the " + bytesText(budgetLeft_) +
               " left of fly's import budget of " + bytesText(options_.maxDecodedBytes) +
               " (docs/scene-format.md, \"Import budget\")",
           "simplify the model or split it into parts, or scale its textures down");
    }
    budgetLeft_ -= bytes;
  }

  static std::string bytesText(uint64_t bytes) {
    std::ostringstream s;
    s.precision(3);
    if (bytes >= (uint64_t(1) << 30)) {
      s << double(bytes) / double(uint64_t(1) << 30) << " GiB";
    } else if (bytes >= (uint64_t(1) << 20)) {
      s << double(bytes) / double(uint64_t(1) << 20) << " MiB";
    } else {
      s << bytes << " bytes";
    }
    return s.str();
  }

  // A declared image size, before decoding, against kMaxTextureDimension, the budget (RGBA as decoded),
  // which it charges, and the bytes its encoding has (`encodedBytes`); returns the bytes charged.
  uint64_t checkImageSize(const ImageSize& size, uint64_t encodedBytes, const std::string& path,
                          const std::string& what) {
    if (size.width == 0 || size.height == 0)
      fail(path, what + " declares an image of 0 pixels", kHintTruncated);
    if (size.width > uint32_t(kMaxTextureDimension) || size.height > uint32_t(kMaxTextureDimension)) {
      fail(path,
           what + " is " + std::to_string(size.width) + " × " + std::to_string(size.height) +
               " px; fly imports textures of at most " + std::to_string(kMaxTextureDimension) +
               " px a side (docs/scene-format.md, \"Import budget\")",
           "scale the texture down to at most " + std::to_string(kMaxTextureDimension) + " px a side");
    }
    const uint64_t bytes = uint64_t(size.width) * size.height * 4 * uint64_t(size.bitsPerChannel / 8);
    charge(bytes, path, what);
    if (encodedBytes < size.minEncodedBytes) {
      fail(path,
           what + " declares " + std::to_string(size.width) + " × " + std::to_string(size.height) +
               " px, which no complete image of its format stores in fewer than " +
               std::to_string(size.minEncodedBytes) + " bytes; it has " + std::to_string(encodedBytes),
           kHintTruncated);
    }
    return bytes;
  }

  // --- Loading.
  void load() {
    std::string bytes = readInputFile(file_, "glTF file");  // missing, directory, 0 bytes → InputError
    if (bytes.size() > UINT_MAX) fail("", "the file is larger than 4 GiB, which tinygltf cannot read");
    std::error_code ec;
    baseDir_ = fs::absolute(file_, ec).parent_path();
    const GltfFolderFiles files(baseDir_);
    tinygltf::TinyGLTF loader;
    loader.SetFsCallbacks(files.callbacks());
    loader.SetImageLoader(&keepEncodedImage, nullptr);

    std::string err;
    // tinygltf's warnings only report image files it could not read; decodedImage() reports those with the
    // material that uses them.
    std::string tinyWarn;
    const bool binary = bytes.size() >= 4 && bytes.compare(0, 4, "glTF") == 0;
    bool ok = false;
    if (binary) {
      checkGlbLayout(bytes);
      patchCompressedMeshJson(bytes, true);
      ok = loader.LoadBinaryFromMemory(&model_, &err, &tinyWarn,
                                       reinterpret_cast<const unsigned char*>(bytes.data()),
                                       unsigned(bytes.size()), baseDir_.string());
    } else {
      std::string ext = file_.extension().string();
      std::transform(ext.begin(), ext.end(), ext.begin(),
                     [](unsigned char c) { return char(std::tolower(c)); });
      if (ext == ".glb") {
        fail("", "the file is not a binary glTF: it does not start with the GLB magic 'glTF'",
             "the file is damaged or not a .glb; export it again");
      }
      patchCompressedMeshJson(bytes, false);
      ok = loader.LoadASCIIFromString(&model_, &err, &tinyWarn, bytes.data(), unsigned(bytes.size()),
                                      baseDir_.string());
    }
    if (!ok) failLoad(err, binary);
    preferWebpSources();
    decodeMeshoptViews();
    // tinygltf reports some problems in `err` and carries on, e.g. a textureInfo without "index".
    std::istringstream lines(err);
    for (std::string line; std::getline(lines, line);) {
      if (!line.empty()) warn(line);
    }
  }

  // The GLB container (glTF 2.0 §4 "GLB File Format Specification"): a 12-byte header (magic, version,
  // length), a JSON chunk and an optional BIN chunk, each with an 8-byte header (length, type). Checked here
  // so that a truncated file is reported as such.
  void checkGlbLayout(const std::string& bytes) const {
    const size_t size = bytes.size();
    const std::string have = " but the file has " + std::to_string(size) + " bytes";
    if (size < 12) fail("", "the GLB file is truncated: its 12-byte header is incomplete", kHintTruncated);
    const uint32_t version = readU32(bytes, 4);
    if (version != 2) {
      fail("",
           "GLB version " + std::to_string(version) + " is not supported; fly reads glTF 2.0 (GLB version 2)",
           "convert the file to glTF 2.0");
    }
    const uint32_t length = readU32(bytes, 8);
    if (length > size) {
      fail("", "the GLB file is truncated: its header says " + std::to_string(length) + " bytes" + have,
           kHintTruncated);
    }
    if (length < 20) fail("", "the GLB file is truncated: it has no JSON chunk", kHintTruncated);
    const uint32_t jsonLength = readU32(bytes, 12);
    if (readU32(bytes, 16) != 0x4E4F534Au) fail("", "the first GLB chunk is not JSON (type 'JSON')");
    const size_t jsonEnd = satMulAdd(20, jsonLength, 1);
    if (jsonEnd > length) {
      fail("",
           "the GLB file is truncated: its JSON chunk needs bytes 20.." + std::to_string(jsonEnd) +
               " but the file is " + std::to_string(length) + " bytes long",
           kHintTruncated);
    }
    const size_t binStart = jsonEnd + (4 - jsonEnd % 4) % 4;  // chunks start on 4-byte boundaries
    if (binStart >= length) return;
    if (binStart + 8 > length) {
      fail("", "the GLB file is truncated inside the BIN chunk's header", kHintTruncated);
    }
    const size_t binEnd = satMulAdd(binStart + 8, readU32(bytes, binStart), 1);
    if (binEnd > length) {
      fail("",
           "the GLB file is truncated: its BIN chunk needs bytes " + std::to_string(binStart + 8) + ".." +
               std::to_string(binEnd) + " but the file is " + std::to_string(length) + " bytes long",
           kHintTruncated);
    }
  }

  // Compressed meshes hold JSON that tinygltf refuses, changed here in the text it parses (`bytes`: the .gltf
  // text or the GLB file):
  // - EXT_meshopt_compression: a fallback buffer (one that loaders which decode the extension never read) may
  //   have no data at all. It gets a one-byte data URI; the views that refer to it are decoded from the
  //   compressed data (decodeMeshoptViews), and any other use of it fails bufferViewData's range check.
  // - KHR_draco_mesh_compression: the indices accessor of a compressed primitive has no buffer view (the
  //   triangles are in the Draco stream). The primitive's "indices" is dropped; the stream gives them.
  void patchCompressedMeshJson(std::string& bytes, bool glb) const {
    if (bytes.find("EXT_meshopt_compression") == std::string::npos &&
        bytes.find("KHR_draco_mesh_compression") == std::string::npos) {
      return;
    }
    const size_t jsonStart = glb ? 20 : 0;
    const size_t jsonLength = glb ? readU32(bytes, 12) : bytes.size();
    nlohmann::json doc =
        nlohmann::json::parse(bytes.begin() + std::ptrdiff_t(jsonStart),
                              bytes.begin() + std::ptrdiff_t(jsonStart + jsonLength), nullptr, false);
    if (doc.is_discarded() || !doc.is_object()) return;  // tinygltf reports the JSON error
    auto extensionOf = [](const nlohmann::json& o, const char* name) -> const nlohmann::json* {
      if (!o.is_object() || !o.contains("extensions") || !o["extensions"].is_object()) return nullptr;
      const nlohmann::json& e = o["extensions"];
      return e.contains(name) && e[name].is_object() ? &e[name] : nullptr;
    };
    bool changed = false;
    if (doc.contains("buffers") && doc["buffers"].is_array()) {
      for (nlohmann::json& b : doc["buffers"]) {
        const nlohmann::json* ext = extensionOf(b, "EXT_meshopt_compression");
        if (!ext || b.contains("uri") || ext->value("fallback", false) != true) continue;
        b["uri"] = "data:application/octet-stream;base64,AA==";
        b["byteLength"] = 1;
        changed = true;
      }
    }
    if (doc.contains("meshes") && doc["meshes"].is_array()) {
      for (nlohmann::json& mesh : doc["meshes"]) {
        if (!mesh.is_object() || !mesh.contains("primitives") || !mesh["primitives"].is_array()) continue;
        for (nlohmann::json& prim : mesh["primitives"]) {
          if (extensionOf(prim, "KHR_draco_mesh_compression") && prim.contains("indices")) {
            prim.erase("indices");
            changed = true;
          }
        }
      }
    }
    if (!changed) return;
    std::string json = doc.dump();
    if (!glb) {
      bytes = std::move(json);
      return;
    }
    while (json.size() % 4) json += ' ';  // GLB chunks are 4-byte aligned (glTF 2.0 §4.4)
    const size_t oldJsonEnd = jsonStart + jsonLength + (4 - jsonLength % 4) % 4;
    std::string out = bytes.substr(0, 12);
    auto u32 = [&out](size_t v) {
      for (int k = 0; k < 4; ++k) out += char((v >> (8 * k)) & 0xff);
    };
    u32(json.size());
    u32(0x4E4F534Au);
    out += json;
    if (oldJsonEnd < bytes.size()) out += bytes.substr(oldJsonEnd);
    const auto total = uint32_t(out.size());
    std::memcpy(out.data() + 8, &total, 4);
    bytes = std::move(out);
  }

  // EXT_meshopt_compression: each compressed buffer view is decoded once, after loading; bufferViewData then
  // hands out the decoded bytes.
  void decodeMeshoptViews() {
    for (size_t v = 0; v < model_.bufferViews.size(); ++v) {
      const tinygltf::BufferView& bv = model_.bufferViews[v];
      auto it = bv.extensions.find("EXT_meshopt_compression");
      if (it == bv.extensions.end()) continue;
      const tinygltf::Value& e = it->second;
      const std::string path = "/bufferViews/" + std::to_string(v) + "/extensions/EXT_meshopt_compression";
      const std::string label = "buffer view " + std::to_string(v) + " (EXT_meshopt_compression)";
      auto number = [&](const char* key, bool required) -> size_t {
        const tinygltf::Value& n = e.Get(key);
        if (n.Type() == tinygltf::NULL_TYPE && !required) return 0;
        if (!n.IsNumber() || n.GetNumberAsDouble() < 0.0) {
          fail(path + "/" + key, label + " needs '" + key + "', a number ≥ 0");
        }
        return size_t(n.GetNumberAsDouble());
      };
      const size_t buffer = number("buffer", true);
      const size_t offset = number("byteOffset", false);
      const size_t length = number("byteLength", true);
      const size_t stride = number("byteStride", true);
      const size_t count = number("count", true);
      const std::string modeName = e.Get("mode").IsString() ? e.Get("mode").Get<std::string>() : "";
      const std::string filterName = e.Get("filter").IsString() ? e.Get("filter").Get<std::string>() : "NONE";
      MeshoptMode mode = MeshoptMode::kAttributes;
      if (modeName == "TRIANGLES") {
        mode = MeshoptMode::kTriangles;
      } else if (modeName == "INDICES") {
        mode = MeshoptMode::kIndices;
      } else if (modeName != "ATTRIBUTES") {
        fail(path + "/mode", label + " has mode '" + modeName +
                                 "'; the extension defines ATTRIBUTES, TRIANGLES "
                                 "and INDICES");
      }
      MeshoptFilter filter = MeshoptFilter::kNone;
      if (filterName == "OCTAHEDRAL") {
        filter = MeshoptFilter::kOctahedral;
      } else if (filterName == "QUATERNION") {
        filter = MeshoptFilter::kQuaternion;
      } else if (filterName == "EXPONENTIAL") {
        filter = MeshoptFilter::kExponential;
      } else if (filterName != "NONE") {
        fail(path + "/filter", label + " has filter '" + filterName +
                                   "'; the extension defines NONE, "
                                   "OCTAHEDRAL, QUATERNION and EXPONENTIAL");
      }
      if (buffer >= model_.buffers.size()) {
        fail(path + "/buffer", label + " refers to buffer " + std::to_string(buffer) + ", but the file has " +
                                   std::to_string(model_.buffers.size()) + " buffers");
      }
      const std::vector<unsigned char>& data = model_.buffers[buffer].data;
      if (satMulAdd(offset, length, 1) > data.size()) {
        fail(path,
             label + " reads bytes " + std::to_string(offset) + ".." + std::to_string(offset + length) +
                 " of buffer " + std::to_string(buffer) + ", which has " + std::to_string(data.size()),
             kHintTruncated);
      }
      const size_t decodedBytes = satMulAdd(0, count, stride);
      if (decodedBytes != bv.byteLength) {
        fail(path, label + " decodes to " + std::to_string(count) + " × " + std::to_string(stride) +
                       " bytes, but the buffer view's byteLength is " + std::to_string(bv.byteLength));
      }
      charge(decodedBytes, path + "/count", label);
      try {
        meshoptViews_[v] = decodeMeshoptView({data.data() + offset, length}, count, stride, mode, filter);
      } catch (const std::runtime_error& err) {
        fail(path, label + " cannot be decoded: " + err.what(), kHintTruncated);
      }
    }
  }

  // EXT_texture_webp: a texture's WebP image replaces its fallback ("source") when a decoder that reads WebP
  // is installed.
  void preferWebpSources() {
    if (!isSupportedExtension("EXT_texture_webp")) return;
    for (tinygltf::Texture& t : model_.textures) {
      auto it = t.extensions.find("EXT_texture_webp");
      if (it != t.extensions.end() && it->second.Get("source").IsNumber()) {
        t.source = it->second.Get("source").GetNumberAsInt();
      }
    }
  }

  // Turns tinygltf's error text into an InputError with a location and a hint.
  [[noreturn]] void failLoad(const std::string& err, bool binary) const {
    // nlohmann::json, which tinygltf parses with: "[json.exception.parse_error.101] parse error at line 3,
    // column 5: syntax error while parsing object - unexpected '}'; expected string literal".
    static const std::regex kJsonError(R"(at line (\d+), column (\d+): ([^\n]*))");
    std::smatch m;
    if (std::regex_search(err, m, kJsonError)) {
      SourceLocation loc{fileStr_, std::stoi(m[1].str()), std::stoi(m[2].str())};
      throw InputError(
          loc, std::string(binary ? "invalid JSON in the GLB's JSON chunk: " : "invalid JSON: ") + m[3].str(),
          "the file is not valid JSON; it may be truncated or damaged by hand editing: look near the "
          "line and column given");
    }
    // The buffer being parsed when loading stopped: tinygltf adds buffers one by one.
    const size_t buffer = model_.buffers.size();
    const std::string bufferLabel = "buffer " + std::to_string(buffer);
    const std::string bufferPath = "/buffers/" + std::to_string(buffer);
    static const std::regex kNotFound(R"(File not found : ([^\n]*))");
    if (std::regex_search(err, m, kNotFound)) {
      fail(bufferPath + "/uri",
           bufferLabel + " refers to '" + m[1].str() + "', which does not exist in " + baseDir_.string(),
           "copy the .bin file next to the glTF file (relative URIs are resolved against the glTF file's "
           "folder), or export a single .glb");
    }
    static const std::regex kSizeMismatch(
        R"(File size mismatch : ([^,]*), requestedBytes (\d+), but got (\d+))");
    if (std::regex_search(err, m, kSizeMismatch)) {
      fail(bufferPath + "/byteLength",
           bufferLabel + " ('" + m[1].str() + "') has " + m[3].str() + " bytes but the glTF file says " +
               m[2].str() + " (byteLength)",
           kHintTruncated);
    }
    if (err.find("File is empty") != std::string::npos || err.find("File read error") != std::string::npos) {
      std::string what = err.substr(0, err.find('\n'));
      fail(bufferPath + "/uri", bufferLabel + ": " + what, kHintTruncated);
    }
    std::string what = err;
    while (!what.empty() && (what.back() == '\n' || what.back() == ' ')) what.pop_back();
    std::replace(what.begin(), what.end(), '\n', ' ');
    if (what.empty()) what = "tinygltf could not read the file";
    fail("", "cannot read the glTF file: " + what);
  }

  // glTF 2.0 §3.12: a required extension the importer does not implement makes the file unusable; one that is
  // only used can be ignored.
  void checkExtensions() {
    for (const std::string& ext : model_.extensionsRequired) {
      if (isSupportedExtension(ext)) continue;
      const UnsupportedExtension* known = findUnsupported(ext);
      fail("/extensionsRequired",
           "the file requires the glTF extension '" + ext + "', which fly does not support",
           known
               ? std::string(known->hint)
               : "export the file without " + ext + "; docs/scene-format.md lists the extensions fly reads");
    }
    for (const std::string& ext : model_.extensionsUsed) {
      const bool required = std::find(model_.extensionsRequired.begin(), model_.extensionsRequired.end(),
                                      ext) != model_.extensionsRequired.end();
      if (required || isSupportedExtension(ext)) continue;
      const UnsupportedExtension* known = findUnsupported(ext);
      warn("the glTF extension '" + ext + "' is not supported: " +
           (known ? std::string(known->ignored) : std::string("what it adds is ignored")));
    }
    warnVariants();
  }

  // KHR_materials_variants: the materials a primitive has without a variant are imported.
  void warnVariants() {
    auto it = model_.extensions.find("KHR_materials_variants");
    if (it == model_.extensions.end()) return;
    const tinygltf::Value& variants = it->second.Get("variants");
    std::string names;
    for (size_t k = 0; variants.IsArray() && k < variants.ArrayLen(); ++k) {
      const tinygltf::Value& n = variants.Get(int(k)).Get("name");
      names +=
          std::string(names.empty() ? "" : ", ") + "'" + (n.IsString() ? n.Get<std::string>() : "?") + "'";
    }
    if (names.empty()) return;
    warn("the file has material variants (KHR_materials_variants) " + names +
         "; the default materials are imported, as a viewer shows the file before a variant is chosen");
  }

  void warnUnsupportedContent() {
    if (!model_.animations.empty()) warn("animations are not imported; the scene is taken in its rest pose");
    if (!model_.skins.empty()) warn("skins are not imported; skinned meshes are taken in their bind pose");
    for (const tinygltf::Mesh& mesh : model_.meshes) {
      for (const tinygltf::Primitive& p : mesh.primitives) {
        if (!p.targets.empty()) {
          warn("morph targets are not imported; meshes keep their base shape");
          return;
        }
      }
    }
  }

  // --- Nodes (glTF 2.0 §3.5).
  struct PendingNode {
    Node node;        // meshes, camera and light hold placeholder ids
    int parent = -1;  // index in nodes_, -1 = one of the imported roots
  };

  void convertNodes() {
    const size_t count = model_.nodes.size();
    // Each node has at most one parent: "the node hierarchy MUST be a set of disjoint strict trees" (§3.5.2).
    // With that checked, walking down from parentless roots visits every node once and cannot loop.
    std::vector<int> parentOf(count, -1);
    for (size_t i = 0; i < count; ++i) {
      for (int c : model_.nodes[i].children) {
        const std::string path = "/nodes/" + std::to_string(i) + "/children";
        if (c < 0 || size_t(c) >= count) {
          fail(path, "node " + std::to_string(i) + " has child " + std::to_string(c) + ", but the file has " +
                         std::to_string(count) + " nodes");
        }
        if (size_t(c) == i || parentOf[size_t(c)] >= 0) {
          fail(path, "node " + std::to_string(c) + " is a child of more than one node (or of itself)",
               "a glTF node hierarchy must be a set of disjoint trees (glTF 2.0 §3.5.2); " +
                   std::string(kHintInvalid));
        }
        parentOf[size_t(c)] = int(i);
      }
    }
    // Nodes that are each other's ancestors have one parent each but no root; walk up from every node.
    std::vector<uint8_t> state(count, 0);  // 0 = not seen, 1 = on the current walk, 2 = leads to a root
    for (size_t i = 0; i < count; ++i) {
      size_t n = i;
      while (state[n] == 0) {
        state[n] = 1;
        if (parentOf[n] < 0) break;
        n = size_t(parentOf[n]);
      }
      if (state[n] == 1 && parentOf[n] >= 0) {
        fail("/nodes/" + std::to_string(n) + "/children",
             "node " + std::to_string(n) + " is its own ancestor: the node hierarchy has a cycle",
             "a glTF node hierarchy must be a set of disjoint trees (glTF 2.0 §3.5.2); " +
                 std::string(kHintInvalid));
      }
      for (n = i; state[n] == 1; n = parentOf[n] < 0 ? n : size_t(parentOf[n])) state[n] = 2;
    }

    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const size_t s = model_.defaultScene >= 0 ? size_t(model_.defaultScene) : 0;
      if (s >= model_.scenes.size()) {
        fail("/scene", "the default scene is " + std::to_string(s) + ", but the file has " +
                           std::to_string(model_.scenes.size()) + " scenes");
      }
      if (model_.scenes.size() > 1) {
        warn("the file has " + std::to_string(model_.scenes.size()) + " scenes; scene " + std::to_string(s) +
             quotedName(model_.scenes[s].name) + " is imported and the others are ignored");
      }
      const std::vector<int>& listedRoots = model_.scenes[s].nodes;
      const std::string path = "/scenes/" + std::to_string(s) + "/nodes";
      std::vector<bool> listed(count, false);
      for (int r : listedRoots) {
        if (r < 0 || size_t(r) >= count) {
          fail(path, "scene " + std::to_string(s) + " lists node " + std::to_string(r) +
                         ", but the file has " + std::to_string(count) + " nodes");
        }
        listed[size_t(r)] = true;
      }
      // glTF 2.0 §3.5.2 makes a scene's nodes root nodes. Some exporters list a child instead (Kenney's
      // models list their one node under an unlisted "tmpParent"); such a node is imported as a root with its
      // own transform, as glTF viewers show it, unless an ancestor of it is listed and brings it along.
      std::vector<bool> taken(count, false);
      for (int r : listedRoots) {
        const std::string label = "scene " + std::to_string(s) + " lists node " + std::to_string(r) +
                                  quotedName(model_.nodes[size_t(r)].name);
        if (taken[size_t(r)]) {
          warn(label + " twice; it is imported once");
          continue;
        }
        bool ancestorListed = false;
        for (int a = parentOf[size_t(r)]; a >= 0 && !ancestorListed; a = parentOf[size_t(a)]) {
          ancestorListed = listed[size_t(a)];
        }
        if (ancestorListed) {
          warn(label +
               " as a root, but an ancestor of it is listed too; it is imported once, under its parent");
          continue;
        }
        if (parentOf[size_t(r)] >= 0) {
          warn(label + " as a root, but it is a child of node " + std::to_string(parentOf[size_t(r)]) +
               "; it is imported as a root with its own transform, as glTF viewers show it");
        }
        taken[size_t(r)] = true;
        roots.push_back(r);
      }
    } else {
      // Without scenes nothing says what to show (§3.5.1); take every parentless node so that a file of loose
      // nodes still imports.
      for (size_t i = 0; i < count; ++i) {
        if (parentOf[i] < 0) roots.push_back(int(i));
      }
    }

    struct Visit {
      int gltfNode;
      int parent;  // index in nodes_
      mat4 worldFromParent;
    };
    const mat4 worldFromImport = options_.parent ? scene_.worldFromLocal(options_.parent) : mat4(1.0f);
    std::vector<Visit> stack;
    for (auto it = roots.rbegin(); it != roots.rend(); ++it) stack.push_back({*it, -1, worldFromImport});
    while (!stack.empty()) {
      const Visit v = stack.back();
      stack.pop_back();
      const auto i = size_t(v.gltfNode);
      const tinygltf::Node& gn = model_.nodes[i];
      const std::string path = "/nodes/" + std::to_string(i);
      PendingNode pn;
      pn.parent = v.parent;
      pn.node.name = name(gn.name, "node", i);
      pn.node.parentFromLocal = nodeTransform(i);
      const mat4 worldFromLocal = v.worldFromParent * pn.node.parentFromLocal;
      if (gn.mesh >= 0) {
        if (size_t(gn.mesh) >= model_.meshes.size()) {
          fail(path + "/mesh", "node " + std::to_string(i) + " refers to mesh " + std::to_string(gn.mesh) +
                                   ", but the file has " + std::to_string(model_.meshes.size()) + " meshes");
        }
        // glTF 2.0 §3.7.4: a negative determinant of the world transform makes clockwise the front face.
        const bool mirrored = glm::determinant(mat3(worldFromLocal)) < 0.0f;
        pn.node.meshes = meshesFor(size_t(gn.mesh), mirrored);
      } else if (gn.mesh < -1) {
        fail(path + "/mesh", "node " + std::to_string(i) + " refers to mesh " + std::to_string(gn.mesh));
      }
      if (gn.camera != -1) pn.node.camera = camera(gn.camera, path + "/camera");
      auto light = gn.extensions.find("KHR_lights_punctual");
      if (light != gn.extensions.end()) pn.node.light = nodeLight(light->second, path);
      nodes_.push_back(std::move(pn));
      const int self = int(nodes_.size() - 1);
      for (auto c = gn.children.rbegin(); c != gn.children.rend(); ++c) {
        stack.push_back({*c, self, worldFromLocal});
      }
    }
  }

  // parentFromLocal from "matrix" (column-major, as glm) or from T · R · S (glTF 2.0 §3.5.3).
  mat4 nodeTransform(size_t i) const {
    const tinygltf::Node& n = model_.nodes[i];
    const std::string path = "/nodes/" + std::to_string(i);
    const std::string label = "node " + std::to_string(i) + quotedName(n.name);
    auto finite = [&](const std::vector<double>& v, const char* key, size_t size) {
      if (v.size() != size) {
        fail(path + "/" + key, label + " has " + std::to_string(v.size()) + " numbers in '" + key +
                                   "'; glTF needs " + std::to_string(size));
      }
      for (double x : v) {
        if (!std::isfinite(x)) {
          fail(path + "/" + key, label + " has a NaN or infinite number in '" + key + "'");
        }
      }
    };
    if (!n.matrix.empty()) {
      finite(n.matrix, "matrix", 16);
      mat4 m(1.0f);
      for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = float(n.matrix[size_t(k)]);
      return m;
    }
    vec3 t(0.0f);
    quat r(1.0f, 0.0f, 0.0f, 0.0f);
    vec3 s(1.0f);
    if (!n.translation.empty()) {
      finite(n.translation, "translation", 3);
      t = vec3(float(n.translation[0]), float(n.translation[1]), float(n.translation[2]));
    }
    if (!n.rotation.empty()) {
      finite(n.rotation, "rotation", 4);
      // glTF stores (x, y, z, w). Exporters round unit quaternions to a few digits; normalising keeps the
      // rotation from also scaling.
      r = quat(float(n.rotation[3]), float(n.rotation[0]), float(n.rotation[1]), float(n.rotation[2]));
      const float len = glm::length(r);
      if (!(len > 1e-6f)) fail(path + "/rotation", label + " has a zero rotation quaternion");
      r = r / len;
    }
    if (!n.scale.empty()) {
      finite(n.scale, "scale", 3);
      s = vec3(float(n.scale[0]), float(n.scale[1]), float(n.scale[2]));
    }
    return glm::translate(mat4(1.0f), t) * glm::mat4_cast(r) * glm::scale(mat4(1.0f), s);
  }

  // --- Cameras (glTF 2.0 §3.10).
  CameraId camera(int index, const std::string& refPath) {
    if (index < 0 || size_t(index) >= model_.cameras.size()) {
      fail(refPath, "camera " + std::to_string(index) + " does not exist; the file has " +
                        std::to_string(model_.cameras.size()) + " cameras");
    }
    const auto i = size_t(index);
    auto cached = cameraIds_.find(i);
    if (cached != cameraIds_.end()) return cached->second;
    const tinygltf::Camera& c = model_.cameras[i];
    const std::string path = "/cameras/" + std::to_string(i);
    const std::string label = "camera " + std::to_string(i) + quotedName(c.name);
    Camera out;
    out.name = name(c.name, "camera", i);
    if (c.type == "perspective") {
      const tinygltf::PerspectiveCamera& p = c.perspective;
      out.projection = Projection::kPerspective;
      if (!(p.yfov > 0.0 && p.yfov < kPi)) {
        fail(path + "/perspective/yfov", label + " has yfov " + str(p.yfov) + " rad; it must be in (0, π)");
      }
      if (!(p.znear > 0.0 && std::isfinite(p.znear))) {
        fail(path + "/perspective/znear", label + " has znear " + str(p.znear) + " m; it must be > 0");
      }
      if (!(p.aspectRatio >= 0.0 && std::isfinite(p.aspectRatio))) {
        fail(path + "/perspective/aspectRatio",
             label + " has aspectRatio " + str(p.aspectRatio) + "; it must be > 0");
      }
      // tinygltf gives 0 for an absent zfar: an infinite projection (§3.10).
      if (p.zfar != 0.0 && !(p.zfar > p.znear)) {
        fail(path + "/perspective/zfar", label + " has zfar " + str(p.zfar) + " m; it must be > znear");
      }
      out.yfovRad = float(p.yfov);
      out.aspectRatio = float(p.aspectRatio);
      out.znearM = float(p.znear);
      out.zfarM = p.zfar == 0.0 ? std::numeric_limits<float>::infinity() : float(p.zfar);
    } else {  // tinygltf accepts only "perspective" and "orthographic"
      const tinygltf::OrthographicCamera& o = c.orthographic;
      out.projection = Projection::kOrthographic;
      if (!(o.xmag != 0.0 && o.ymag != 0.0 && std::isfinite(o.xmag) && std::isfinite(o.ymag))) {
        fail(path + "/orthographic", label + " has xmag " + str(o.xmag) + " and ymag " + str(o.ymag) +
                                         "; both must be finite and non-zero");
      }
      if (!(o.znear >= 0.0 && o.zfar > o.znear && std::isfinite(o.zfar))) {
        fail(path + "/orthographic", label + " has znear " + str(o.znear) + " m and zfar " + str(o.zfar) +
                                         " m; they must satisfy 0 ≤ znear < zfar < ∞");
      }
      if (o.xmag < 0.0 || o.ymag < 0.0) {
        warn(label + " has a negative xmag or ymag (a mirrored view); their absolute values are used");
      }
      out.xmagM = float(std::abs(o.xmag));
      out.ymagM = float(std::abs(o.ymag));
      out.znearM = float(o.znear);
      out.zfarM = float(o.zfar);
    }
    cameras_.push_back(std::move(out));
    return cameraIds_[i] = pendingId<CameraId>(cameras_.size() - 1);
  }

  // --- Lights (KHR_lights_punctual).
  LightId nodeLight(const tinygltf::Value& ext, const std::string& nodePath) {
    const std::string path = nodePath + "/extensions/KHR_lights_punctual/light";
    if (!ext.IsObject() || !ext.Get("light").IsNumber()) {
      fail(path, "the node's KHR_lights_punctual extension has no light index");
    }
    const int index = ext.Get("light").GetNumberAsInt();
    if (index < 0 || size_t(index) >= model_.lights.size()) {
      fail(path, "light " + std::to_string(index) + " does not exist; the file has " +
                     std::to_string(model_.lights.size()) + " lights");
    }
    const auto i = size_t(index);
    auto cached = lightIds_.find(i);
    if (cached != lightIds_.end()) return cached->second;
    const tinygltf::Light& l = model_.lights[i];
    const std::string lpath = "/extensions/KHR_lights_punctual/lights/" + std::to_string(i);
    const std::string label = "light " + std::to_string(i) + quotedName(l.name);
    Light out;
    out.name = name(l.name, "light", i);
    if (l.type == "point") {
      out.type = LightType::kPoint;
    } else if (l.type == "spot") {
      out.type = LightType::kSpot;
    } else if (l.type == "directional") {
      out.type = LightType::kDirectional;
    } else {
      fail(lpath + "/type", label + " has type '" + l.type +
                                "'; KHR_lights_punctual defines 'point', 'spot' and 'directional'");
    }
    if (!l.color.empty()) {
      if (l.color.size() != 3) {
        fail(lpath + "/color",
             label + " has a color with " + std::to_string(l.color.size()) + " numbers; it needs 3");
      }
      out.color = Rgb(float(l.color[0]), float(l.color[1]), float(l.color[2]));
    }
    out.intensity = float(l.intensity);  // cd for point and spot, lux for directional, as in fly
    // tinygltf gives 0 for an absent range: no cut-off. A directional light has no range.
    if (l.range != 0.0 && out.type != LightType::kDirectional) out.rangeM = float(l.range);
    if (out.type == LightType::kSpot) {
      out.innerConeRad = float(l.spot.innerConeAngle);
      out.outerConeRad = float(l.spot.outerConeAngle);
    }
    const std::string problem = validate(out);
    if (!problem.empty()) fail(lpath, label + ": " + problem);
    lights_.push_back(std::move(out));
    return lightIds_[i] = pendingId<LightId>(lights_.size() - 1);
  }

  // --- Meshes (glTF 2.0 §3.7.2).
  struct MeshEntry {
    bool converted = false;
    std::vector<MeshId> ids;                      // one per kept primitive, placeholders
    std::optional<std::vector<MeshId>> mirrored;  // the same with reversed winding, made on first use
  };

  std::vector<MeshId> meshesFor(size_t meshIndex, bool mirrored) {
    if (meshEntries_.empty()) meshEntries_.resize(model_.meshes.size());
    MeshEntry& e = meshEntries_[meshIndex];
    if (!e.converted) {
      const tinygltf::Mesh& gm = model_.meshes[meshIndex];
      for (size_t p = 0; p < gm.primitives.size(); ++p) {
        if (std::optional<Mesh> m = convertPrimitive(meshIndex, p)) {
          meshes_.push_back(std::move(*m));
          e.ids.push_back(pendingId<MeshId>(meshes_.size() - 1));
        }
      }
      e.converted = true;
    }
    if (!mirrored) return e.ids;
    if (!e.mirrored) {
      // A copy whose triangles run the other way round, so that counter-clockwise is the front face in world
      // space under this node's mirroring transform. Normals stay: the inverse transpose of the node's
      // transform already turns them to the front side.
      std::vector<MeshId> ids;
      for (MeshId id : e.ids) {
        Mesh copy = meshes_[id.value - 1];
        copy.name += " (mirrored)";
        for (size_t t = 0; t + 2 < copy.indices.size(); t += 3) {
          std::swap(copy.indices[t + 1], copy.indices[t + 2]);
        }
        meshes_.push_back(std::move(copy));
        ids.push_back(pendingId<MeshId>(meshes_.size() - 1));
      }
      e.mirrored = std::move(ids);
    }
    return *e.mirrored;
  }

  // An accessor's elements where they lie, after every byte range they and their sparse substitution
  // (glTF 2.0 §3.6.2.3) touch has been checked: component c of element e is at(e, c), converted by
  // component(), with the sparse values replacing elements when applySparse is called. Read in place rather
  // than copied, since a mesh's attributes are most of the data a glTF file holds.
  struct AccessorData {
    const unsigned char* data = nullptr;  // element 0; null for an accessor without a buffer view (all zeros)
    size_t stride = 0;                    // bytes from one element to the next
    size_t elements = 0;
    int components = 0;  // 0: no accessor
    int componentType = TINYGLTF_COMPONENT_TYPE_FLOAT;
    bool normalized = false;
    // Sparse substitution: `sparseCount` element indices of type sparseIndexType and their values, tightly
    // packed.
    size_t sparseCount = 0;
    const unsigned char* sparseIndices = nullptr;
    int sparseIndexType = TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT;
    const unsigned char* sparseValues = nullptr;

    size_t count() const { return components ? elements : 0; }
    bool empty() const { return count() == 0; }
    double at(size_t e, size_t c) const {
      if (!data) return 0.0;
      return component(data + e * stride + c * componentSize(componentType), componentType, normalized);
    }
    // Calls f(element, component, value) for every sparse value, in the file's order (later ones win).
    template <typename F>
    void applySparse(F&& f) const {
      const auto n = size_t(components);
      const size_t compSize = componentSize(componentType);
      const size_t indexSize = componentSize(sparseIndexType);
      for (size_t k = 0; k < sparseCount; ++k) {
        const auto target = size_t(component(sparseIndices + k * indexSize, sparseIndexType, false));
        for (size_t c = 0; c < n; ++c) {
          f(target, c, component(sparseValues + (k * n + c) * compSize, componentType, normalized));
        }
      }
    }
  };

  // The elements as float vectors of N components: the accessor's components (at most N) converted by
  // component() and then to float, any further ones 1 (a VEC3 colour read as VEC4 is opaque).
  template <int N>
  static std::vector<glm::vec<N, float>> floatVectors(const AccessorData& d) {
    using V = glm::vec<N, float>;
    std::vector<V> out;
    if (d.empty()) return out;
    const size_t n = d.count();
    const int have = std::min(N, d.components);
    out.resize(n, V(1.0f));
    if (!d.data) {
      for (V& v : out) {
        for (int c = 0; c < have; ++c) v[c] = 0.0f;
      }
    } else if (d.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT) {
      // float → double → float is the identity (up to NaN payloads, which the mesh repairs replace): copy.
      const size_t bytes = sizeof(float) * size_t(have);
      for (size_t e = 0; e < n; ++e) std::memcpy(&out[e], d.data + e * d.stride, bytes);
    } else {
      for (size_t e = 0; e < n; ++e) {
        for (int c = 0; c < have; ++c) out[e][c] = static_cast<float>(d.at(e, size_t(c)));
      }
    }
    d.applySparse([&](size_t e, size_t c, double v) {
      if (int(c) < have) out[e][int(c)] = static_cast<float>(v);
    });
    return out;
  }

  // The elements' components in order as doubles (double holds every 32-bit index exactly), sparse values
  // substituted.
  static std::vector<double> doubles(const AccessorData& d) {
    const auto n = size_t(d.components);
    std::vector<double> out(d.count() * n);
    for (size_t e = 0; e < d.count(); ++e) {
      for (size_t c = 0; c < n; ++c) out[e * n + c] = d.at(e, c);
    }
    d.applySparse([&](size_t e, size_t c, double v) { out[e * n + c] = v; });
    return out;
  }

  // A buffer view after checking that it lies inside its buffer (glTF 2.0 §3.6.1).
  const unsigned char* bufferViewData(int view, const std::string& referrer, const std::string& refPath,
                                      size_t* byteLength) const {
    if (view < 0 || size_t(view) >= model_.bufferViews.size()) {
      fail(refPath, referrer + " refers to buffer view " + std::to_string(view) + ", but the file has " +
                        std::to_string(model_.bufferViews.size()) + " buffer views");
    }
    const tinygltf::BufferView& bv = model_.bufferViews[size_t(view)];
    auto decoded = meshoptViews_.find(size_t(view));
    if (decoded != meshoptViews_.end()) {
      *byteLength = decoded->second.size();
      return decoded->second.data();
    }
    const std::string path = "/bufferViews/" + std::to_string(view);
    if (bv.buffer < 0 || size_t(bv.buffer) >= model_.buffers.size()) {
      fail(path + "/buffer", "buffer view " + std::to_string(view) + " refers to buffer " +
                                 std::to_string(bv.buffer) + ", but the file has " +
                                 std::to_string(model_.buffers.size()) + " buffers");
    }
    const std::vector<unsigned char>& data = model_.buffers[size_t(bv.buffer)].data;
    const size_t end = satMulAdd(bv.byteOffset, bv.byteLength, 1);
    if (end > data.size()) {
      fail(path,
           "buffer view " + std::to_string(view) + " covers bytes " + std::to_string(bv.byteOffset) + ".." +
               std::to_string(end) + " but buffer " + std::to_string(bv.buffer) + " has " +
               std::to_string(data.size()) + " bytes",
           kHintTruncated);
    }
    *byteLength = bv.byteLength;
    return data.data() + bv.byteOffset;
  }

  static size_t componentSize(int componentType) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE:
        return 1;
      case TINYGLTF_COMPONENT_TYPE_SHORT:
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT:
        return 2;
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
      case TINYGLTF_COMPONENT_TYPE_FLOAT:
        return 4;
      default:
        return 0;  // INT and DOUBLE are not glTF 2.0 accessor types (§3.6.2.2)
    }
  }

  // One component as a number. Normalised integers follow the glTF conversion (glTF 2.0 §3.11, repeated in
  // KHR_mesh_quantization): BYTE f = max(c / 127, −1), UNSIGNED_BYTE f = c / 255, SHORT f = max(c / 32767,
  // −1), UNSIGNED_SHORT f = c / 65535.
  static double component(const unsigned char* p, int componentType, bool normalized) {
    switch (componentType) {
      case TINYGLTF_COMPONENT_TYPE_BYTE: {
        int8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? std::max(c / 127.0, -1.0) : c;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: {
        uint8_t c;
        std::memcpy(&c, p, 1);
        return normalized ? c / 255.0 : c;
      }
      case TINYGLTF_COMPONENT_TYPE_SHORT: {
        int16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? std::max(c / 32767.0, -1.0) : c;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
        uint16_t c;
        std::memcpy(&c, p, 2);
        return normalized ? c / 65535.0 : c;
      }
      case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
        uint32_t c;
        std::memcpy(&c, p, 4);
        return normalized ? c / 4294967295.0 : c;
      }
      default: {  // FLOAT; componentSize() rejected the rest
        float c;
        std::memcpy(&c, p, 4);
        return c;
      }
    }
  }

  static const char* typeName(int type) {
    switch (type) {
      case TINYGLTF_TYPE_SCALAR:
        return "SCALAR";
      case TINYGLTF_TYPE_VEC2:
        return "VEC2";
      case TINYGLTF_TYPE_VEC3:
        return "VEC3";
      case TINYGLTF_TYPE_VEC4:
        return "VEC4";
      default:
        return "a matrix type";
    }
  }

  // Accessor `index` (glTF 2.0 §3.6.2), including byteStride and sparse substitution (§3.6.2.3), after
  // checking every byte range it touches. `role` says what it is for ("POSITION of mesh 'Wall' primitive 0");
  // `types` lists the glTF types the role allows.
  AccessorData readAccessor(int index, const std::string& role, const std::string& refPath,
                            std::initializer_list<int> types) const {
    if (index < 0 || size_t(index) >= model_.accessors.size()) {
      fail(refPath, role + " refers to accessor " + std::to_string(index) + ", but the file has " +
                        std::to_string(model_.accessors.size()) + " accessors");
    }
    const tinygltf::Accessor& a = model_.accessors[size_t(index)];
    const std::string path = "/accessors/" + std::to_string(index);
    const std::string label = "accessor " + std::to_string(index) + " (" + role + ")";
    if (std::find(types.begin(), types.end(), a.type) == types.end()) {
      std::string allowed;
      for (int t : types) allowed += std::string(allowed.empty() ? "" : " or ") + typeName(t);
      fail(path + "/type", label + " has type " + typeName(a.type) + "; it must be " + allowed);
    }
    const size_t compSize = componentSize(a.componentType);
    if (compSize == 0) {
      fail(path + "/componentType", label + " has componentType " + std::to_string(a.componentType) +
                                        ", which glTF 2.0 does not allow");
    }
    AccessorData out;
    out.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    out.componentType = a.componentType;
    out.normalized = a.normalized;
    out.elements = a.count;
    const auto components = size_t(out.components);
    const size_t elementSize = compSize * components;
    // Charged as fly stores it (4-byte floats and indices), before the file's data is looked at, so that a
    // claimed size beyond the budget fails here rather than in an allocation.
    charge(satMulAdd(0, a.count, components * 4), path + "/count",
           label + ", " + std::to_string(a.count) + " elements of " + typeName(a.type) + ",");
    // An accessor without a buffer view is all zeros (plus its sparse values); cap its size, since nothing in
    // the file bounds it.
    if (a.bufferView < 0 && a.count > (size_t(1) << 28)) {
      fail(path + "/count", label + " has " + std::to_string(a.count) + " elements and no data");
    }
    if (a.bufferView >= 0) {
      size_t viewLength = 0;
      const unsigned char* view = bufferViewData(a.bufferView, label, path + "/bufferView", &viewLength);
      const size_t viewStride = model_.bufferViews[size_t(a.bufferView)].byteStride;
      if (viewStride != 0 && viewStride < elementSize) {
        fail(path, label + " has elements of " + std::to_string(elementSize) + " bytes but buffer view " +
                       std::to_string(a.bufferView) + " has a byteStride of " + std::to_string(viewStride));
      }
      const size_t stride = viewStride ? viewStride : elementSize;
      const size_t end = a.count == 0
                             ? a.byteOffset
                             : satMulAdd(satMulAdd(a.byteOffset, stride, a.count - 1), elementSize, 1);
      if (end > viewLength) {
        fail(path,
             label + " reads bytes " + std::to_string(a.byteOffset) + ".." +
                 (end == SIZE_MAX ? std::string("∞") : std::to_string(end)) + " but buffer view " +
                 std::to_string(a.bufferView) + " has " + std::to_string(viewLength) + " bytes",
             kHintTruncated);
      }
      out.data = view + a.byteOffset;
      out.stride = stride;
    }
    if (a.sparse.isSparse) checkSparse(a, label, path, compSize, &out);
    return out;
  }

  // Sparse substitution (glTF 2.0 §3.6.2.3): `count` element indices and tightly packed values replace
  // elements. Checks their byte ranges and indices and points `out` at them.
  void checkSparse(const tinygltf::Accessor& a, const std::string& label, const std::string& path,
                   size_t compSize, AccessorData* out) const {
    const auto& sp = a.sparse;
    const std::string spath = path + "/sparse";
    if (sp.count < 0 || size_t(sp.count) > a.count) {
      fail(spath + "/count", label + " has " + std::to_string(sp.count) + " sparse values but " +
                                 std::to_string(a.count) + " elements");
    }
    const auto count = size_t(sp.count);
    const size_t indexSize = sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE    ? 1
                             : sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT ? 2
                             : sp.indices.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT   ? 4
                                                                                                  : 0;
    if (indexSize == 0) {
      fail(spath + "/indices/componentType",
           label + " has sparse indices of componentType " + std::to_string(sp.indices.componentType) +
               "; glTF allows UNSIGNED_BYTE, UNSIGNED_SHORT and UNSIGNED_INT");
    }
    if (sp.indices.byteOffset < 0 || sp.values.byteOffset < 0) {
      fail(spath, label + " has a negative sparse byteOffset");
    }
    const auto components = size_t(out->components);
    const size_t elementSize = compSize * components;
    auto range = [&](int view, size_t offset, size_t bytes, const char* what) {
      size_t viewLength = 0;
      const unsigned char* data =
          bufferViewData(view, label, spath + "/" + what + "/bufferView", &viewLength);
      if (offset + bytes > viewLength) {
        fail(spath + "/" + what,
             label + " reads sparse " + what + " at bytes " + std::to_string(offset) + ".." +
                 std::to_string(offset + bytes) + " but buffer view " + std::to_string(view) + " has " +
                 std::to_string(viewLength) + " bytes",
             kHintTruncated);
      }
      return data + offset;
    };
    // count ≤ a.count, which a buffer view or the cap in readAccessor bounds, so these products do not
    // overflow.
    const unsigned char* indices =
        range(sp.indices.bufferView, size_t(sp.indices.byteOffset), count * indexSize, "indices");
    const unsigned char* values =
        range(sp.values.bufferView, size_t(sp.values.byteOffset), count * elementSize, "values");
    for (size_t k = 0; k < count; ++k) {
      const auto target = size_t(component(indices + k * indexSize, sp.indices.componentType, false));
      if (target >= a.count) {
        fail(spath + "/indices", label + " has sparse index " + std::to_string(target) + ", past its " +
                                     std::to_string(a.count) + " elements");
      }
    }
    out->sparseCount = count;
    out->sparseIndices = indices;
    out->sparseIndexType = sp.indices.componentType;
    out->sparseValues = values;
  }

  // --- KHR_draco_mesh_compression: a primitive's attributes and triangles in one Draco bit stream.
  struct DracoPrimitive {
    DracoMesh mesh;
    std::map<std::string, int> ids;  // glTF attribute semantic → Draco attribute unique id
  };

  std::optional<DracoPrimitive> dracoPrimitive(const tinygltf::Primitive& prim, const std::string& where,
                                               const std::string& path) const {
    auto it = prim.extensions.find("KHR_draco_mesh_compression");
    if (it == prim.extensions.end()) return std::nullopt;
    const tinygltf::Value& ext = it->second;
    const std::string dpath = path + "/extensions/KHR_draco_mesh_compression";
    if (!ext.Get("bufferView").IsNumber()) {
      fail(dpath + "/bufferView", where + ": KHR_draco_mesh_compression needs a 'bufferView'");
    }
    const tinygltf::Value& attrs = ext.Get("attributes");
    if (!attrs.IsObject())
      fail(dpath + "/attributes", where + ": KHR_draco_mesh_compression needs 'attributes'");
    DracoPrimitive d;
    std::map<int, DracoAttributeRequest> requests;
    for (const std::string& semantic : attrs.Keys()) {
      const tinygltf::Value& id = attrs.Get(semantic);
      auto a = prim.attributes.find(semantic);
      if (!id.IsNumber() || a == prim.attributes.end()) {
        fail(dpath + "/attributes/" + semantic,
             where + ": the compressed attribute " + semantic +
                 " needs a Draco id (a number) and an accessor among the primitive's attributes");
      }
      if (a->second < 0 || size_t(a->second) >= model_.accessors.size()) {
        fail(path + "/attributes/" + semantic, semantic + " of " + where + " refers to accessor " +
                                                   std::to_string(a->second) + ", but the file has " +
                                                   std::to_string(model_.accessors.size()) + " accessors");
      }
      const tinygltf::Accessor& acc = model_.accessors[size_t(a->second)];
      const size_t compSize = componentSize(acc.componentType);
      if (compSize == 0) {
        fail("/accessors/" + std::to_string(a->second) + "/componentType",
             "accessor " + std::to_string(a->second) + " has componentType " +
                 std::to_string(acc.componentType) + ", which glTF 2.0 does not allow");
      }
      const int components = tinygltf::GetNumComponentsInType(uint32_t(acc.type));
      // Charged at the size the accessor declares, before the stream is decoded.
      charge(satMulAdd(0, acc.count, size_t(components) * 4),
             "/accessors/" + std::to_string(a->second) + "/count",
             "accessor " + std::to_string(a->second) + " (" + semantic + " of " + where + "), " +
                 std::to_string(acc.count) + " elements of " + typeName(acc.type) + ",");
      const bool isFloat = acc.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
      const bool isSigned = acc.componentType == TINYGLTF_COMPONENT_TYPE_BYTE ||
                            acc.componentType == TINYGLTF_COMPONENT_TYPE_SHORT;
      requests[id.GetNumberAsInt()] = {components, isFloat, int(compSize), isSigned};
      d.ids[semantic] = id.GetNumberAsInt();
    }
    if (!d.ids.count("POSITION")) fail(dpath + "/attributes", where + ": the Draco stream has no POSITION");
    size_t size = 0;
    const unsigned char* bytes = bufferViewData(ext.Get("bufferView").GetNumberAsInt(),
                                                where + " (Draco data)", dpath + "/bufferView", &size);
    try {
      d.mesh = decodeDracoMesh({bytes, size}, requests);
    } catch (const std::runtime_error& e) {
      fail(dpath, where + ": the Draco-compressed mesh cannot be decoded: " + e.what(), kHintTruncated);
    }
    const size_t declared = model_.accessors[size_t(prim.attributes.at("POSITION"))].count;
    if (d.mesh.pointCount != declared) {
      fail(dpath,
           where + ": the Draco stream has " + std::to_string(d.mesh.pointCount) +
               " points but the POSITION accessor declares " + std::to_string(declared),
           kHintTruncated);
    }
    return d;
  }

  // A decoded Draco attribute as accessor data, converted by glTF's rules for the accessor's componentType.
  AccessorData dracoAttribute(const DracoPrimitive& d, const std::string& semantic, int accessor,
                              const std::string& role, std::initializer_list<int> types) const {
    const tinygltf::Accessor& a = model_.accessors[size_t(accessor)];
    const std::string path = "/accessors/" + std::to_string(accessor);
    if (std::find(types.begin(), types.end(), a.type) == types.end()) {
      fail(path + "/type", "accessor " + std::to_string(accessor) + " (" + role + ") has type " +
                               typeName(a.type) + ", which " + semantic + " does not allow");
    }
    const std::vector<uint8_t>& bytes = d.mesh.attributes.at(d.ids.at(semantic));
    AccessorData out;
    out.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    out.componentType = a.componentType;
    out.normalized = a.normalized;
    out.stride = componentSize(a.componentType) * size_t(out.components);
    out.elements = bytes.size() / out.stride;
    out.data = bytes.data();
    return out;
  }

  // Triangle list from a primitive's vertex sequence (glTF 2.0 §3.7.2.1, "Topology types"):
  // strips p_i = {v_i, v_(i+(1+i%2)), v_(i+(2−i%2))}, fans p_i = {v_(i+1), v_(i+2), v_0}.
  std::vector<uint32_t> triangleList(std::vector<uint32_t>&& v, int mode, const std::string& where) {
    std::vector<uint32_t> out;
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      const size_t whole = v.size() / 3 * 3;
      if (whole != v.size()) {
        warn(where + " has " + std::to_string(v.size()) + " vertex indices, not a multiple of 3; the last " +
             std::to_string(v.size() - whole) + " are ignored");
      }
      v.resize(whole);
      return std::move(v);
    }
    if (v.size() < 3) return out;
    out.reserve((v.size() - 2) * 3);
    for (size_t i = 0; i + 2 < v.size(); ++i) {
      if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
        out.insert(out.end(), {v[i], v[i + 1 + i % 2], v[i + 2 - i % 2]});
      } else {
        out.insert(out.end(), {v[i + 1], v[i + 2], v[0]});
      }
    }
    return out;
  }

  std::optional<Mesh> convertPrimitive(size_t meshIndex, size_t primIndex) {
    const tinygltf::Mesh& gm = model_.meshes[meshIndex];
    const tinygltf::Primitive& prim = gm.primitives[primIndex];
    const std::string where = "mesh" +
                              (gm.name.empty() ? " " + std::to_string(meshIndex) : quotedName(gm.name)) +
                              " primitive " + std::to_string(primIndex);
    const std::string path =
        "/meshes/" + std::to_string(meshIndex) + "/primitives/" + std::to_string(primIndex);
    Mesh m;
    m.name = name(gm.name, "mesh", meshIndex);
    if (gm.primitives.size() > 1) m.name += "#" + std::to_string(primIndex);

    const int mode = prim.mode < 0 ? TINYGLTF_MODE_TRIANGLES : prim.mode;
    if (mode == TINYGLTF_MODE_POINTS || mode == TINYGLTF_MODE_LINE || mode == TINYGLTF_MODE_LINE_LOOP ||
        mode == TINYGLTF_MODE_LINE_STRIP) {
      warn("skipped " + where + ": it draws " + (mode == TINYGLTF_MODE_POINTS ? "points" : "lines") +
           ", and fly imports triangles only");
      return std::nullopt;
    }
    if (mode != TINYGLTF_MODE_TRIANGLES && mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      fail(path + "/mode", where + " has mode " + std::to_string(mode) + ", which glTF does not define");
    }
    auto attribute = [&](const char* semantic) {
      auto it = prim.attributes.find(semantic);
      return it == prim.attributes.end() ? -1 : it->second;
    };
    const int positionAccessor = attribute("POSITION");
    if (positionAccessor < 0) {
      warn("skipped " + where + ": it has no POSITION attribute");
      return std::nullopt;
    }

    // Vertex attributes (glTF 2.0 §3.7.2.1). Integer types other than those the core allows come from
    // KHR_mesh_quantization and are converted the same way.
    const std::string apath = path + "/attributes/";
    const std::optional<DracoPrimitive> draco = dracoPrimitive(prim, where, path);
    // An attribute from the Draco stream when the primitive is compressed and lists it, else its accessor.
    auto attributeData = [&](const std::string& semantic, int accessor, std::initializer_list<int> types) {
      const std::string role = semantic + " of " + where;
      if (draco && draco->ids.count(semantic)) return dracoAttribute(*draco, semantic, accessor, role, types);
      return readAccessor(accessor, role, apath + semantic, types);
    };
    const AccessorData pos = attributeData("POSITION", positionAccessor, {TINYGLTF_TYPE_VEC3});
    const size_t n = pos.count();
    auto read = [&](const char* semantic, std::initializer_list<int> types) -> AccessorData {
      const int a = attribute(semantic);
      if (a < 0) return {};
      AccessorData d = attributeData(semantic, a, types);
      if (d.count() != n) {
        fail("/accessors/" + std::to_string(a), "accessor " + std::to_string(a) + " (" + semantic + " of " +
                                                    where + ") has " + std::to_string(d.count()) +
                                                    " elements but POSITION has " + std::to_string(n));
      }
      return d;
    };
    const AccessorData normals = read("NORMAL", {TINYGLTF_TYPE_VEC3});
    const AccessorData tangents = read("TANGENT", {TINYGLTF_TYPE_VEC4});
    const AccessorData uv0 = read("TEXCOORD_0", {TINYGLTF_TYPE_VEC2});
    const AccessorData uv1 = read("TEXCOORD_1", {TINYGLTF_TYPE_VEC2});
    const AccessorData colors = read("COLOR_0", {TINYGLTF_TYPE_VEC3, TINYGLTF_TYPE_VEC4});

    m.positions = floatVectors<3>(pos);
    m.normals = floatVectors<3>(normals);
    m.tangents = floatVectors<4>(tangents);
    m.uv0 = floatVectors<2>(uv0);
    m.uv1 = floatVectors<2>(uv1);
    m.colors = floatVectors<4>(colors);  // VEC3 colours are opaque (w = 1)

    // Vertex sequence: the indices, or 0..n−1 for a non-indexed primitive.
    std::vector<uint32_t> sequence;
    if (draco) {
      // The compressed stream's triangles replace the indices accessor (KHR_draco_mesh_compression).
      if (mode != TINYGLTF_MODE_TRIANGLES) {
        fail(path + "/mode", where +
                                 " is Draco-compressed, which KHR_draco_mesh_compression allows for "
                                 "triangle lists (mode 4) only");
      }
      sequence = draco->mesh.indices;
      for (size_t k = 0; k < sequence.size(); ++k) {
        if (sequence[k] >= n) {
          fail(path + "/extensions/KHR_draco_mesh_compression",
               where + ": the Draco stream has index " + std::to_string(sequence[k]) + " at position " +
                   std::to_string(k) + ", past its " + std::to_string(n) + " points",
               kHintTruncated);
        }
      }
    } else if (prim.indices >= 0) {
      const std::string role = "indices of " + where;
      const AccessorData idx = readAccessor(prim.indices, role, path + "/indices", {TINYGLTF_TYPE_SCALAR});
      const tinygltf::Accessor& ia = model_.accessors[size_t(prim.indices)];
      const int ct = ia.componentType;
      if ((ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
           ct != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT) ||
          ia.normalized) {
        fail("/accessors/" + std::to_string(prim.indices) + "/componentType",
             "accessor " + std::to_string(prim.indices) + " (" + role +
                 ") must have componentType UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT and not be "
                 "normalized");
      }
      // Sparse indices are substituted before the check; plain ones are checked where they lie.
      const std::vector<double> substituted = idx.sparseCount ? doubles(idx) : std::vector<double>();
      sequence.resize(idx.count());
      for (size_t k = 0; k < idx.count(); ++k) {
        const double v = idx.sparseCount ? substituted[k] : idx.at(k, 0);
        if (v >= double(n)) {
          fail("/accessors/" + std::to_string(prim.indices),
               "accessor " + std::to_string(prim.indices) + " (" + role + ") has index " + str(v) +
                   " at position " + std::to_string(k) + ", past the vertex count " + std::to_string(n));
        }
        sequence[k] = static_cast<uint32_t>(v);
      }
    } else {
      sequence.resize(n);
      std::iota(sequence.begin(), sequence.end(), 0u);
    }
    m.indices = triangleList(std::move(sequence), mode, where);

    dropBadTriangles(&m);
    if (m.indices.empty()) {
      warn("mesh '" + m.name + "' has no triangles left and is dropped");
      return std::nullopt;
    }
    compactVertices(&m);
    if (m.normals.empty()) {
      flatNormals(&m);
    } else {
      repairNormals(&m);
    }
    repairTangents(&m);
    repairAttributes(&m);

    if (prim.material >= 0) {
      if (size_t(prim.material) >= model_.materials.size()) {
        fail(path + "/material", where + " refers to material " + std::to_string(prim.material) +
                                     ", but the file has " + std::to_string(model_.materials.size()) +
                                     " materials");
      }
      m.material = material(size_t(prim.material));
      m.twoSided = model_.materials[size_t(prim.material)].doubleSided;
    } else {
      m.material = defaultMaterial();
    }
    const std::string problem = validate(m);
    if (!problem.empty()) fail(path, where + ": " + problem);
    return m;
  }

  // Drops triangles with a NaN or infinite position, then degenerate ones: repeated vertices, or three points
  // on a line. "On a line" is relative to size: twice the area, |e1 × e2|, at most 1e-6 × the longest edge²,
  // i.e. a height below a millionth of the base, which float positions cannot resolve reliably.
  void dropBadTriangles(Mesh* m) {
    size_t kept = 0;  // the kept triangles' indices, compacted in place
    size_t nonFinite = 0;
    size_t degenerate = 0;
    for (size_t t = 0; t < m->indices.size(); t += 3) {
      const uint32_t i0 = m->indices[t], i1 = m->indices[t + 1], i2 = m->indices[t + 2];
      const vec3 &a = m->positions[i0], &b = m->positions[i1], &c = m->positions[i2];
      if (!isFinite(a) || !isFinite(b) || !isFinite(c)) {
        ++nonFinite;
        continue;
      }
      const dvec3 e1 = dvec3(b) - dvec3(a), e2 = dvec3(c) - dvec3(a), e3 = dvec3(c) - dvec3(b);
      const double longest2 = std::max({glm::dot(e1, e1), glm::dot(e2, e2), glm::dot(e3, e3)});
      if (i0 == i1 || i1 == i2 || i0 == i2 || glm::length(glm::cross(e1, e2)) <= 1e-6 * longest2) {
        ++degenerate;
        continue;
      }
      m->indices[kept++] = i0;
      m->indices[kept++] = i1;
      m->indices[kept++] = i2;
    }
    if (nonFinite) {
      warn("dropped " + std::to_string(nonFinite) + (nonFinite == 1 ? " triangle" : " triangles") +
           " with NaN or Inf positions in mesh '" + m->name + "'");
    }
    if (degenerate) {
      warn("dropped " + std::to_string(degenerate) + " degenerate " +
           (degenerate == 1 ? "triangle" : "triangles") + " in mesh '" + m->name + "'");
    }
    m->indices.resize(kept);
  }

  // Keeps only the vertices the triangles use, in their original order: primitives may share one large vertex
  // buffer, and dropped triangles leave vertices (possibly with NaN positions) behind.
  static void compactVertices(Mesh* m) {
    std::vector<bool> used(m->positions.size(), false);
    for (uint32_t i : m->indices) used[i] = true;
    if (std::find(used.begin(), used.end(), false) == used.end()) return;
    std::vector<uint32_t> remap(m->positions.size(), UINT32_MAX);
    uint32_t next = 0;
    for (size_t i = 0; i < remap.size(); ++i) {
      if (used[i]) remap[i] = next++;
    }
    auto compact = [&](auto& attr) {
      if (attr.empty()) return;
      size_t out = 0;
      for (size_t i = 0; i < attr.size(); ++i) {
        if (remap[i] != UINT32_MAX) attr[out++] = attr[i];
      }
      attr.resize(out);
    };
    compact(m->positions);
    compact(m->normals);
    compact(m->tangents);
    compact(m->uv0);
    compact(m->uv1);
    compact(m->colors);
    for (uint32_t& i : m->indices) i = remap[i];
  }

  static dvec3 faceNormal(const Mesh& m, size_t t) {  // |n| = twice the area; counter-clockwise = front
    const dvec3 a(m.positions[m.indices[t]]), b(m.positions[m.indices[t + 1]]),
        c(m.positions[m.indices[t + 2]]);
    return glm::cross(b - a, c - a);
  }

  // glTF 2.0 §3.7.2.1: "When normals are not specified, client implementations MUST calculate flat normals
  // and the provided tangents (if present) MUST be ignored." Each triangle gets vertices of its own.
  static void flatNormals(Mesh* m) {
    Mesh flat;
    const size_t corners = m->indices.size();
    flat.positions.reserve(corners);
    flat.normals.reserve(corners);
    for (size_t t = 0; t < corners; t += 3) {
      const vec3 n = vec3(glm::normalize(faceNormal(*m, t)));
      for (size_t k = 0; k < 3; ++k) {
        const uint32_t i = m->indices[t + k];
        flat.positions.push_back(m->positions[i]);
        flat.normals.push_back(n);
        if (!m->uv0.empty()) flat.uv0.push_back(m->uv0[i]);
        if (!m->uv1.empty()) flat.uv1.push_back(m->uv1[i]);
        if (!m->colors.empty()) flat.colors.push_back(m->colors[i]);
        flat.indices.push_back(static_cast<uint32_t>(t + k));
      }
    }
    m->positions = std::move(flat.positions);
    m->normals = std::move(flat.normals);
    m->uv0 = std::move(flat.uv0);
    m->uv1 = std::move(flat.uv1);
    m->colors = std::move(flat.colors);
    m->indices = std::move(flat.indices);
    m->tangents.clear();
  }

  // Normals must be unit length (§3.7.2.1). Zero-length or NaN ones are replaced by the area-weighted normal
  // of the triangles around the vertex; others that are off by more than 0.1 % are renormalised with a
  // warning (smaller errors are exporter rounding and are renormalised silently).
  void repairNormals(Mesh* m) {
    std::vector<size_t> bad;
    size_t renormalised = 0;
    for (size_t i = 0; i < m->normals.size(); ++i) {
      vec3& n = m->normals[i];
      const float len = glm::length(n);
      if (!std::isfinite(len) || len < 1e-12f) {
        bad.push_back(i);
        continue;
      }
      if (std::abs(len - 1.0f) > 1e-3f) ++renormalised;
      n /= len;
    }
    if (!bad.empty()) {
      std::vector<dvec3> sum(m->normals.size(), dvec3(0.0));
      for (size_t t = 0; t < m->indices.size(); t += 3) {
        const dvec3 fn = faceNormal(*m, t);
        for (size_t k = 0; k < 3; ++k) sum[m->indices[t + k]] += fn;
      }
      for (size_t i : bad) {
        const double len = glm::length(sum[i]);
        // Every vertex belongs to a triangle (compactVertices), but opposite faces can cancel.
        m->normals[i] = len > 0.0 ? vec3(sum[i] / len) : vec3(0.0f, 1.0f, 0.0f);
      }
      warn("replaced " + std::to_string(bad.size()) + " zero-length or NaN normals in mesh '" + m->name +
           "' with the normals of the triangles around them");
    }
    if (renormalised) {
      warn("renormalised " + std::to_string(renormalised) + " normals in mesh '" + m->name +
           "' that were not unit length");
    }
  }

  // Tangents: xyz unit length, w = ±1 (§3.7.2.1). One that cannot be repaired voids the whole set, since a
  // tangent frame needs all of them.
  void repairTangents(Mesh* m) {
    size_t bad = 0;
    for (vec4& t : m->tangents) {
      const float len = glm::length(vec3(t));
      if (!isFinite(t) || len < 1e-12f) {
        ++bad;
        continue;
      }
      t = vec4(vec3(t) / len, t.w < 0.0f ? -1.0f : 1.0f);
    }
    if (bad) {
      m->tangents.clear();
      warn("dropped the tangents of mesh '" + m->name + "': " + std::to_string(bad) +
           " of them are zero-length, NaN or Inf");
    }
  }

  // NaN or infinite texture coordinates and colours are replaced (0 and opaque white), so they cannot poison
  // light-map packing or shading.
  void repairAttributes(Mesh* m) {
    size_t bad = 0;
    for (auto* uv : {&m->uv0, &m->uv1}) {
      for (vec2& v : *uv) {
        if (!isFinite(v)) {
          v = vec2(0.0f);
          ++bad;
        }
      }
    }
    if (bad) {
      warn("replaced " + std::to_string(bad) + " NaN or Inf texture coordinates in mesh '" + m->name +
           "' with 0");
    }
    bad = 0;
    for (vec4& c : m->colors) {
      if (!isFinite(c)) {
        c = vec4(1.0f);
        ++bad;
      }
    }
    if (bad) {
      warn("replaced " + std::to_string(bad) + " NaN or Inf vertex colours in mesh '" + m->name +
           "' with white");
    }
  }

  // --- Materials (see the comment block at the top).
  MaterialId defaultMaterial() {
    if (!defaultMaterial_) {
      Material m;
      m.name = options_.namePrefix + "default";
      materials_.push_back(std::move(m));
      defaultMaterial_ = pendingId<MaterialId>(materials_.size() - 1);
    }
    return defaultMaterial_;
  }

  // A number from an extension object, `fallback` when absent.
  double extNumber(const tinygltf::Value& ext, const char* key, double fallback,
                   const std::string& path) const {
    const tinygltf::Value& v = ext.Get(key);
    if (v.Type() == tinygltf::NULL_TYPE) return fallback;
    if (!v.IsNumber()) fail(path + "/" + key, std::string("'") + key + "' must be a number");
    return v.GetNumberAsDouble();
  }

  std::vector<double> extNumbers(const tinygltf::Value& ext, const char* key, std::vector<double> fallback,
                                 const std::string& path) const {
    const tinygltf::Value& v = ext.Get(key);
    if (v.Type() == tinygltf::NULL_TYPE) return fallback;
    if (!v.IsArray() || v.ArrayLen() != fallback.size()) {
      fail(path + "/" + key,
           std::string("'") + key + "' must be an array of " + std::to_string(fallback.size()) + " numbers");
    }
    std::vector<double> out;
    for (size_t k = 0; k < v.ArrayLen(); ++k) {
      const tinygltf::Value& e = v.Get(int(k));
      if (!e.IsNumber()) fail(path + "/" + key, std::string("'") + key + "' must contain numbers only");
      out.push_back(e.GetNumberAsDouble());
    }
    return out;
  }

  // A factor that glTF restricts to [0, 1].
  float unitFactor(double v, const std::string& path, const std::string& what) const {
    if (!(v >= 0.0 && v <= 1.0)) fail(path, what + " is " + str(v) + "; glTF requires a value in [0, 1]");
    return float(v);
  }

  Rgb unitColor(const std::vector<double>& c, const std::string& path, const std::string& what) const {
    return Rgb(unitFactor(c[0], path, what), unitFactor(c[1], path, what), unitFactor(c[2], path, what));
  }

  // A material extension's object, or null when the material does not use it (tinygltf keeps only extensions
  // that are JSON objects).
  static const tinygltf::Value* extension(const tinygltf::Material& gm, const char* key) {
    auto it = gm.extensions.find(key);
    return it == gm.extensions.end() ? nullptr : &it->second;
  }

  // A textureInfo given as a JSON object inside a material extension (tinygltf leaves those as JSON values).
  TexInfo extensionTexInfo(const tinygltf::Value& ext, const char* key, const std::string& path) const {
    const tinygltf::Value& v = ext.Get(key);
    if (v.Type() == tinygltf::NULL_TYPE) return {};
    if (!v.IsObject() || !v.Get("index").IsNumber()) {
      fail(path + "/" + key, std::string("'") + key + "' needs an 'index'");
    }
    TexInfo t;
    t.index = v.Get("index").GetNumberAsInt();
    if (v.Get("texCoord").IsNumber()) t.texCoord = v.Get("texCoord").GetNumberAsInt();
    const tinygltf::Value& extensions = v.Get("extensions");
    if (extensions.Has("KHR_texture_transform")) t.transform = &extensions.Get("KHR_texture_transform");
    return t;
  }

  MaterialId material(size_t i) {
    auto cached = materialIds_.find(i);
    if (cached != materialIds_.end()) return cached->second;
    const tinygltf::Material& gm = model_.materials[i];
    const std::string path = "/materials/" + std::to_string(i);
    const std::string label = "material " + std::to_string(i) + quotedName(gm.name);
    const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
    const std::string ppath = path + "/pbrMetallicRoughness";
    Material m;
    m.name = name(gm.name, "material", i);

    const std::vector<double>& bc = pbr.baseColorFactor;  // tinygltf checks it has 4 numbers
    const Rgb base = unitColor(bc, ppath + "/baseColorFactor", label + " baseColorFactor");
    const float alpha = unitFactor(bc[3], ppath + "/baseColorFactor", label + " baseColorFactor alpha");
    // Metalness: where metallicRoughnessTexture's blue channel varies, the dielectric (metallic 0) with that
    // channel as Material::metalnessTexture, mixed per texel; otherwise one value for the whole material, the
    // factor times the channel's value.
    const float metallicFactor =
        unitFactor(pbr.metallicFactor, ppath + "/metallicFactor", label + " metallicFactor");
    const bool metalnessTexels =
        metallicFactor > 0.0f &&
        !constantChannel(pbr.metallicRoughnessTexture.index, 2, label + " metallicRoughnessTexture");
    const float metallic =
        metalnessTexels ? 0.0f
                        : metallicFactor * meanChannel(pbr.metallicRoughnessTexture.index, 2, false,
                                                       label + " metallicRoughnessTexture");
    const float roughness =
        unitFactor(pbr.roughnessFactor, ppath + "/roughnessFactor", label + " roughnessFactor");

    float ior = 1.5f;  // glTF's dielectric without KHR_materials_ior
    if (const tinygltf::Value* e = extension(gm, "KHR_materials_ior")) {
      const double v = extNumber(*e, "ior", 1.5, path + "/extensions/KHR_materials_ior");
      const double clamped = std::clamp(v, 1.0, 4.0);
      if (clamped != v) {
        warn(label + ": ior " + str(v) + " is outside fly's range [1, 4]; " + str(clamped) + " is used");
      }
      ior = float(clamped);
    }
    Rgb specularColor(1.0f);
    float specular = 1.0f;
    if (const tinygltf::Value* e = extension(gm, "KHR_materials_specular")) {
      const std::string epath = path + "/extensions/KHR_materials_specular";
      specular = unitFactor(extNumber(*e, "specularFactor", 1.0, epath), epath + "/specularFactor",
                            label + " specularFactor");
      const std::vector<double> c = extNumbers(*e, "specularColorFactor", {1.0, 1.0, 1.0}, epath);
      for (double x : c) {
        if (!(x >= 0.0 && std::isfinite(x))) {
          fail(epath + "/specularColorFactor", label + " specularColorFactor must be ≥ 0");
        }
      }
      // KHR_materials_specular lets specularColorFactor exceed 1 to raise F0 above F0(ior); reflectionColor
      // is at most 1, so that extra reflectance is lost.
      specularColor = glm::min(Rgb(float(c[0]), float(c[1]), float(c[2])), Rgb(1.0f));
      if (*std::max_element(c.begin(), c.end()) > 1.0) {
        warn(label + ": specularColorFactor above 1 is clamped to 1 (fly's reflection colour is at most 1)");
      }
      // Its textures scale the factors by their means (the realistic material has no per-texel specular
      // strength or colour): specularTexture's alpha (linear), specularColorTexture's RGB (sRGB).
      const int strength = checkedTextureIndex(extensionTexInfo(*e, "specularTexture", epath),
                                               epath + "/specularTexture");
      const int colour = checkedTextureIndex(extensionTexInfo(*e, "specularColorTexture", epath),
                                             epath + "/specularColorTexture");
      if (strength >= 0) specular *= meanChannel(strength, 3, false, label + " specularTexture");
      if (colour >= 0) specularColor *= meanColour(colour, true, label + " specularColorTexture");
      if (strength >= 0 || colour >= 0) {
        warn(label + ": the textures of KHR_materials_specular are applied as their mean over the image");
      }
    }
    m.ior = ior;
    m.reflectionGlossiness = roughness;
    m.diffuseColor = base * (1.0f - metallic);
    if (metallic >= 0.5f) {
      const Rgb dielectricF0 = glm::min(fresnelF0(ior) * specularColor, Rgb(1.0f)) * specular;
      m.reflectionModel = ReflectionModel::kUniform;
      m.reflectionColor = glm::mix(dielectricF0, base, metallic);
    } else {
      m.reflectionModel = ReflectionModel::kFresnel;
      m.reflectionColor = specularColor * specular;
    }
    bool coatIsLobe = false;
    const tinygltf::Value* coat = extension(gm, "KHR_materials_clearcoat");
    const std::string cpath = path + "/extensions/KHR_materials_clearcoat";
    if (coat) {
      ClearCoat c;
      c.amount = unitFactor(extNumber(*coat, "clearcoatFactor", 0.0, cpath), cpath + "/clearcoatFactor",
                            label + " clearcoatFactor");
      c.glossiness = unitFactor(extNumber(*coat, "clearcoatRoughnessFactor", 0.0, cpath),
                                cpath + "/clearcoatRoughnessFactor", label + " clearcoatRoughnessFactor");
      const CoatedMaterial coated = applyClearCoat(m, c);
      m = coated.material;
      coatIsLobe = coated.coatIsLobe;
      if (c.amount > 0.0f && !coatIsLobe) {
        warn(label + ": its clear coat is dropped: the " + (metallic >= 0.5f ? "metal's" : "base's") +
             " own reflection is the larger or sharper one, and fly's material has one reflection lobe");
      }
      if (coat->Has("clearcoatNormalTexture")) {
        warn(label + ": clearcoatNormalTexture is not imported; the coat follows the base's normals");
      }
    }
    if (const tinygltf::Value* e = extension(gm, "KHR_materials_sheen")) {
      const std::string spath = path + "/extensions/KHR_materials_sheen";
      Rgb sheenColor = unitColor(extNumbers(*e, "sheenColorFactor", {0.0, 0.0, 0.0}, spath),
                                 spath + "/sheenColorFactor", label + " sheenColorFactor");
      float sheenRoughness =
          unitFactor(extNumber(*e, "sheenRoughnessFactor", 0.0, spath), spath + "/sheenRoughnessFactor",
                     label + " sheenRoughnessFactor");
      // Its textures scale the factors by their means, as applySheen takes one sheen per material:
      // sheenColorTexture's RGB (sRGB), sheenRoughnessTexture's alpha (linear).
      const int colour = checkedTextureIndex(extensionTexInfo(*e, "sheenColorTexture", spath),
                                             spath + "/sheenColorTexture");
      const int rough = checkedTextureIndex(extensionTexInfo(*e, "sheenRoughnessTexture", spath),
                                            spath + "/sheenRoughnessTexture");
      if (colour >= 0) sheenColor *= meanColour(colour, true, label + " sheenColorTexture");
      if (rough >= 0) sheenRoughness *= meanChannel(rough, 3, false, label + " sheenRoughnessTexture");
      if (colour >= 0 || rough >= 0) {
        warn(label + ": the textures of KHR_materials_sheen are applied as their mean over the image");
      }
      m = applySheen(m, sheenColor, sheenRoughness);
    }
    if (pbr.baseColorTexture.index >= 0) {
      m.diffuseTexture = textureRef(
          texInfo(pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, pbr.baseColorTexture.extensions),
          ppath + "/baseColorTexture", label + " baseColorTexture", Channels::kAll);
    }
    // KHR_materials_anisotropy stretches the base's lobe; its conversion takes in the roughness texture.
    const tinygltf::Value* anisotropy = extension(gm, "KHR_materials_anisotropy");
    const bool anisotropic = anisotropy && importAnisotropy(*anisotropy, gm, path, label, coatIsLobe, &m);
    if (coatIsLobe) {
      // The lobe is the coat's: its factor (red) and roughness (green) textures take the reflection slots.
      m.reflectionTexture =
          textureRef(extensionTexInfo(*coat, "clearcoatTexture", cpath), cpath + "/clearcoatTexture",
                     label + " clearcoatTexture", Channels::kRed);
      m.reflectionGlossinessTexture = textureRef(extensionTexInfo(*coat, "clearcoatRoughnessTexture", cpath),
                                                 cpath + "/clearcoatRoughnessTexture",
                                                 label + " clearcoatRoughnessTexture", Channels::kGreen);
    } else {
      if (metallic >= 0.5f && m.diffuseTexture) {
        m.reflectionTexture = m.diffuseTexture;
        m.reflectionTextureSrgb = true;
      }
      if (!anisotropic && pbr.metallicRoughnessTexture.index >= 0) {
        const tinygltf::TextureInfo& t = pbr.metallicRoughnessTexture;
        m.reflectionGlossinessTexture =
            textureRef(texInfo(t.index, t.texCoord, t.extensions), ppath + "/metallicRoughnessTexture",
                       label + " metallicRoughnessTexture", Channels::kGreen);
      }
    }
    if (metalnessTexels) {
      const tinygltf::TextureInfo& t = pbr.metallicRoughnessTexture;
      m.metalnessTexture = textureRef(texInfo(t.index, t.texCoord, t.extensions),
                                      ppath + "/metallicRoughnessTexture", label + " metallicRoughnessTexture",
                                      Channels::kBlue);
      m.metalnessFactor = metallicFactor;
    }

    if (const tinygltf::Value* e = extension(gm, "KHR_materials_transmission")) {
      const std::string epath = path + "/extensions/KHR_materials_transmission";
      const float t = unitFactor(extNumber(*e, "transmissionFactor", 0.0, epath),
                                 epath + "/transmissionFactor", label + " transmissionFactor");
      m.transmissionColor = base * t * (1.0f - metallic);
      m.transmissionGlossiness = roughness;
      m.transmissionTexture =
          textureRef(extensionTexInfo(*e, "transmissionTexture", epath), epath + "/transmissionTexture",
                     label + " transmissionTexture", Channels::kRed);
      if (const tinygltf::Value* v = extension(gm, "KHR_materials_volume")) {
        const std::string vpath = path + "/extensions/KHR_materials_volume";
        const double distance =
            extNumber(*v, "attenuationDistance", std::numeric_limits<double>::infinity(), vpath);
        if (!(distance > 0.0)) {
          fail(vpath + "/attenuationDistance", label + " attenuationDistance must be > 0 m");
        }
        Rgb color = unitColor(extNumbers(*v, "attenuationColor", {1.0, 1.0, 1.0}, vpath),
                              vpath + "/attenuationColor", label + " attenuationColor");
        if (glm::any(glm::lessThan(color, Rgb(1e-4f)))) {
          // Beer–Lambert with colour 0 is an infinite absorption coefficient; 1e-4 is black for any thickness
          // that matters.
          color = glm::max(color, Rgb(1e-4f));
          warn(label + ": attenuationColor channels below 1e-4 are raised to 1e-4 (fully absorbing)");
        }
        m.scatteringColor = color;
        m.scatteringDistanceM = float(distance);
      }
    }
    m.opacity = alpha;
    if (gm.alphaMode == "MASK") {
      m.alphaMode = AlphaMode::kMask;
      m.alphaCutoff = unitFactor(gm.alphaCutoff, path + "/alphaCutoff", label + " alphaCutoff");
    } else if (gm.alphaMode == "BLEND") {
      m.alphaMode = AlphaMode::kBlend;
    } else if (gm.alphaMode != "OPAQUE") {
      fail(path + "/alphaMode",
           label + " has alphaMode '" + gm.alphaMode + "'; glTF defines OPAQUE, MASK and BLEND");
    }

    // tinygltf checks that emissiveFactor has 3 numbers.
    const Rgb emissive = unitColor(gm.emissiveFactor, path + "/emissiveFactor", label + " emissiveFactor");
    float strength = 1.0f;
    const tinygltf::Value* strengthExtension = extension(gm, "KHR_materials_emissive_strength");
    if (const tinygltf::Value* e = strengthExtension) {
      const std::string epath = path + "/extensions/KHR_materials_emissive_strength";
      const double s = extNumber(*e, "emissiveStrength", 1.0, epath);
      if (!(s >= 0.0 && std::isfinite(s))) {
        fail(epath + "/emissiveStrength", label + " emissiveStrength must be ≥ 0");
      }
      strength = float(s);
    }
    m.emissionLuminance = emissive * strength;
    // Without the extension, a display colour (sdb::Material::emissionDisplay).
    m.emissionDisplay = strengthExtension == nullptr && maxComponent(emissive) > 0.0f;
    if (gm.emissiveTexture.index >= 0) {
      m.emissionTexture = textureRef(
          texInfo(gm.emissiveTexture.index, gm.emissiveTexture.texCoord, gm.emissiveTexture.extensions),
          path + "/emissiveTexture", label + " emissiveTexture", Channels::kAll);
    }
    if (gm.normalTexture.index >= 0) {
      const tinygltf::NormalTextureInfo& t = gm.normalTexture;
      m.bumpTexture = textureRef(texInfo(t.index, t.texCoord, t.extensions), path + "/normalTexture",
                                 label + " normalTexture", Channels::kAll);
      if (!std::isfinite(t.scale)) {
        fail(path + "/normalTexture/scale", label + " normalTexture scale is not finite");
      }
      if (t.scale < 0.0) {
        warn(label + ": the negative normalTexture scale " + str(t.scale) + " is used as its absolute value");
      }
      m.bumpScale = float(std::abs(t.scale));
    }
    m.doubleSided = gm.doubleSided;

    const std::string problem = validate(m);
    if (!problem.empty()) fail(path, label + ": " + problem);
    materials_.push_back(std::move(m));
    return materialIds_[i] = pendingId<MaterialId>(materials_.size() - 1);
  }

  // KHR_materials_anisotropy (sdb/gltf_anisotropy.h): the base's roughness (factor and metallicRoughnessTexture)
  // and the extension's strength, rotation and texture become m's glossiness, anisotropy and rotation, as
  // constants or as textures on the anisotropy texture's grid (else the roughness texture's), sampled as that
  // texture is. The values are checked in any case; false, leaving m as it was, where the lobe stays isotropic
  // (strength 0, or roughness 1) or is the clear coat's (`coatIsLobe`), which the extension does not stretch.
  bool importAnisotropy(const tinygltf::Value& e, const tinygltf::Material& gm, const std::string& path,
                        const std::string& label, bool coatIsLobe, Material* m) {
    const std::string epath = path + "/extensions/KHR_materials_anisotropy";
    GltfAnisotropyInput in;
    in.roughness = float(gm.pbrMetallicRoughness.roughnessFactor);  // checked by material()
    in.strength = unitFactor(extNumber(e, "anisotropyStrength", 0.0, epath), epath + "/anisotropyStrength",
                             label + " anisotropyStrength");
    // JSON numbers are finite (the parser refuses 1e999); taken modulo a full turn, so that none becomes
    // infinite as a float.
    in.rotationRad = float(std::remainder(extNumber(e, "anisotropyRotation", 0.0, epath), 2.0 * kPi));
    int anisotropyImage = -1;
    const TextureRef anisotropyRef =
        sampling(extensionTexInfo(e, "anisotropyTexture", epath), epath + "/anisotropyTexture",
                 label + " anisotropyTexture", &anisotropyImage);
    if (in.strength <= 0.0f) return false;
    if (coatIsLobe) {
      warn(label +
           ": its anisotropy (KHR_materials_anisotropy) is dropped: the reflection lobe is the clear "
           "coat's, which the anisotropy does not stretch");
      return false;
    }
    const tinygltf::TextureInfo& mr = gm.pbrMetallicRoughness.metallicRoughnessTexture;
    const std::string mrWhat = label + " metallicRoughnessTexture";
    int roughnessImage = -1;
    const TextureRef roughnessRef =
        sampling(texInfo(mr.index, mr.texCoord, mr.extensions),
                 path + "/pbrMetallicRoughness/metallicRoughnessTexture", mrWhat, &roughnessImage);
    if (anisotropyImage >= 0) {
      in.anisotropyTexture = &decodedImage(size_t(anisotropyImage), label + " anisotropyTexture");
    }
    if (roughnessImage >= 0) {
      const UvTransform& a = anisotropyRef.transform;
      const UvTransform& r = roughnessRef.transform;
      if (in.anisotropyTexture && (anisotropyRef.texCoord != roughnessRef.texCoord || a.offset != r.offset ||
                                   a.rotationRad != r.rotationRad || a.scale != r.scale)) {
        in.roughness *= meanChannel(mr.index, 1, false, mrWhat);
        warn(label +
             ": its metallicRoughnessTexture and anisotropyTexture lie on different texture "
             "coordinates; the anisotropy is converted with the roughness's mean over the image");
      } else {
        in.roughnessTexture = &decodedImage(size_t(roughnessImage), mrWhat);
        in.roughnessWrapS = roughnessRef.wrapS;
        in.roughnessWrapT = roughnessRef.wrapT;
      }
    }
    GltfAnisotropyConversion c = convertGltfAnisotropy(in);
    if (!c.anisotropic) return false;
    m->reflectionGlossiness = c.glossiness;
    m->anisotropyU = c.anisotropyU;
    m->anisotropyV = c.anisotropyV;
    m->anisotropyRotationRad = c.rotationRad;
    const bool onAnisotropyGrid = in.anisotropyTexture != nullptr;
    const Texture* grid = onAnisotropyGrid ? in.anisotropyTexture : in.roughnessTexture;
    auto add = [&](std::optional<Texture>& t, const std::string& what) -> TextureRef {
      if (!t) return {};
      t->name = grid->name + " (" + what + ")";
      t->sourcePath = grid->sourcePath;
      charge(t->pixels.size(), onAnisotropyGrid ? epath + "/anisotropyTexture" : path, label + " " + what);
      textures_.push_back(std::move(*t));
      TextureRef ref = onAnisotropyGrid ? anisotropyRef : roughnessRef;
      ref.texture = pendingId<TextureId>(textures_.size() - 1);
      return ref;
    };
    m->reflectionGlossinessTexture = add(c.glossinessTexture, "glossiness");
    m->anisotropyTexture = add(c.anisotropyTexture, "anisotropy");
    m->anisotropyRotationTexture = add(c.rotationTexture, "anisotropy rotation");
    if (c.clampedTexels > 0) {
      const vec2 asked = gltfAnisotropicAlphas(in.roughness, in.strength);
      warn(label + ": its anisotropy stretches the lobe more than fly's limit of 10:1" +
           (c.texels > 1
                ? " at " + std::to_string(c.clampedTexels) + " of " + std::to_string(c.texels) + " texels"
                : " (GGX α " + str(asked.x) + " along, " + str(asked.y) + " across)") +
           "; there the lobe keeps glTF's width along the anisotropy direction and is a tenth of it across "
           "(docs/scene-format.md, \"Anisotropy\")");
    }
    return true;
  }

  // --- Textures (glTF 2.0 §3.8; KHR_texture_transform).
  TextureRef textureRef(const TexInfo& info, const std::string& path, const std::string& what,
                        Channels channels) {
    int image = -1;
    TextureRef ref = sampling(info, path, what, &image);
    if (image >= 0) ref.texture = imageTexture(size_t(image), channels, what);
    return ref;
  }

  // A texture reference checked and converted as textureRef does, without its texture: how it is sampled,
  // and in *image the glTF image it samples (−1 when there is none: no reference, or an image fly cannot read).
  TextureRef sampling(const TexInfo& info, const std::string& path, const std::string& what, int* image) {
    TextureRef ref;
    if (info.index < 0) return ref;
    if (size_t(info.index) >= model_.textures.size()) {
      fail(path + "/index", what + " refers to texture " + std::to_string(info.index) +
                                ", but the file has " + std::to_string(model_.textures.size()) + " textures");
    }
    int texCoord = info.texCoord;
    if (info.transform) {
      const std::string tpath = path + "/extensions/KHR_texture_transform";
      if (!info.transform->IsObject()) fail(tpath, what + ": KHR_texture_transform must be a JSON object");
      const std::vector<double> offset = extNumbers(*info.transform, "offset", {0.0, 0.0}, tpath);
      const std::vector<double> scale = extNumbers(*info.transform, "scale", {1.0, 1.0}, tpath);
      const double rotation = extNumber(*info.transform, "rotation", 0.0, tpath);
      for (double v : {offset[0], offset[1], scale[0], scale[1], rotation}) {
        if (!std::isfinite(v)) fail(tpath, what + " has a NaN or infinite KHR_texture_transform value");
      }
      ref.transform.offset = vec2(float(offset[0]), float(offset[1]));
      ref.transform.scale = vec2(float(scale[0]), float(scale[1]));
      ref.transform.rotationRad = float(rotation);
      texCoord = int(extNumber(*info.transform, "texCoord", texCoord, tpath));  // overrides the textureInfo's
    }
    if (texCoord < 0) fail(path + "/texCoord", what + " has texCoord " + std::to_string(texCoord));
    if (texCoord > 1) {
      warn(what + " uses TEXCOORD_" + std::to_string(texCoord) +
           ", which fly does not import; TEXCOORD_0 is used instead");
      texCoord = 0;
    }
    ref.texCoord = texCoord;
    const tinygltf::Texture& t = model_.textures[size_t(info.index)];
    if (t.source < 0) {
      warn(what + ": texture " + std::to_string(info.index) +
           " has no image fly can read (it may come from an unsupported extension); the material has no "
           "texture "
           "there");
      return {};
    }
    if (size_t(t.source) >= model_.images.size()) {
      fail("/textures/" + std::to_string(info.index) + "/source",
           "texture " + std::to_string(info.index) + " refers to image " + std::to_string(t.source) +
               ", but the file has " + std::to_string(model_.images.size()) + " images");
    }
    if (t.sampler >= 0) {
      if (size_t(t.sampler) >= model_.samplers.size()) {
        fail("/textures/" + std::to_string(info.index) + "/sampler",
             "texture " + std::to_string(info.index) + " refers to sampler " + std::to_string(t.sampler) +
                 ", but the file has " + std::to_string(model_.samplers.size()) + " samplers");
      }
      const tinygltf::Sampler& s = model_.samplers[size_t(t.sampler)];
      const std::string spath = "/samplers/" + std::to_string(t.sampler);
      ref.wrapS = wrapMode(s.wrapS, spath + "/wrapS");
      ref.wrapT = wrapMode(s.wrapT, spath + "/wrapT");
      ref.magFilter = magFilter(s.magFilter, spath + "/magFilter");
      ref.minFilter = minFilter(s.minFilter, spath + "/minFilter");
    }
    *image = t.source;
    return ref;
  }

  // The mean over texture `index`'s image of channel `channel` (0 red, 1 green, 2 blue, 3 alpha), in [0, 1],
  // each texel sRGB-decoded first when `srgb`; 1 when there is no such texture or image (textureRef reports
  // what is wrong with a reference; checkedTextureIndex for textures that are only averaged).
  float meanChannel(int index, int channel, bool srgb, const std::string& what) {
    if (index < 0 || size_t(index) >= model_.textures.size()) return 1.0f;
    const int source = model_.textures[size_t(index)].source;
    if (source < 0 || size_t(source) >= model_.images.size()) return 1.0f;
    const Texture& t = decodedImage(size_t(source), what);
    if (channel >= t.channels) return 1.0f;
    const size_t bytes = size_t(t.bitsPerChannel / 8);
    const size_t pixels = size_t(t.width) * size_t(t.height);
    if (pixels == 0) return 1.0f;
    const double maxValue = bytes == 2 ? 65535.0 : 255.0;
    double sum = 0.0;
    for (size_t p = 0; p < pixels; ++p) {
      const uint8_t* b = &t.pixels[(p * size_t(t.channels) + size_t(channel)) * bytes];
      uint16_t v = b[0];
      if (bytes == 2) std::memcpy(&v, b, 2);
      sum += srgb ? double(srgbToLinear(float(double(v) / maxValue))) : double(v) / maxValue;
    }
    return float(sum / double(pixels));
  }
  // Whether a channel of a texture's image has one value at every pixel (true where there is no such image
  // or channel, which meanChannel reads as 1).
  bool constantChannel(int index, int channel, const std::string& what) {
    if (index < 0 || size_t(index) >= model_.textures.size()) return true;
    const int source = model_.textures[size_t(index)].source;
    if (source < 0 || size_t(source) >= model_.images.size()) return true;
    const Texture& t = decodedImage(size_t(source), what);
    if (channel >= t.channels) return true;
    const size_t bytes = size_t(t.bitsPerChannel / 8);
    const size_t pixels = size_t(t.width) * size_t(t.height);
    const size_t stride = size_t(t.channels) * bytes;
    const uint8_t* first = &t.pixels[size_t(channel) * bytes];
    for (size_t p = 1; p < pixels; ++p) {
      if (std::memcmp(first + p * stride, first, bytes) != 0) return false;
    }
    return true;
  }
  Rgb meanColour(int index, bool srgb, const std::string& what) {
    return {meanChannel(index, 0, srgb, what), meanChannel(index, 1, srgb, what),
            meanChannel(index, 2, srgb, what)};
  }

  // The texture index of a textureInfo whose texture is only averaged (never sampled), checked as
  // textureRef checks a sampled one; −1 when there is none.
  int checkedTextureIndex(const TexInfo& info, const std::string& path) const {
    if (info.index < 0) return -1;
    if (size_t(info.index) >= model_.textures.size()) {
      fail(path + "/index", "refers to texture " + std::to_string(info.index) + ", but the file has " +
                                std::to_string(model_.textures.size()) + " textures");
    }
    return info.index;
  }

  // A sampler's wrapS or wrapT (glTF 2.0 §5.26: 33071, 33648 or 10497, the default).
  WrapMode wrapMode(int value, const std::string& path) {
    switch (value) {
      case TINYGLTF_TEXTURE_WRAP_REPEAT:
        return WrapMode::kRepeat;
      case TINYGLTF_TEXTURE_WRAP_CLAMP_TO_EDGE:
        return WrapMode::kClampToEdge;
      case TINYGLTF_TEXTURE_WRAP_MIRRORED_REPEAT:
        return WrapMode::kMirroredRepeat;
      default:
        fail(path,
             "wrap mode " + std::to_string(value) +
                 " is not one of glTF's 33071 (CLAMP_TO_EDGE), 33648 (MIRRORED_REPEAT), 10497 (REPEAT)");
    }
  }

  // A sampler's magFilter (glTF 2.0 §5.26: 9728 NEAREST or 9729 LINEAR; −1, undefined, is linear).
  MagFilter magFilter(int value, const std::string& path) {
    switch (value) {
      case -1:
      case TINYGLTF_TEXTURE_FILTER_LINEAR:
        return MagFilter::kLinear;
      case TINYGLTF_TEXTURE_FILTER_NEAREST:
        return MagFilter::kNearest;
      default:
        fail(path, "magFilter " + std::to_string(value) + " is not one of glTF's 9728 (NEAREST), 9729 (LINEAR)");
    }
  }

  // A sampler's minFilter (glTF 2.0 §5.26: 9728, 9729, 9984–9987; −1, undefined, is trilinear).
  MinFilter minFilter(int value, const std::string& path) {
    switch (value) {
      case -1:
      case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_LINEAR:
        return MinFilter::kLinearMipmapLinear;
      case TINYGLTF_TEXTURE_FILTER_NEAREST:
        return MinFilter::kNearest;
      case TINYGLTF_TEXTURE_FILTER_LINEAR:
        return MinFilter::kLinear;
      case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_NEAREST:
        return MinFilter::kNearestMipmapNearest;
      case TINYGLTF_TEXTURE_FILTER_LINEAR_MIPMAP_NEAREST:
        return MinFilter::kLinearMipmapNearest;
      case TINYGLTF_TEXTURE_FILTER_NEAREST_MIPMAP_LINEAR:
        return MinFilter::kNearestMipmapLinear;
      default:
        fail(path, "minFilter " + std::to_string(value) +
                       " is not one of glTF's 9728 (NEAREST), 9729 (LINEAR), 9984–9987 (the mipmap filters)");
    }
  }

  // `usedBy` names the first material slot that uses the image, for messages.
  TextureId imageTexture(size_t image, Channels channels, const std::string& usedBy) {
    const auto key = std::make_pair(image, channels);
    auto cached = textureIds_.find(key);
    if (cached != textureIds_.end()) return cached->second;
    const Texture& decoded = decodedImage(image, usedBy);
    if (channels == Channels::kAll) {
      textures_.push_back(decoded);
    } else {
      // One channel of the RGBA image, as a grey texture of its own.
      Texture grey;
      const int channel = channels == Channels::kRed ? 0 : channels == Channels::kGreen ? 1 : 2;
      constexpr const char* kNames[3] = {" (red)", " (green)", " (blue)"};
      grey.name = decoded.name + kNames[channel];
      grey.sourcePath = decoded.sourcePath;
      grey.width = decoded.width;
      grey.height = decoded.height;
      grey.channels = 1;
      grey.bitsPerChannel = decoded.bitsPerChannel;
      const size_t bytes = size_t(decoded.bitsPerChannel / 8);
      const size_t pixelBytes = bytes * size_t(decoded.channels);
      const size_t offset = size_t(channel) * bytes;
      const size_t pixels = size_t(decoded.width) * size_t(decoded.height);
      grey.pixels.resize(pixels * bytes);
      for (size_t p = 0; p < pixels; ++p) {
        std::memcpy(&grey.pixels[p * bytes], &decoded.pixels[p * pixelBytes + offset], bytes);
      }
      textures_.push_back(std::move(grey));
    }
    return textureIds_[key] = pendingId<TextureId>(textures_.size() - 1);
  }

  const Texture& decodedImage(size_t i, const std::string& usedBy) {
    auto cached = decoded_.find(i);
    if (cached != decoded_.end()) return cached->second;
    const tinygltf::Image& img = model_.images[i];
    const std::string path = "/images/" + std::to_string(i);
    const std::string label = "image " + std::to_string(i) + quotedName(img.name) + " (" + usedBy + ")";
    const unsigned char* bytes = nullptr;
    size_t size = 0;
    std::string source = "<embedded>";
    if (img.bufferView >= 0) {
      bytes = bufferViewData(img.bufferView, label, path + "/bufferView", &size);
    } else if (!img.uri.empty()) {  // tinygltf keeps `uri` only for external files
      const fs::path file = baseDir_ / percentDecode(img.uri);
      source = file.string();
      if (img.image.empty()) {
        std::error_code ec;
        if (!fs::is_regular_file(file, ec)) {
          fail(path + "/uri",
               label + " refers to '" + img.uri + "', which does not exist (looked for " + source + ")",
               "copy the texture next to the glTF file, keeping its relative path, or export a .glb with "
               "embedded "
               "textures");
        }
        fail(path + "/uri", label + ": '" + source + "' is empty or cannot be read",
             "check the file and its permissions, or export the model again");
      }
      bytes = img.image.data();
      size = img.image.size();
    } else {
      bytes = img.image.data();  // decoded from a data: URI
      size = img.image.size();
    }
    if (size == 0) fail(path, label + " has no data", kHintTruncated);
    const std::string data = img.uri.empty() ? "its embedded data" : "'" + source + "'";
    if (size > size_t(INT_MAX)) fail(path, label + " is larger than 2 GiB");
    const std::span<const uint8_t> encoded(bytes, size);
    const ImageFormat format = imageFormat(encoded);
    if (format == ImageFormat::kKtx2) {
      fail(path,
           label + ": " + data +
               " is a KTX2 (Basis Universal) texture, the format of the glTF extension "
               "KHR_texture_basisu, which fly cannot decode",
           "convert the texture to PNG or JPEG (e.g. with KTX-Software: `ktx extract " +
               (img.uri.empty() ? std::string("TEXTURE.ktx2") : percentDecode(img.uri)) +
               " OUT.png`) and refer to the PNG or JPEG in the glTF file");
    }
    Texture t;
    std::vector<std::string> notes;
    uint64_t charged = 0;
    if (format == ImageFormat::kPng || format == ImageFormat::kJpeg) {
      // The header's size is checked against the budget before anything is decoded.
      const std::optional<ImageSize> header = imageSize(encoded, format);
      if (!header) fail(path, label + ": " + data + " has no readable image header", kHintTruncated);
      charged = checkImageSize(*header, encoded.size(), path, label + ": " + data);
    }
    if (const ImageDecoder& decoder = installedImageDecoder()) {
      budgetLeft_ += charged;  // the decoder checks the size itself; the budget is charged what it returns
      try {
        t = decoder(encoded, size_t(std::min<uint64_t>(budgetLeft_, SIZE_MAX)), notes);
      } catch (const std::runtime_error& e) {
        fail(path, label + ": " + data + ": " + e.what(),
             "the image is damaged or in a variant the decoder does not read; save it again as an ordinary "
             "PNG or JPEG");
      }
      const size_t expected = size_t(t.width) * size_t(t.height) * 4 * size_t(t.bitsPerChannel / 8);
      if (t.channels != 4 || (t.bitsPerChannel != 8 && t.bitsPerChannel != 16) || t.width <= 0 ||
          t.height <= 0 || t.pixels.size() != expected) {
        throw std::logic_error("the installed image decoder returned a texture that breaks its contract");
      }
      charge(t.pixels.size(), path, label + ": " + data);
    } else {
      if (format != ImageFormat::kPng && format != ImageFormat::kJpeg) {
        fail(path,
             label + ": " + data + " is " + formatName(format) +
                 "; without an image decoder installed fly reads PNG and JPEG, the formats glTF 2.0 allows",
             "convert the texture to PNG or JPEG, or use the fly program, which decodes WebP, HDR, EXR and "
             "TIFF through OpenImageIO");
      }
      // stb_image, which tinygltf uses, expands every image to RGBA when given no options; 16-bit PNGs keep
      // 16 bits. The format check keeps other formats away from it: its 16-bit PNM path in the version
      // tinygltf uses writes fewer bytes than tinygltf copies.
      tinygltf::Image out;
      out.name = img.name;
      std::string err;
      std::string unused;
      if (!tinygltf::LoadImageData(&out, int(i), &err, &unused, 0, 0, bytes, int(size), nullptr)) {
        while (!err.empty() && (err.back() == '\n' || err.back() == '.')) err.pop_back();
        fail(path, label + ": " + data + " cannot be decoded: " + err,
             "the image is damaged or uses a PNG or JPEG variant stb_image does not read (e.g. 12-bit or "
             "arithmetic-coded JPEG); save it again as an ordinary PNG or JPEG");
      }
      t.width = out.width;
      t.height = out.height;
      t.channels = out.component;
      t.bitsPerChannel = out.bits;
      t.pixels = std::move(out.image);
    }
    for (const std::string& n : notes) warn(label + ": " + n);
    t.name = options_.namePrefix;
    if (!img.name.empty()) {
      t.name += img.name;
    } else if (!img.uri.empty()) {
      t.name += fs::path(percentDecode(img.uri)).stem().string();
    } else {
      t.name += "image" + std::to_string(i);
    }
    t.sourcePath = source;
    return decoded_[i] = std::move(t);
  }

  // --- Adding everything to the Scene, placeholders replaced by the ids it gives.
  template <class IdT>
  IdT add(Added<IdT> added) {
    result_.changes.merge(added.changes);
    return added.id;
  }

  void commit() {
    std::vector<TextureId> textureIds;
    for (Texture& t : textures_) textureIds.push_back(add(scene_.addTexture(std::move(t))));
    std::vector<MaterialId> materialIds;
    for (Material& m : materials_) {
      for (TextureRef* r :
           {&m.diffuseTexture, &m.reflectionTexture, &m.reflectionGlossinessTexture, &m.anisotropyTexture,
            &m.anisotropyRotationTexture, &m.transmissionTexture, &m.metalnessTexture, &m.bumpTexture,
            &m.emissionTexture}) {
        if (*r) r->texture = textureIds[r->texture.value - 1];
      }
      materialIds.push_back(add(scene_.addMaterial(std::move(m))));
    }
    // A mesh that only mirrored nodes use was converted just to make its mirrored copy; it is not added.
    std::vector<bool> used(meshes_.size(), false);
    for (const PendingNode& pn : nodes_) {
      for (MeshId id : pn.node.meshes) used[id.value - 1] = true;
    }
    std::vector<MeshId> meshIds(meshes_.size());
    for (size_t i = 0; i < meshes_.size(); ++i) {
      if (!used[i]) continue;
      Mesh& m = meshes_[i];
      m.material = materialIds[m.material.value - 1];
      meshIds[i] = add(scene_.addMesh(std::move(m)));
    }
    std::vector<CameraId> cameraIds;
    for (Camera& c : cameras_) cameraIds.push_back(add(scene_.addCamera(std::move(c))));
    std::vector<LightId> lightIds;
    for (Light& l : lights_) lightIds.push_back(add(scene_.addLight(std::move(l))));
    std::vector<NodeId> nodeIds;
    for (PendingNode& pn : nodes_) {  // parents come before their children
      Node& n = pn.node;
      n.parent = pn.parent < 0 ? options_.parent : nodeIds[size_t(pn.parent)];
      for (MeshId& id : n.meshes) id = meshIds[id.value - 1];
      if (n.camera) n.camera = cameraIds[n.camera.value - 1];
      if (n.light) n.light = lightIds[n.light.value - 1];
      nodeIds.push_back(add(scene_.addNode(std::move(n))));
      if (pn.parent < 0) result_.roots.push_back(nodeIds.back());
    }
  }

  Scene& scene_;
  const GltfImportOptions& options_;
  fs::path file_;
  std::string fileStr_;
  fs::path baseDir_;
  tinygltf::Model model_;
  GltfImportResult result_;
  mutable uint64_t budgetLeft_ = options_.maxDecodedBytes;  // charge() runs in const readers too

  // Converted entities waiting for commit(); placeholder ids index them.
  std::vector<Texture> textures_;
  std::vector<Material> materials_;
  std::vector<Mesh> meshes_;
  std::vector<Camera> cameras_;
  std::vector<Light> lights_;
  std::vector<PendingNode> nodes_;

  // From glTF indices to placeholders, so that shared entities are converted once.
  std::map<size_t, Texture> decoded_;
  std::map<size_t, std::vector<uint8_t>> meshoptViews_;  // EXT_meshopt_compression views, decoded
  std::map<std::pair<size_t, Channels>, TextureId> textureIds_;
  std::map<size_t, MaterialId> materialIds_;
  std::map<size_t, CameraId> cameraIds_;
  std::map<size_t, LightId> lightIds_;
  std::vector<MeshEntry> meshEntries_;
  MaterialId defaultMaterial_;
};

}  // namespace

void setImageDecoder(ImageDecoder decoder) {
  imageDecoderSlot() = std::move(decoder);
}

GltfImportResult importGltf(Scene& scene, const std::filesystem::path& file,
                            const GltfImportOptions& options) {
  return Importer(scene, file, options).run();
}

}  // namespace fly::sdb
