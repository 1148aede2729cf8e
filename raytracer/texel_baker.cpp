#include "raytracer/texel_baker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>

#include "raytracer/enclosure.h"
#include "raytracer/sampler.h"

namespace fly::raytracer {
namespace {

// The sampler group that places a sample in its texel's footprint, far above the integrator's groups (3 per
// path vertex from group 0, at most 3 · kPathLengthGuard of them), and ≡ 31 mod 32 for the sampler's group
// cache (as the baker's one-ring group).
constexpr uint32_t kFootprintGroup = (1u << 20) + 31;

// A texel whose pieces' areas sum to 1 texel² within this is covered whole (Texel::fullSquare): the
// clipped pieces' areas are exact to float rounding, ~10⁻⁶, and charts that overlap in UV, whose sum
// exceeds 1, are not covered whole.
constexpr float kFullSquareTolerance = 1e-4f;

// Seam sweeps (Kaczmarz); each projects onto every seam point's constraint once.
constexpr int kSeamSweeps = 64;

float cross2(const vec2& a, const vec2& b) {
  return a.x * b.y - a.y * b.x;
}

// The convex polygon `poly` clipped to the closed half-plane s·x[axis] ≤ s·bound (Sutherland–Hodgman). Points
// on the boundary stay, so a triangle that only touches the square keeps a degenerate polygon.
std::vector<vec2> clip(const std::vector<vec2>& poly, int axis, float bound, float s) {
  std::vector<vec2> out;
  for (size_t i = 0; i < poly.size(); ++i) {
    const vec2& p = poly[i];
    const vec2& q = poly[(i + 1) % poly.size()];
    const float dp = s * (p[axis] - bound);
    const float dq = s * (q[axis] - bound);
    if (dp <= 0.0f) out.push_back(p);
    if ((dp < 0.0f && dq > 0.0f) || (dp > 0.0f && dq < 0.0f)) {
      vec2 x = p + (q - p) * (dp / (dp - dq));
      x[axis] = bound;  // exactly on the boundary
      out.push_back(x);
    }
  }
  return out;
}

// Bilinear lookup at (u, v) of a width × height texture (texel centres at (i + ½)/width, clamped at the
// border): 4 texel indices and their weights.
struct Bilinear {
  uint32_t texel[4];
  float weight[4];
};
Bilinear bilinear(const vec2& uv, uint32_t width, uint32_t height) {
  const float x = uv.x * float(width) - 0.5f;
  const float y = uv.y * float(height) - 0.5f;
  const float x0 = std::floor(x), y0 = std::floor(y);
  const float fx = x - x0, fy = y - y0;
  auto clampTo = [](float c, uint32_t n) { return uint32_t(std::clamp(c, 0.0f, float(n - 1))); };
  const uint32_t i0 = clampTo(x0, width), i1 = clampTo(x0 + 1.0f, width);
  const uint32_t j0 = clampTo(y0, height), j1 = clampTo(y0 + 1.0f, height);
  return {{j0 * width + i0, j0 * width + i1, j1 * width + i0, j1 * width + i1},
          {(1 - fx) * (1 - fy), fx * (1 - fy), (1 - fx) * fy, fx * fy}};
}

// Fills every texel that `known` does not mark with the mean of its known 8-neighbours, ring by ring outwards
// from the known texels (each ring reads only texels known before it). Texels no ring reaches (no known
// texel at all) keep their value.
void dilate(uint32_t width, uint32_t height, std::vector<uint8_t> known,
            std::span<std::vector<Rgb>* const> maps) {
  const int w = int(width), h = int(height);
  std::vector<uint8_t> queued(known.size(), 0);
  std::vector<uint32_t> ring;
  auto enqueueNeighbours = [&](int i, int j, std::vector<uint32_t>& into) {
    for (int dj = -1; dj <= 1; ++dj) {
      for (int di = -1; di <= 1; ++di) {
        const int x = i + di, y = j + dj;
        if (x < 0 || y < 0 || x >= w || y >= h) continue;
        const uint32_t t = uint32_t(y) * width + uint32_t(x);
        if (known[t] || queued[t]) continue;
        queued[t] = 1;
        into.push_back(t);
      }
    }
  };
  for (int j = 0; j < h; ++j) {
    for (int i = 0; i < w; ++i) {
      if (known[uint32_t(j) * width + uint32_t(i)]) enqueueNeighbours(i, j, ring);
    }
  }
  std::vector<Rgb> values;
  while (!ring.empty()) {
    for (std::vector<Rgb>* map : maps) {
      values.assign(ring.size(), Rgb(0.0f));
      for (size_t r = 0; r < ring.size(); ++r) {
        const int i = int(ring[r] % width), j = int(ring[r] / width);
        int count = 0;
        for (int dj = -1; dj <= 1; ++dj) {
          for (int di = -1; di <= 1; ++di) {
            const int x = i + di, y = j + dj;
            if (x < 0 || y < 0 || x >= w || y >= h) continue;
            const uint32_t t = uint32_t(y) * width + uint32_t(x);
            if (!known[t]) continue;
            values[r] += (*map)[t];
            ++count;
          }
        }
        values[r] /= float(std::max(count, 1));
      }
      for (size_t r = 0; r < ring.size(); ++r) (*map)[ring[r]] = values[r];
    }
    for (uint32_t t : ring) known[t] = 1;
    std::vector<uint32_t> next;
    for (uint32_t t : ring) enqueueNeighbours(int(t % width), int(t / width), next);
    ring = std::move(next);
  }
}

// One point of a seam: the same surface point's lookups in the two copies of the edge, which should agree.
struct SeamPoint {
  Bilinear a, b;
};

// Kaczmarz sweeps over the seam points: each step changes the texels of both lookups along their weights, by
// the least change that makes the two lookups equal.
void makeSeamsAgree(const std::vector<SeamPoint>& seam, std::vector<Rgb>& lux) {
  for (int sweep = 0; sweep < kSeamSweeps; ++sweep) {
    for (const SeamPoint& s : seam) {
      Rgb la(0.0f), lb(0.0f);
      float norm = 0.0f;
      for (int k = 0; k < 4; ++k) {
        la += s.a.weight[k] * lux[s.a.texel[k]];
        lb += s.b.weight[k] * lux[s.b.texel[k]];
        norm += s.a.weight[k] * s.a.weight[k] + s.b.weight[k] * s.b.weight[k];
      }
      const Rgb step = (la - lb) / norm;
      for (int k = 0; k < 4; ++k) {
        lux[s.a.texel[k]] -= s.a.weight[k] * step;
        lux[s.b.texel[k]] += s.b.weight[k] * step;
      }
    }
  }
  // Values cannot go below 0 in light; a lookup's small overshoot at a dark corner must not either.
  for (Rgb& v : lux) v = glm::max(v, Rgb(0.0f));
}

}  // namespace

TexelSource::TexelSource(const rdb::TraceRdb& rdb, const EmbreeScene& scene, const Integrator& integrator)
    : rdb_(rdb), scene_(scene), integrator_(integrator) {
  reachM_ = enclosureReachM(rdb);
  interiorBackFace_.assign(rdb.triangleCount(), false);
  for (const rdb::TraceMesh& m : rdb.meshes) {
    for (uint32_t t = m.firstTriangle; t < m.firstTriangle + m.triangleCount && t < rdb.triangleCount();
         ++t) {
      interiorBackFace_[t] = !m.twoSided && !rdb.materials[rdb.triangleMaterial[t]].doubleSided;
    }
  }

  for (uint32_t k = 0; k < rdb.lightTextures.size(); ++k) {
    const rdb::TraceLightTexture& lt = rdb.lightTextures[k];
    if (lt.mesh >= rdb.meshes.size() || lt.width == 0 || lt.height == 0 ||
        lt.cornerUv.size() != 3 * size_t{rdb.meshes[lt.mesh].triangleCount} || !(lt.texelsPerMetre > 0.0f)) {
      throw std::invalid_argument("TexelSource: light texture " + std::to_string(k) +
                                  " does not match its mesh");
    }
    const rdb::TraceMesh& mesh = rdb.meshes[lt.mesh];
    const vec2 size(float(lt.width), float(lt.height));
    touched_.emplace_back(size_t{lt.width} * lt.height, uint8_t{0});
    std::vector<std::pair<uint32_t, Piece>> fragments;  // (texel index, piece)
    for (uint32_t local = 0; local < mesh.triangleCount; ++local) {
      const uint32_t t = mesh.firstTriangle + local;
      if (!(scene.triangleAreaM2(t) > 0.0f)) continue;  // Embree left it out: nothing to sample on it
      if (!rdb::inLightTexture(lt.cornerUv[3 * size_t{local}])) continue;  // on the vertex light map
      const vec2 a = lt.cornerUv[3 * size_t{local}] * size;
      const vec2 b = lt.cornerUv[3 * size_t{local} + 1] * size;
      const vec2 c = lt.cornerUv[3 * size_t{local} + 2] * size;
      if (!std::isfinite(a.x + a.y + b.x + b.y + c.x + c.y)) continue;
      const vec2 lo = glm::min(a, glm::min(b, c));
      const vec2 hi = glm::max(a, glm::max(b, c));
      const int i0 = std::max(0, int(std::floor(lo.x))),
                i1 = std::min(int(lt.width) - 1, int(std::floor(hi.x)));
      const int j0 = std::max(0, int(std::floor(lo.y))),
                j1 = std::min(int(lt.height) - 1, int(std::floor(hi.y)));
      for (int j = j0; j <= j1; ++j) {
        for (int i = i0; i <= i1; ++i) {
          std::vector<vec2> poly = {a, b, c};
          poly = clip(poly, 0, float(i), -1.0f);
          poly = clip(poly, 0, float(i + 1), 1.0f);
          poly = clip(poly, 1, float(j), -1.0f);
          poly = clip(poly, 1, float(j + 1), 1.0f);
          const uint32_t index = uint32_t(j) * lt.width + uint32_t(i);
          bool hasArea = false;
          for (size_t m = 2; m < poly.size(); ++m) {
            if (std::abs(cross2(poly[m - 1] - poly[0], poly[m] - poly[0])) > 1e-9f) {
              fragments.push_back({index, Piece{t, poly[0], poly[m - 1], poly[m]}});
              hasArea = true;
            }
          }
          // A triangle without area here that still reaches inside the square (a sliver, or zero UV area):
          // the texel is touched but has nothing to sample. Contact along the square's border only is not.
          for (const vec2& x : poly) {
            hasArea =
                hasArea || (x.x > float(i) && x.x < float(i + 1) && x.y > float(j) && x.y < float(j + 1));
          }
          if (hasArea) touched_[k][index] = 1;
        }
      }
    }
    // Texels in row order; within one, the pieces in triangle order (deterministic).
    std::stable_sort(fragments.begin(), fragments.end(),
                     [](const auto& x, const auto& y) { return x.first < y.first; });
    for (size_t f = 0; f < fragments.size();) {
      Texel texel;
      texel.texture = k;
      texel.index = fragments[f].first;
      texel.firstPiece = uint32_t(pieces_.size());
      float sum = 0.0f;
      for (; f < fragments.size() && fragments[f].first == texel.index; ++f) {
        const Piece& p = fragments[f].second;
        sum += 0.5f * std::abs(cross2(p.b - p.a, p.c - p.a));
        pieces_.push_back(p);
        pieceCdf_.push_back(sum);
      }
      texel.endPiece = uint32_t(pieces_.size());
      texel.fullSquare = std::abs(sum - 1.0f) <= kFullSquareTolerance;
      texel.cornerTexels = vec2(float(texel.index % lt.width), float(texel.index / lt.width));
      placeAnchor(texel, rdb.meshes[lt.mesh].twoSided);
      texels_.push_back(texel);
    }
  }
  for (uint32_t i = 0; i < texels_.size(); ++i) points_.push_back({i, false});
  for (uint32_t i = 0; i < texels_.size(); ++i) {
    if (rdb.meshes[rdb.lightTextures[texels_[i].texture].mesh].twoSided) points_.push_back({i, true});
  }
}

void TexelSource::surfaceAt(uint32_t k, uint32_t t, const vec2& x, vec3& pM, vec3& n) const {
  const rdb::TraceLightTexture& lt = rdb_.lightTextures[k];
  const uint32_t local = t - rdb_.meshes[lt.mesh].firstTriangle;
  const vec2 size(float(lt.width), float(lt.height));
  const vec2 a = lt.cornerUv[3 * size_t{local}] * size;
  const vec2 b = lt.cornerUv[3 * size_t{local} + 1] * size;
  const vec2 c = lt.cornerUv[3 * size_t{local} + 2] * size;
  const float d = cross2(b - a, c - a);
  // Barycentrics of x (inside the triangle up to rounding: clamped and renormalised).
  float w[3] = {0.0f, cross2(x - a, c - a) / d, cross2(b - a, x - a) / d};
  w[0] = 1.0f - w[1] - w[2];
  float sum = 0.0f;
  for (float& wi : w) sum += (wi = std::max(wi, 0.0f));
  pM = vec3(0.0f);
  vec3 shading(0.0f);
  for (size_t i = 0; i < 3; ++i) {
    const uint32_t v = rdb_.indices[3 * size_t{t} + i];
    pM += (w[i] / sum) * rdb_.positionsM[v];
    shading += (w[i] / sum) * rdb_.normals[v];
  }
  // The front is the side of the shading normal; the geometric normal replaces a shading normal that is
  // degenerate or points to the other side of the surface (as the vertex baker does).
  const vec3& ng = scene_.triangleNormal(t);
  const vec3 ngFront = glm::dot(ng, shading) >= 0.0f ? ng : -ng;
  const float len = glm::length(shading);
  n = len > 0.0f ? shading / len : ngFront;
  if (!(glm::dot(n, ngFront) > 0.0f)) n = ngFront;
}

float TexelSource::liftM(uint32_t k, float magnitudeM) const {
  const float texelM = 1.0f / rdb_.lightTextures[k].texelsPerMetre;
  return std::max(1e-3f * texelM, 16.0f * rayOffsetM(magnitudeM));
}

void TexelSource::placeAnchor(Texel& texel, bool twoSided) {
  const rdb::TraceLightTexture& lt = rdb_.lightTextures[texel.texture];
  const vec2 centre(float(texel.index % lt.width) + 0.5f, float(texel.index / lt.width) + 0.5f);
  // Candidates: the texel's centre on the piece under it, then the pieces' centroids, largest first.
  std::vector<std::pair<uint32_t, vec2>> candidates;
  for (uint32_t p = texel.firstPiece; p < texel.endPiece; ++p) {
    const Piece& q = pieces_[p];
    const float d = cross2(q.b - q.a, q.c - q.a);
    const float w1 = cross2(centre - q.a, q.c - q.a) / d, w2 = cross2(q.b - q.a, centre - q.a) / d;
    if (w1 >= 0.0f && w2 >= 0.0f && w1 + w2 <= 1.0f) {
      candidates.insert(candidates.begin(), {p, centre});
      break;
    }
  }
  std::vector<uint32_t> byArea;
  for (uint32_t p = texel.firstPiece; p < texel.endPiece; ++p) byArea.push_back(p);
  std::stable_sort(byArea.begin(), byArea.end(), [&](uint32_t x, uint32_t y) {
    const Piece& a = pieces_[x];
    const Piece& b = pieces_[y];
    return std::abs(cross2(a.b - a.a, a.c - a.a)) > std::abs(cross2(b.b - b.a, b.c - b.a));
  });
  for (uint32_t p : byArea) {
    const Piece& q = pieces_[p];
    candidates.emplace_back(p, (q.a + q.b + q.c) / 3.0f);
  }
  // The first candidate that is not inside a closed object (raytracer/enclosure.h); the first of all when
  // every one is: the texel then lies inside and is hidden.
  uint64_t rays = 0;
  for (size_t c = 0; c < candidates.size(); ++c) {
    Texel t = texel;
    const vec3 front = anchorAt(t, candidates[c].first, candidates[c].second);
    const float magnitude = std::max(scene_.triangleMagnitudeM(t.anchorTriangle), maxAbs(t.anchorM));
    t.enclosed[0] = isEnclosed(scene_, t.anchorM, front, magnitude, reachM_, rays);
    t.enclosed[1] = !twoSided || isEnclosed(scene_, t.anchorM, -front, magnitude, reachM_, rays);
    if (c == 0 || !(t.enclosed[0] && t.enclosed[1])) texel = t;
    if (!(t.enclosed[0] && t.enclosed[1])) break;
  }
}

vec3 TexelSource::anchorAt(Texel& texel, uint32_t piece, const vec2& at) {
  const rdb::TraceLightTexture& lt = rdb_.lightTextures[texel.texture];
  texel.anchorTriangle = pieces_[piece].triangle;
  vec3 n;
  surfaceAt(texel.texture, texel.anchorTriangle, at, texel.anchorM, n);
  const vec3& ng = scene_.triangleNormal(texel.anchorTriangle);
  const vec3 ngFront = glm::dot(ng, n) >= 0.0f ? ng : -ng;

  // Probes along the surface: the nearest back face of a one-sided surface within a texel diagonal means the
  // anchor lies inside an object; it moves just beyond that face.
  const float lift =
      liftM(texel.texture, std::max(scene_.triangleMagnitudeM(texel.anchorTriangle), maxAbs(texel.anchorM)));
  const float reachM = 1.5f / lt.texelsPerMetre;
  const vec3 helper = std::abs(ngFront.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0);
  const vec3 t1 = glm::normalize(glm::cross(ngFront, helper));
  const vec3 t2 = glm::cross(ngFront, t1);
  const vec3 origin = texel.anchorM + lift * ngFront;
  float nearest = std::numeric_limits<float>::infinity();
  vec3 nearestDir(0.0f);
  for (int d = 0; d < 8; ++d) {
    const float angle = float(d) * kPiF / 4.0f;
    const vec3 dir = std::cos(angle) * t1 + std::sin(angle) * t2;
    const std::optional<Hit> hit = scene_.intersect(origin, dir, reachM);
    if (hit && glm::dot(dir, hit->geometricNormal) > 0.0f && interiorBackFace_[hit->triangle] &&
        hit->distanceM < nearest) {
      nearest = hit->distanceM;
      nearestDir = dir;
    }
  }
  if (std::isfinite(nearest)) texel.anchorM += (nearest + lift) * nearestDir;
  return ngFront;
}

uint32_t TexelSource::groupCount() const {
  return 2 * std::max<uint32_t>(1, static_cast<uint32_t>(rdb_.lightTextures.size()));
}

uint32_t TexelSource::groupOf(size_t point) const {
  const Point& pt = points_[point];
  return 2 * texels_[pt.texel].texture + (pt.back ? 1 : 0);
}

template <class S>
PointSample TexelSource::sampleAt(size_t point, S& sampler, uint64_t& rays) const {
  const Point& pt = points_[point];
  const Texel& texel = texels_[pt.texel];
  sampler.startGroup(kFootprintGroup);
  const vec2 u = sampler.next2D();
  vec2 q;
  uint32_t j = texel.firstPiece;
  if (texel.fullSquare) {
    // Uniform in the square, in the piece under the point: the one it is most inside of (the pieces tile
    // the square; a point on a shared edge may round to either).
    q = texel.cornerTexels + u;
    float best = -std::numeric_limits<float>::infinity();
    for (uint32_t k = texel.firstPiece; k < texel.endPiece; ++k) {
      const Piece& c = pieces_[k];
      const float orientation = cross2(c.b - c.a, c.c - c.a) > 0.0f ? 1.0f : -1.0f;
      const float inside =
          std::min({orientation * cross2(c.b - c.a, q - c.a), orientation * cross2(c.c - c.b, q - c.b),
                    orientation * cross2(c.a - c.c, q - c.c)});
      if (inside > best) {
        best = inside;
        j = k;
      }
    }
  } else {
    // A piece by area, then the remainder of u.x (uniform again) and u.y place the point in it uniformly.
    const float total = pieceCdf_[texel.endPiece - 1];
    const float x = u.x * total;
    while (j + 1 < texel.endPiece && pieceCdf_[j] <= x) ++j;
    const float below = j == texel.firstPiece ? 0.0f : pieceCdf_[j - 1];
    const float r = std::clamp((x - below) / (pieceCdf_[j] - below), 0.0f, 0x1.fffffep-1f);
    const float s = std::sqrt(r);
    const Piece& c = pieces_[j];
    q = (1.0f - s) * c.a + s * (1.0f - u.y) * c.b + s * u.y * c.c;
  }
  const Piece& piece = pieces_[j];
  vec3 p, n;
  surfaceAt(texel.texture, piece.triangle, q, p, n);
  const vec3& ng = scene_.triangleNormal(piece.triangle);
  vec3 side = glm::dot(ng, n) >= 0.0f ? ng : -ng;
  if (pt.back) {
    n = -n;
    side = -side;
  }
  const float magnitude = std::max(scene_.triangleMagnitudeM(piece.triangle), maxAbs(texel.anchorM));
  // The leak test: the segment from the anchor to the point, just above the surface on the baked side.
  const float lift = liftM(texel.texture, magnitude);
  const vec3 from = texel.anchorM + lift * side;
  const vec3 span = p - texel.anchorM;
  const float length = glm::length(span);
  if (length > lift) {
    const vec3 dir = span / length;
    ++rays;
    if (const std::optional<Hit> hit = scene_.intersect(from, dir, length)) {
      p = texel.anchorM + std::max(hit->distanceM - lift, 0.0f) * dir;
    }
  }
  PointSample x;
  x.lux = integrator_.sampleIrradiance(p, n, sampler, rays, magnitude, &x.sunDirectLux);
  return x;
}

PointSample TexelSource::sample(size_t point, SobolSampler& sampler, uint64_t& rays) const {
  return sampleAt(point, sampler, rays);
}
PointSample TexelSource::sample(size_t point, RandomSampler& sampler, uint64_t& rays) const {
  return sampleAt(point, sampler, rays);
}

std::vector<LightTexture> TexelSource::finish(std::span<const IrradianceEstimate> estimates) const {
  if (estimates.size() != points_.size()) {
    throw std::invalid_argument("TexelSource::finish: " + std::to_string(estimates.size()) +
                                " estimates for " + std::to_string(points_.size()) + " points");
  }
  std::vector<LightTexture> out(rdb_.lightTextures.size());
  std::vector<std::vector<uint8_t>> baked(out.size());
  for (size_t k = 0; k < out.size(); ++k) {
    const rdb::TraceLightTexture& lt = rdb_.lightTextures[k];
    const size_t n = size_t{lt.width} * lt.height;
    LightTexture& tex = out[k];
    tex.mesh = lt.mesh;
    tex.width = lt.width;
    tex.height = lt.height;
    const bool twoSided = rdb_.meshes[lt.mesh].twoSided;
    const bool sun = keepsSunDirect();
    for (auto [values, wanted] : {std::pair{&tex.frontLux, true},
                                  {&tex.frontStdErrorLux, true},
                                  {&tex.backLux, twoSided},
                                  {&tex.backStdErrorLux, twoSided},
                                  {&tex.frontSunDirectLux, sun},
                                  {&tex.frontSunDirectStdErrorLux, sun},
                                  {&tex.backSunDirectLux, sun && twoSided},
                                  {&tex.backSunDirectStdErrorLux, sun && twoSided},
                                  {&tex.frontSunDirectSpreadLux, sun},
                                  {&tex.backSunDirectSpreadLux, sun && twoSided}}) {
      if (wanted) values->assign(n, Rgb(0.0f));
    }
    baked[k].assign(n, 0);
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    const Texel& texel = texels_[points_[i].texel];
    LightTexture& tex = out[texel.texture];
    const bool back = points_[i].back;
    (back ? tex.backLux : tex.frontLux)[texel.index] = estimates[i].meanLux;
    (back ? tex.backStdErrorLux : tex.frontStdErrorLux)[texel.index] = estimates[i].stdErrorLux;
    if (!tex.frontSunDirectLux.empty()) {
      (back ? tex.backSunDirectLux : tex.frontSunDirectLux)[texel.index] = estimates[i].sunDirectMeanLux;
      (back ? tex.backSunDirectStdErrorLux : tex.frontSunDirectStdErrorLux)[texel.index] =
          estimates[i].sunDirectStdErrorLux;
      (back ? tex.backSunDirectSpreadLux : tex.frontSunDirectSpreadLux)[texel.index] =
          estimates[i].sunDirectSpreadLux;
    }
    baked[texel.texture][texel.index] = 1;
    tex.hiddenTexelSides += isHidden(i) ? 1 : 0;
    if (!isHidden(i)) tex.samples = std::max(tex.samples, estimates[i].samples);
  }

  for (size_t k = 0; k < out.size(); ++k) {
    LightTexture& tex = out[k];
    for (size_t t = 0; t < baked[k].size(); ++t) {
      tex.bakedTexels += baked[k][t];
      tex.emptyTexels += touched_[k][t] && !baked[k][t];
    }
    std::vector<std::vector<Rgb>*> maps;
    for (std::vector<Rgb>* m :
         {&tex.frontLux, &tex.frontStdErrorLux, &tex.backLux, &tex.backStdErrorLux, &tex.frontSunDirectLux,
          &tex.frontSunDirectStdErrorLux, &tex.backSunDirectLux, &tex.backSunDirectStdErrorLux,
          &tex.frontSunDirectSpreadLux, &tex.backSunDirectSpreadLux}) {
      if (!m->empty()) maps.push_back(m);
    }
    dilate(tex.width, tex.height, baked[k], maps);
    tex.baked = baked[k];

    // Seams: edges of two triangles of the mesh through the same two vertices, with different UVs.
    const rdb::TraceLightTexture& lt = rdb_.lightTextures[k];
    const rdb::TraceMesh& mesh = rdb_.meshes[lt.mesh];
    struct Side {
      vec2 uvLow, uvHigh;  // at the edge's lower and higher vertex index
    };
    std::map<std::pair<uint32_t, uint32_t>, std::vector<Side>> edges;
    for (uint32_t local = 0; local < mesh.triangleCount; ++local) {
      const size_t t = mesh.firstTriangle + size_t{local};
      for (size_t c = 0; c < 3; ++c) {
        const size_t d = (c + 1) % 3;
        uint32_t va = rdb_.indices[3 * t + c], vb = rdb_.indices[3 * t + d];
        vec2 ua = lt.cornerUv[3 * size_t{local} + c], ub = lt.cornerUv[3 * size_t{local} + d];
        if (va == vb || !rdb::inLightTexture(ua)) continue;
        if (va > vb) {
          std::swap(va, vb);
          std::swap(ua, ub);
        }
        edges[{va, vb}].push_back({ua, ub});
      }
    }
    std::vector<SeamPoint> seam;
    const vec2 size(float(lt.width), float(lt.height));
    for (const auto& [key, sides] : edges) {
      if (sides.size() != 2) continue;  // a boundary edge, or a non-manifold one
      const Side& a = sides[0];
      const Side& b = sides[1];
      if (a.uvLow == b.uvLow && a.uvHigh == b.uvHigh) continue;
      ++tex.seamEdges;
      const float lengthTexels =
          std::max(glm::length((a.uvHigh - a.uvLow) * size), glm::length((b.uvHigh - b.uvLow) * size));
      const int count = std::max(2, int(std::ceil(2.0f * lengthTexels)));
      for (int q = 0; q < count; ++q) {
        const float s = (float(q) + 0.5f) / float(count);
        seam.push_back({bilinear(glm::mix(a.uvLow, a.uvHigh, s), lt.width, lt.height),
                        bilinear(glm::mix(b.uvLow, b.uvHigh, s), lt.width, lt.height)});
      }
    }
    if (!seam.empty()) {
      // The same linear projection for E and its sun-direct part, so that E − E_sunDirect is projected alike.
      for (std::vector<Rgb>* m :
           {&tex.frontLux, &tex.backLux, &tex.frontSunDirectLux, &tex.backSunDirectLux}) {
        if (!m->empty()) makeSeamsAgree(seam, *m);
      }
    }
  }
  return out;
}

}  // namespace fly::raytracer
