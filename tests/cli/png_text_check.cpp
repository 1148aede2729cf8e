// Checks the metadata of a PNG that fly wrote:
//   fly_png_text_check FILE DPI KEY=TEXT...
// The file's print resolution (pHYs) must be DPI within 0.0127, the rounding of pHYs' whole pixels per metre
// (0: none written), and each KEY's text chunk must exist and contain TEXT. Prints the metadata; exit 0 when
// every check passes, 1 otherwise, 2 for bad usage.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "base/file_io.h"
#include "base/png_metadata.h"

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: fly_png_text_check FILE DPI KEY=TEXT...\n");
    return 2;
  }
  try {
    const fly::PngMetadata m = fly::readPngMetadata(fly::readInputFile(argv[1], "PNG file"));
    std::printf("%s: %.4f dpi\n", argv[1], m.dotsPerInch);
    for (const auto& [key, value] : m.text) std::printf("  %s: %s\n", key.c_str(), value.c_str());
    bool ok = std::fabs(m.dotsPerInch - std::atof(argv[2])) <= 0.5 * 0.0254 + 1e-9;
    if (!ok) std::printf("FAIL: %.4f dpi, expected %s\n", m.dotsPerInch, argv[2]);
    for (int i = 3; i < argc; ++i) {
      const std::string want = argv[i];
      const size_t eq = want.find('=');
      const std::string key = want.substr(0, eq), text = eq == std::string::npos ? "" : want.substr(eq + 1);
      bool found = false;
      for (const auto& [k, v] : m.text) found = found || (k == key && v.find(text) != std::string::npos);
      if (!found) std::printf("FAIL: no %s containing '%s'\n", key.c_str(), text.c_str());
      ok = ok && found;
    }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 1;
  }
}
