#include "cli/cairo_png.h"

#include <stdexcept>
#include <string>

#include "base/file_io.h"

namespace fly::cli {

namespace {

cairo_status_t appendToString(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

void writeCairoPng(cairo_surface_t* surface, cairo_t* cr, const std::filesystem::path& path,
                   std::string_view what, const PngMetadata& metadata) {
  cairo_surface_flush(surface);
  std::string png;
  if (cairo_status(cr) != CAIRO_STATUS_SUCCESS ||
      cairo_surface_write_to_png_stream(surface, appendToString, &png) != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error("drawing the " + std::string(what) +
                             " failed: " + std::string(cairo_status_to_string(cairo_status(cr))));
  }
  writeFileAtomic(path, withPngMetadata(png, metadata));
}

}  // namespace fly::cli
