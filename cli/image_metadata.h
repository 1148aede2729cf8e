// The settings every image fly writes carries in its file (PNG text chunks, EXR header attributes), so that
// an image found later says how it was made: the program, the command line, the scene's site, time and sky,
// and what a command adds (exposure, scale, units); and its print resolution (`--dpi`).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <utility>
#include <vector>

#include "base/image_io.h"
#include "base/png_metadata.h"
#include "sdb/scene.h"

namespace fly::cli {

using ImageSettings = std::vector<std::pair<std::string, std::string>>;

// Records the command line of this process (main() calls it once, before the command runs).
void recordCommandLine(int argc, const char* const* argv);
// The recorded command line, arguments separated by spaces and quoted ('…') where they hold a space or quote.
const std::string& commandLine();

// "Title", "Software" (fly and its version), "fly:command" (the command line), then `settings` as given
// (keys "fly:…"), and the print resolution dotsPerInch (0 = none).
PngMetadata imageMetadata(const std::string& title, const ImageSettings& settings, double dotsPerInch = 0.0);

// The scene's daylight as settings: "fly:site" (latitude, longitude, elevation, north angle, time zone; when
// the scene has a site), "fly:time" (local date and time, or the sun placed directly), "fly:sky" (model,
// CIE type or turbidity, sun on or off).
ImageSettings daylightSettings(const sdb::Scene& scene);

// The metadata's text as EXR string attributes, and its resolution as "fly:dpi".
ExrAttributes exrAttributes(const PngMetadata& metadata);

// --dpi N: the print resolution written into the image (PNG pHYs, EXR "fly:dpi"), [1, 10000] dots per inch.
void addDpiOption(CLI::App& sub, double* dotsPerInch);

}  // namespace fly::cli
