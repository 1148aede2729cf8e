// Writing a cairo drawing as a PNG file atomically (base/file_io.h writeFileAtomic): cairo's PNG encoder into
// memory, the metadata's chunks added (base/png_metadata.h), then one atomic write — shared by the diagrams
// the CLI draws.
#pragma once

#include <cairo.h>

#include <filesystem>
#include <string_view>

#include "base/png_metadata.h"

namespace fly::cli {

// Flushes `surface`, encodes it as PNG (RGB for CAIRO_FORMAT_RGB24 surfaces) with `metadata` and writes it to
// `path`. std::runtime_error naming `what` when drawing on `cr` or encoding failed; nothing is written then.
void writeCairoPng(cairo_surface_t* surface, cairo_t* cr, const std::filesystem::path& path,
                   std::string_view what, const PngMetadata& metadata);

}  // namespace fly::cli
