#include "cli/plan_section.h"

namespace fly::cli {

std::vector<std::array<dvec2, 2>> horizontalSection(const rdb::TraceRdb& rdb, double heightM) {
  std::vector<std::array<dvec2, 2>> segments;
  for (size_t t = 0; t < rdb.triangleCount(); ++t) {
    std::array<dvec3, 3> p;
    std::array<double, 3> d;  // signed height above the plane
    for (int k = 0; k < 3; ++k) {
      p[k] = dvec3(rdb.positionsM[rdb.indices[3 * t + k]]);
      d[k] = p[k].y - heightM;
    }
    std::vector<dvec2> ends;
    // An edge in the plane (two corners on it) is the section of the triangle above it only, so that a wall
    // meshed in rows is cut once at a row of vertices.
    const int onPlane = int(d[0] == 0.0) + int(d[1] == 0.0) + int(d[2] == 0.0);
    if (onPlane == 2) {
      const int apart = d[0] != 0.0 ? 0 : d[1] != 0.0 ? 1 : 2;
      if (d[apart] > 0.0) {
        const dvec3& a = p[(apart + 1) % 3];
        const dvec3& b = p[(apart + 2) % 3];
        segments.push_back({dvec2(a.x, a.z), dvec2(b.x, b.z)});
      }
      continue;
    }
    for (int k = 0; k < 3 && ends.size() < 2; ++k) {
      const int k1 = (k + 1) % 3;
      // Each edge from a corner strictly on one side to a corner on or beyond the other side; a corner on the
      // plane is counted by the edge that ends at it only.
      if ((d[k] < 0.0 && d[k1] >= 0.0) || (d[k] > 0.0 && d[k1] <= 0.0)) {
        const double f = d[k] / (d[k] - d[k1]);
        const dvec3 q = p[k] + f * (p[k1] - p[k]);
        ends.emplace_back(q.x, q.z);
      }
    }
    if (ends.size() == 2 && ends[0] != ends[1]) segments.push_back({ends[0], ends[1]});
  }
  return segments;
}

}  // namespace fly::cli
