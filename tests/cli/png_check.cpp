// Checks a PNG that a test wrote:
//   fly_png_check FILE WIDTH HEIGHT [same OTHER MAX_DIFF | differs OTHER | lit FRACTION]
// FILE must be WIDTH × HEIGHT and not uniform (some channel takes two values); with "same", no channel of
// any pixel differs from OTHER's by more than MAX_DIFF (0..255); with "differs", some channel of some pixel
// differs by more than 8; with "lit", at least FRACTION (0..1) of the pixels have a channel above 24 (of
// 255): not black. Prints what it found; exit 0 when every check passes, 1 otherwise.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "base/image_io.h"

int main(int argc, char** argv) {
  if (argc != 4 && argc != 6 && argc != 7) {
    std::fprintf(stderr, "usage: fly_png_check FILE WIDTH HEIGHT [same OTHER MAX_DIFF | differs OTHER | lit FRACTION]\n");
    return 2;
  }
  try {
    const fly::ImageU8 a = fly::readPng(argv[1]);
    const int w = std::atoi(argv[2]), h = std::atoi(argv[3]);
    int lo = 255, hi = 0;
    for (uint8_t v : a.pixels) {
      lo = std::min(lo, int(v));
      hi = std::max(hi, int(v));
    }
    std::printf("%s: %d×%d, %d channels, values %d..%d\n", argv[1], a.width, a.height, a.channels, lo, hi);
    bool ok = true;
    if (a.width != w || a.height != h) {
      std::printf("FAIL: expected %d×%d\n", w, h);
      ok = false;
    }
    if (lo == hi) {
      std::printf("FAIL: uniform image\n");
      ok = false;
    }
    if (argc == 6 && std::string(argv[4]) == "lit") {
      const int channels = a.channels;
      size_t lit = 0;
      for (size_t p = 0; p + size_t(channels) <= a.pixels.size(); p += size_t(channels)) {
        lit += *std::max_element(a.pixels.begin() + long(p), a.pixels.begin() + long(p) + std::min(channels, 3)) > 24;
      }
      const double fraction = double(lit) / double(size_t(a.width) * size_t(a.height));
      std::printf("%.1f %% of the pixels are lit (a channel above 24)\n", 100.0 * fraction);
      if (fraction < std::atof(argv[5])) {
        std::printf("FAIL: fewer than %.1f %%\n", 100.0 * std::atof(argv[5]));
        ok = false;
      }
    } else if (argc > 4) {
      const std::string how = argv[4];
      const fly::ImageU8 b = fly::readPng(argv[5]);
      if (b.width != a.width || b.height != a.height || b.channels != a.channels) {
        std::printf("FAIL: %s is %d×%d×%d\n", argv[5], b.width, b.height, b.channels);
        return 1;
      }
      int maxDiff = 0;
      size_t differing = 0;
      for (size_t i = 0; i < a.pixels.size(); ++i) {
        const int d = std::abs(int(a.pixels[i]) - int(b.pixels[i]));
        maxDiff = std::max(maxDiff, d);
        differing += d > 8 ? 1 : 0;
      }
      std::printf("against %s: largest difference %d, %zu values differ by more than 8\n", argv[5], maxDiff,
                  differing);
      if (how == "same" && argc == 7 && maxDiff > std::atoi(argv[6])) {
        std::printf("FAIL: differs by more than %s\n", argv[6]);
        ok = false;
      } else if (how == "differs" && differing == 0) {
        std::printf("FAIL: the images are the same\n");
        ok = false;
      } else if (how != "same" && how != "differs") {
        std::printf("FAIL: unknown comparison '%s'\n", how.c_str());
        ok = false;
      }
    }
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("FAIL: %s\n", e.what());
    return 1;
  }
}
