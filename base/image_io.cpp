#include "base/image_io.h"

#include <Iex.h>
#include <ImfChannelList.h>
#include <ImfFrameBuffer.h>
#include <ImfHeader.h>
#include <ImfIO.h>
#include <ImfInputFile.h>
#include <ImfOutputFile.h>
#include <ImfStringAttribute.h>
#include <stb_image.h>
#include <stb_image_write.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <string_view>

#include "base/error.h"
#include "base/file_io.h"

namespace fly {

namespace fs = std::filesystem;

namespace {

// Largest image read or written, in pixels: 16384², 3.2 GB of float RGB. Beyond it a header is more likely
// corrupt than real, and stb's int sizes would overflow.
constexpr int64_t kMaxPixels = int64_t{1} << 28;

// The file is built in memory and written with writeFileAtomic, so that a failed write leaves no partial
// file.
class MemoryOStream : public Imf::OStream {
 public:
  explicit MemoryOStream(const char* fileName) : Imf::OStream(fileName) {}

  void write(const char c[], int n) override {
    const size_t count = static_cast<size_t>(n);
    if (pos_ + count > bytes_.size()) bytes_.resize(pos_ + count);
    std::memcpy(bytes_.data() + pos_, c, count);
    pos_ += count;
  }
  uint64_t tellp() override { return pos_; }
  void seekp(uint64_t pos) override { pos_ = static_cast<size_t>(pos); }

  const std::string& bytes() const { return bytes_; }

 private:
  std::string bytes_;
  size_t pos_ = 0;
};

class MemoryIStream : public Imf::IStream {
 public:
  MemoryIStream(std::string_view bytes, const char* fileName) : Imf::IStream(fileName), bytes_(bytes) {}

  bool read(char c[], int n) override {
    const size_t count = static_cast<size_t>(n);
    if (count > bytes_.size() - pos_) throw Iex::InputExc("unexpected end of file");
    std::memcpy(c, bytes_.data() + pos_, count);
    pos_ += count;
    return pos_ < bytes_.size();
  }
  uint64_t tellg() override { return pos_; }
  void seekg(uint64_t pos) override { pos_ = static_cast<size_t>(std::min<uint64_t>(pos, bytes_.size())); }

 private:
  std::string_view bytes_;
  size_t pos_ = 0;
};

constexpr const char* kRgbNames[3] = {"R", "G", "B"};

// writeFileAtomic names its temporary file; the caller wants the file it asked for.
void writeOutput(const fs::path& path, std::string_view bytes) {
  try {
    writeFileAtomic(path, bytes);
  } catch (const std::runtime_error& e) {
    throw std::runtime_error("cannot write " + path.string() + ": " + e.what());
  }
}

}  // namespace

void writeExr(const fs::path& path, const ImageRgbF& image, const ExrAttributes& attributes) {
  const std::string where = "writeExr(" + path.string() + "): ";
  if (image.width < 1 || image.height < 1 || int64_t{image.width} * image.height > kMaxPixels) {
    throw std::invalid_argument(where + "image size " + std::to_string(image.width) + "×" +
                                std::to_string(image.height) + " is empty or over 2^28 pixels");
  }
  const size_t values = 3 * static_cast<size_t>(image.width) * static_cast<size_t>(image.height);
  if (image.rgb.size() != values) {
    throw std::invalid_argument(where + "rgb holds " + std::to_string(image.rgb.size()) +
                                " floats, expected " + std::to_string(values));
  }
  const auto bad =
      std::find_if(image.rgb.begin(), image.rgb.end(), [](float v) { return !std::isfinite(v); });
  if (bad != image.rgb.end()) {
    const size_t pixel = static_cast<size_t>(bad - image.rgb.begin()) / 3;
    throw std::invalid_argument(where + "non-finite value at pixel (" +
                                std::to_string(pixel % static_cast<size_t>(image.width)) + ", " +
                                std::to_string(pixel / static_cast<size_t>(image.width)) + ")");
  }

  Imf::Header header(image.width, image.height);
  header.compression() = Imf::ZIP_COMPRESSION;
  for (const char* name : kRgbNames) header.channels().insert(name, Imf::Channel(Imf::FLOAT));
  for (const auto& [name, value] : attributes) {
    if (name.empty() || header.find(name) != header.end()) {
      throw std::invalid_argument(where + "attribute name '" + name +
                                  "' is empty, repeated or OpenEXR's own");
    }
    header.insert(name, Imf::StringAttribute(value));
  }

  MemoryOStream stream(path.c_str());
  {
    Imf::OutputFile file(stream, header);
    Imf::FrameBuffer frame;
    // OpenEXR's Slice takes a mutable pointer but only reads through it when writing.
    char* base = reinterpret_cast<char*>(const_cast<float*>(image.rgb.data()));
    const size_t xStride = 3 * sizeof(float);
    const size_t yStride = xStride * static_cast<size_t>(image.width);
    for (int c = 0; c < 3; ++c) {
      frame.insert(kRgbNames[c], Imf::Slice(Imf::FLOAT, base + c * sizeof(float), xStride, yStride));
    }
    file.setFrameBuffer(frame);
    file.writePixels(image.height);
  }  // the destructor writes the scan-line offset table
  writeOutput(path, stream.bytes());
}

ImageRgbF readExr(const fs::path& path, ExrAttributes* attributes) {
  const std::string bytes = readInputFile(path, "OpenEXR file");
  const SourceLocation loc{path.string()};
  MemoryIStream stream(bytes, path.c_str());
  ImageRgbF image;
  try {
    Imf::InputFile file(stream);
    const Imf::Header& header = file.header();
    for (const char* name : kRgbNames) {
      if (header.channels().findChannel(name) == nullptr) {
        throw InputError(loc, std::string("OpenEXR file has no ") + name + " channel",
                         "fly reads RGB images; save the image with R, G and B channels");
      }
    }
    const Imath::Box2i window = header.dataWindow();
    const int64_t width = int64_t{window.max.x} - window.min.x + 1;
    const int64_t height = int64_t{window.max.y} - window.min.y + 1;
    if (width < 1 || height < 1 || width * height > kMaxPixels) {
      throw InputError(loc, "OpenEXR data window " + std::to_string(width) + "×" + std::to_string(height) +
                                " is empty or over 2^28 pixels");
    }
    image.width = static_cast<int>(width);
    image.height = static_cast<int>(height);
    image.rgb.resize(3 * static_cast<size_t>(width * height));
    Imf::FrameBuffer frame;
    const size_t xStride = 3 * sizeof(float);
    for (int c = 0; c < 3; ++c) {
      frame.insert(kRgbNames[c], Imf::Slice::Make(Imf::FLOAT, image.rgb.data() + c, window, xStride,
                                                  xStride * static_cast<size_t>(width)));
    }
    file.setFrameBuffer(frame);
    file.readPixels(window.min.y, window.max.y);
    if (attributes != nullptr) {
      attributes->clear();
      for (auto it = header.begin(); it != header.end(); ++it) {
        if (const auto* s = dynamic_cast<const Imf::StringAttribute*>(&it.attribute())) {
          attributes->emplace_back(it.name(), s->value());
        }
      }
    }
  } catch (const Iex::BaseExc& e) {
    throw InputError(loc, std::string("not a readable OpenEXR file: ") + e.what(),
                     "the file is damaged or not an EXR image; write it again");
  }
  const auto bad =
      std::find_if(image.rgb.begin(), image.rgb.end(), [](float v) { return !std::isfinite(v); });
  if (bad != image.rgb.end()) {
    const size_t pixel = static_cast<size_t>(bad - image.rgb.begin()) / 3;
    throw InputError(loc,
                     "OpenEXR file has a NaN or infinite value at pixel (" +
                         std::to_string(pixel % static_cast<size_t>(image.width)) + ", " +
                         std::to_string(pixel / static_cast<size_t>(image.width)) + ")",
                     "fix the program that wrote it; physical images must hold finite values");
  }
  return image;
}

void writePng(const fs::path& path, int width, int height, int channels, const uint8_t* pixels,
              const PngMetadata& metadata) {
  const std::string where = "writePng(" + path.string() + "): ";
  if (width < 1 || height < 1 || int64_t{width} * height > kMaxPixels || channels < 1 || channels > 4 ||
      pixels == nullptr) {
    throw std::invalid_argument(where + "invalid image " + std::to_string(width) + "×" +
                                std::to_string(height) + "×" + std::to_string(channels) +
                                (pixels == nullptr ? " (no pixels)" : ""));
  }
  std::string bytes;
  const auto append = [](void* context, void* data, int size) {
    static_cast<std::string*>(context)->append(static_cast<const char*>(data), static_cast<size_t>(size));
  };
  if (stbi_write_png_to_func(append, &bytes, width, height, channels, pixels, width * channels) == 0) {
    throw std::runtime_error(where + "PNG encoding failed");
  }
  writeOutput(path, withPngMetadata(bytes, metadata));
}

ImageU8 readPng(const fs::path& path) {
  const std::string bytes = readInputFile(path, "PNG file");
  const SourceLocation loc{path.string()};
  // PNG signature (ISO/IEC 15948, 5.2); stb_image would also accept JPEG, BMP and others.
  constexpr std::string_view kSignature("\x89PNG\r\n\x1a\n", 8);
  if (bytes.size() > INT_MAX || std::string_view(bytes).substr(0, kSignature.size()) != kSignature) {
    throw InputError(loc, "not a PNG file", "give a .png image");
  }
  ImageU8 image;
  const std::unique_ptr<stbi_uc, decltype(&stbi_image_free)> data(
      stbi_load_from_memory(reinterpret_cast<const stbi_uc*>(bytes.data()), static_cast<int>(bytes.size()),
                            &image.width, &image.height, &image.channels, 0),
      &stbi_image_free);
  if (!data) {
    throw InputError(loc, std::string("not a readable PNG file: ") + stbi_failure_reason(),
                     "the file is damaged; write it again");
  }
  const size_t size = static_cast<size_t>(image.width) * static_cast<size_t>(image.height) *
                      static_cast<size_t>(image.channels);
  image.pixels.assign(data.get(), data.get() + size);
  return image;
}

}  // namespace fly
