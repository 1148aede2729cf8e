#include "sdb/portal.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace fly::sdb {

namespace {

// Twice the area vector of the triangle (a, b, c), in double precision.
dvec3 twiceAreaVector(const dvec3& a, const dvec3& b, const dvec3& c) {
  return glm::cross(b - a, c - a);
}

// "0.0123", "1.5e-07": four significant digits.
std::string shortNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return buf;
}

}  // namespace

std::optional<PortalProblem> checkPortal(std::span<const vec3> cornersM) {
  const size_t n = cornersM.size();
  if (n != 3 && n != 4) {
    return PortalProblem{std::nullopt, "a portal has 3 or 4 corners; got " + std::to_string(n),
                         "give a triangle of 3 corners or a convex quad of 4, in order around its edge"};
  }
  for (size_t i = 0; i < n; ++i) {
    if (!isFinite(cornersM[i])) {
      return PortalProblem{i, "the corner is not a finite point", "give [x, y, z] in metres"};
    }
  }
  std::vector<dvec3> p(cornersM.begin(), cornersM.end());
  // The area of the triangles (0, 1, 2) and (0, 2, 3) that the portal is made of (portalTrianglesM).
  double areaM2 = 0.5 * glm::length(twiceAreaVector(p[0], p[1], p[2]));
  if (n == 4) areaM2 += 0.5 * glm::length(twiceAreaVector(p[0], p[2], p[3]));
  if (!(areaM2 >= kPortalMinAreaM2)) {
    return PortalProblem{std::nullopt,
                         "the portal's area is " + shortNumber(areaM2) + " m², below " +
                             shortNumber(kPortalMinAreaM2) + " m²: its corners lie on a line or together",
                         "give the corners of the opening in metres, in order around its edge"};
  }
  if (n == 3) return std::nullopt;

  double longestEdgeM = 0.0;
  for (size_t i = 0; i < 4; ++i) longestEdgeM = std::max(longestEdgeM, glm::length(p[(i + 1) % 4] - p[i]));
  const dvec3 first = twiceAreaVector(p[0], p[1], p[2]);
  const double firstLength = glm::length(first);
  // Three corners on a line (within the planarity tolerance): a triangle with an extra corner on an edge.
  if (firstLength <= kPortalPlanarityTolerance * longestEdgeM * glm::length(p[2] - p[0])) {
    return PortalProblem{1, "corner 1 lies on the line through corners 0 and 2",
                         "leave corner 1 out and give the portal as a triangle of 3 corners"};
  }
  const dvec3 normal = first / firstLength;
  const double offPlaneM = std::abs(glm::dot(normal, p[3] - p[0]));
  if (offPlaneM > kPortalPlanarityTolerance * longestEdgeM) {
    return PortalProblem{3,
                         "corner 3 lies " + shortNumber(offPlaneM) +
                             " m off the plane of corners 0, 1 and 2 (more than " +
                             shortNumber(kPortalPlanarityTolerance) + " of the longest edge, " +
                             shortNumber(longestEdgeM) + " m)",
                         "a portal is flat: move corner 3 into the plane, or declare two triangles"};
  }
  // Convex: the turn at every corner has the sign of the turn at corner 1, and is no straight line.
  for (size_t i = 0; i < 4; ++i) {
    const dvec3 in = p[i] - p[(i + 3) % 4];
    const dvec3 out = p[(i + 1) % 4] - p[i];
    const double turn = glm::dot(glm::cross(in, out), normal);
    if (!(turn > kPortalPlanarityTolerance * glm::length(in) * glm::length(out))) {
      return PortalProblem{
          i,
          "the quad is not convex at corner " + std::to_string(i) +
              " (its edges cross, or it turns the other way or runs straight there)",
          "give the 4 corners in order around the opening's edge, or split it into triangles"};
    }
  }
  return std::nullopt;
}

std::vector<vec3> portalTrianglesM(const Portal& portal) {
  const std::vector<vec3>& c = portal.cornersM;
  if (c.size() == 3) return c;
  return {c[0], c[1], c[2], c[0], c[2], c[3]};
}

double portalAreaM2(const Portal& portal) {
  const std::vector<vec3> t = portalTrianglesM(portal);
  double areaM2 = 0.0;
  for (size_t i = 0; i + 2 < t.size(); i += 3) {
    areaM2 += 0.5 * glm::length(twiceAreaVector(dvec3(t[i]), dvec3(t[i + 1]), dvec3(t[i + 2])));
  }
  return areaM2;
}

vec3 portalNormal(const Portal& portal) {
  const std::vector<vec3> t = portalTrianglesM(portal);
  dvec3 sum(0.0);
  for (size_t i = 0; i + 2 < t.size(); i += 3)
    sum += twiceAreaVector(dvec3(t[i]), dvec3(t[i + 1]), dvec3(t[i + 2]));
  return vec3(glm::normalize(sum));
}

}  // namespace fly::sdb
