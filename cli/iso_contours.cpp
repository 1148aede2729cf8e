#include "cli/iso_contours.h"

#include <cmath>

namespace fly::cli {

std::vector<std::array<dvec2, 2>> isoContours(const ScalarGrid& grid, double level) {
  std::vector<std::array<dvec2, 2>> segments;
  for (int r = 0; r + 1 < grid.rows; ++r) {
    for (int c = 0; c + 1 < grid.columns; ++c) {
      // Corners counter-clockwise in lattice coordinates: (c, r), (c+1, r), (c+1, r+1), (c, r+1).
      const std::array<dvec2, 4> p = {dvec2(c, r), dvec2(c + 1, r), dvec2(c + 1, r + 1), dvec2(c, r + 1)};
      const std::array<double, 4> v = {grid.at(c, r), grid.at(c + 1, r), grid.at(c + 1, r + 1),
                                       grid.at(c, r + 1)};
      bool complete = true;
      for (const double x : v) complete = complete && std::isfinite(x);
      if (!complete) continue;
      int mask = 0;
      for (int k = 0; k < 4; ++k) mask |= (v[k] >= level ? 1 : 0) << k;
      if (mask == 0 || mask == 15) continue;
      // The crossing on edge k, from corner k to corner k+1.
      auto crossing = [&](int k) {
        const int k1 = (k + 1) % 4;
        const double t = (level - v[k]) / (v[k1] - v[k]);
        return p[k] + t * (p[k1] - p[k]);
      };
      std::vector<int> edges;  // the crossed edges in order around the square
      for (int k = 0; k < 4; ++k) {
        if (((mask >> k) & 1) != ((mask >> ((k + 1) % 4)) & 1)) edges.push_back(k);
      }
      if (edges.size() == 2) {
        segments.push_back({crossing(edges[0]), crossing(edges[1])});
        continue;
      }
      // Saddle: all four edges crossed. When the centre (the corners' mean) lies on the side of corner 0, the
      // lines separate corners 1 and 3 from it: they pair edges (0, 1) and (2, 3); otherwise (3, 0) and (1,
      // 2).
      const bool centreAbove = (v[0] + v[1] + v[2] + v[3]) / 4.0 >= level;
      if (centreAbove == bool(mask & 1)) {
        segments.push_back({crossing(0), crossing(1)});
        segments.push_back({crossing(2), crossing(3)});
      } else {
        segments.push_back({crossing(3), crossing(0)});
        segments.push_back({crossing(1), crossing(2)});
      }
    }
  }
  return segments;
}

}  // namespace fly::cli
