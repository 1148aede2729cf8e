#include "raytracer/lit_patches.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <thread>

#include "raytracer/sampler.h"
#include "raytracer/warp.h"

namespace fly::raytracer {
namespace {

// Clear panes a training ray passes at most before it counts as blocked.
constexpr uint32_t kTrainingPanes = 8;

// Grid coordinates are kept in 20 bits each (±2^19 cells), the normal's bin in 3.
constexpr int64_t kCoordinateBias = int64_t{1} << 19;

// Sub-triangles of a map: the triangle (in barycentric coordinates (u, v) of p1 and p2, p0 at the origin)
// split into its three corner triangles (children 0, 1, 2 at p0, p1, p2) and the middle one (child 3, turned
// over), each of a quarter of the area. childToParent maps a point of the unit triangle into child k.
vec2 childToParent(uint32_t k, const vec2& c) {
  switch (k) {
    case 0:
      return 0.5f * c;
    case 1:
      return vec2(0.5f + 0.5f * c.x, 0.5f * c.y);
    case 2:
      return vec2(0.5f * c.x, 0.5f + 0.5f * c.y);
    default:
      return vec2(0.5f - 0.5f * c.x, 0.5f - 0.5f * c.y);
  }
}

// The child (childToParent's k) that holds barycentric point b, and b in the child's own coordinates.
uint32_t childOf(vec2& b) {
  if (b.x >= 0.5f) {
    b = vec2(2.0f * b.x - 1.0f, 2.0f * b.y);
    return 1;
  }
  if (b.y >= 0.5f) {
    b = vec2(2.0f * b.x, 2.0f * b.y - 1.0f);
    return 2;
  }
  if (b.x + b.y < 0.5f) {
    b = 2.0f * b;
    return 0;
  }
  b = vec2(1.0f - 2.0f * b.x, 1.0f - 2.0f * b.y);
  return 3;
}

// The sub-triangle of level `level` that holds barycentric point b (its base-4 index, the first split the
// most significant digit).
uint32_t subTriangleOf(vec2 b, uint32_t level) {
  uint32_t index = 0;
  for (uint32_t l = 0; l < level; ++l) index = 4 * index + childOf(b);
  return index;
}

// The level of the maps' splits for a triangle of longest edge longestM: until the sub-triangles'
// longest edge is at most targetEdgeM, at most kMaxMapLevel.
uint32_t splitLevel(float longestM, float targetEdgeM) {
  uint32_t level = 0;
  while (level < kMaxMapLevel && longestM > targetEdgeM * float(1u << level)) ++level;
  return level;
}

// The point of sub-triangle `index` of level `level` at c in its own unit triangle.
vec2 subTrianglePoint(uint32_t index, uint32_t level, vec2 c) {
  for (uint32_t l = 0; l < level; ++l) {
    c = childToParent(index & 3u, c);
    index >>= 2;
  }
  return c;
}

uint32_t normalBin(const vec3& n) {
  const vec3 a = glm::abs(n);
  if (a.x >= a.y && a.x >= a.z) return n.x >= 0.0f ? 0 : 1;
  if (a.y >= a.z) return n.y >= 0.0f ? 2 : 3;
  return n.z >= 0.0f ? 4 : 5;
}

}  // namespace

uint64_t LitPatches::keyOf(const vec3& p, const vec3& n) const {
  const vec3 g = glm::floor((p - originM_) / cellSizeM_);
  auto coordinate = [](float x) {
    const double c = std::clamp(double(x), double(-kCoordinateBias), double(kCoordinateBias - 1));
    return static_cast<uint64_t>(static_cast<int64_t>(c) + kCoordinateBias);
  };
  return (coordinate(g.x) << 43) | (coordinate(g.y) << 23) | (coordinate(g.z) << 3) | normalBin(n);
}

float LitPatches::cellSizeM(std::span<const TrainingPoint> points, std::span<const uint32_t> indices,
                            std::span<const vec3> positionsM, vec3* boxLoM) {
  if (points.empty()) return 1.0f;
  vec3 lo = points.front().p, hi = lo;
  for (const TrainingPoint& q : points) {
    lo = glm::min(lo, q.p);
    hi = glm::max(hi, q.p);
  }
  if (boxLoM) *boxLoM = lo;
  const float longest = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
  std::vector<float> edgesM;
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    for (size_t c = 0; c < 3; ++c) {
      const float e = glm::length(positionsM[indices[t + c]] - positionsM[indices[t + (c + 1) % 3]]);
      if (e > 0.0f && std::isfinite(e)) edgesM.push_back(e);
    }
  }
  float medianEdgeM = 0.0f;
  if (!edgesM.empty()) {
    std::nth_element(edgesM.begin(), edgesM.begin() + static_cast<std::ptrdiff_t>(edgesM.size() / 2),
                     edgesM.end());
    medianEdgeM = edgesM[edgesM.size() / 2];
  }
  const float size = std::max(longest / kCellsAlongLongestSide, kCellsPerEdgeLength * medianEdgeM);
  return size > 0.0f && std::isfinite(size) ? size : 1.0f;
}

LitPatches::LitPatches(const EmbreeScene& scene, std::span<const TrainingPoint> points,
                       std::span<const uint8_t> passesStraight,
                       std::span<const uint32_t> indices, std::span<const vec3> positionsM,
                       const RadianceEstimate& radiance, const FaceRadiance& faceRadiance, bool maps) {
  if (points.empty()) return;
  vec3 lo = points.front().p;
  cellSizeM_ = cellSizeM(points, indices, positionsM, &lo);
  originM_ = lo;

  // The training points of each cell, cells in order of their first point (deterministic).
  std::unordered_map<uint64_t, uint32_t> candidate;
  std::vector<std::vector<uint32_t>> members;
  std::vector<uint64_t> keys;
  for (uint32_t i = 0; i < points.size(); ++i) {
    const uint64_t key = keyOf(points[i].p, points[i].n);
    auto [it, inserted] = candidate.try_emplace(key, static_cast<uint32_t>(members.size()));
    if (inserted) {
      members.emplace_back();
      keys.push_back(key);
    }
    members[it->second].push_back(i);
  }

  // Training: per cell, per triangle hit, the hits and the sum of their radiance estimates, and the escapes.
  // Hits of one face: its triangle, whether the front, the sum of their one-sample estimates, their count.
  struct TriangleHits {
    uint32_t triangle;
    bool front;
    double radiance;
    uint32_t count;
  };
  struct Training {
    std::vector<TriangleHits> hits;  // sorted by triangle
    uint32_t escapes = 0;
  };
  const size_t cellCandidates = members.size();
  std::vector<Training> training(cellCandidates);
  const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t c; (c = next.fetch_add(1)) < cellCandidates;) {
      const std::vector<uint32_t>& own = members[c];
      SobolSampler sampler(keys[c]);
      std::vector<TriangleHits> hits;
      Training& out = training[c];
      for (uint32_t j = 0; j < kTrainingRaysPerCell; ++j) {
        const TrainingPoint& q = points[own[j % own.size()]];
        sampler.startSample(j);
        const Onb frame = onb(q.n);
        const vec3 d = glm::normalize(frame.toWorld(sampleCosineHemisphere(sampler.next2D())));
        vec3 o = offsetRayOrigin(q.p, q.n, q.magnitudeM);
        bool escaped = true;
        for (uint32_t panes = 0; panes <= kTrainingPanes; ++panes) {
          const std::optional<Hit> hit = scene.intersect(o, d, std::numeric_limits<float>::infinity());
          if (!hit) break;
          const float cosHit = glm::dot(hit->geometricNormal, d);
          if (passesStraight[hit->triangle]) {
            if (panes == kTrainingPanes) {
              escaped = false;
              break;
            }
            o = offsetRayOrigin(o + hit->distanceM * d, cosHit > 0.0f ? hit->geometricNormal : -hit->geometricNormal,
                                scene.triangleMagnitudeM(hit->triangle));
            continue;
          }
          escaped = false;
          const float l = radiance(*hit, d, detail::mix64(keys[c] ^ (uint64_t{j} << 40)));
          hits.push_back({hit->triangle, cosHit < 0.0f, std::isfinite(l) ? std::max(double(l), 0.0) : 0.0, 1});
          break;
        }
        out.escapes += escaped ? 1 : 0;
        // Past this many escapes the cell is open whatever its other rays find.
        if (float(out.escapes) > kMaxEscapeFraction * float(kTrainingRaysPerCell)) break;
      }
      std::sort(hits.begin(), hits.end(), [](const TriangleHits& a, const TriangleHits& b) {
        return a.triangle < b.triangle || (a.triangle == b.triangle && a.front < b.front) ||
               (a.triangle == b.triangle && a.front == b.front && a.radiance < b.radiance);
      });
      for (const TriangleHits& h : hits) {
        if (!out.hits.empty() && out.hits.back().triangle == h.triangle && out.hits.back().front == h.front) {
          ++out.hits.back().count;
          out.hits.back().radiance += h.radiance;
        } else {
          out.hits.push_back({h.triangle, h.front, h.radiance, 1});
        }
      }
    }
  };
  {
    std::vector<std::jthread> pool;
    for (uint32_t k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
  }

  // The triangles around each triangle: those sharing a vertex with it, itself included.
  const size_t triangleCount = indices.size() / 3;
  const size_t vertexCount = positionsM.size();
  std::vector<uint32_t> ringStart(vertexCount + 1, 0);
  for (uint32_t v : indices) ++ringStart[v + 1];
  for (size_t v = 0; v < vertexCount; ++v) ringStart[v + 1] += ringStart[v];
  std::vector<uint32_t> ring(indices.size());
  {
    std::vector<uint32_t> fill(ringStart.begin(), ringStart.end() - 1);
    for (size_t i = 0; i < indices.size(); ++i) ring[fill[indices[i]]++] = static_cast<uint32_t>(i / 3);
  }
  auto around = [&](uint32_t t, std::vector<uint32_t>& out) {
    out.clear();
    for (size_t c = 0; c < 3; ++c) {
      const uint32_t v = indices[3 * size_t{t} + c];
      out.insert(out.end(), ring.begin() + ringStart[v], ring.begin() + ringStart[v + 1]);
    }
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
  };

  // Per enclosed cell, its hits spread over the triangles around each hit triangle (same face), as shares of
  // the hit counts: a sun patch's triangles that no training ray happened to hit get the share of their
  // neighbours'.
  struct Spread {
    uint64_t face;  // 2 t + back
    double share;
  };
  std::vector<std::vector<Spread>> spreads(cellCandidates);
  auto enclosed = [&](const Training& t) {
    return float(t.escapes) <= kMaxEscapeFraction * float(kTrainingRaysPerCell) && !t.hits.empty();
  };
  next = 0;
  auto spreadWork = [&] {
    std::vector<uint32_t> neighbours;
    for (size_t c; (c = next.fetch_add(1)) < cellCandidates;) {
      if (!enclosed(training[c])) continue;
      std::vector<Spread>& out = spreads[c];
      for (const TriangleHits& h : training[c].hits) {
        if (h.triangle >= triangleCount) continue;
        around(h.triangle, neighbours);
        const double share = double(h.count) / double(neighbours.size());
        for (uint32_t n : neighbours) out.push_back({2 * uint64_t{n} + (h.front ? 0 : 1), share});
      }
      std::sort(out.begin(), out.end(), [](const Spread& a, const Spread& b) { return a.face < b.face; });
      size_t kept = 0;
      for (const Spread& x : out) {
        if (kept > 0 && out[kept - 1].face == x.face) {
          out[kept - 1].share += x.share;
        } else {
          out[kept++] = x;
        }
      }
      out.resize(kept);
    }
  };
  {
    std::vector<std::jthread> pool;
    for (uint32_t k = 1; k < threads; ++k) pool.emplace_back(spreadWork);
    spreadWork();
  }

  // The mean radiance of every face that some spread reaches.
  std::vector<uint64_t> faces;
  for (const std::vector<Spread>& spread : spreads) {
    for (const Spread& x : spread) faces.push_back(x.face);
  }
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  std::vector<float> faceRadiances(faces.size(), 0.0f);
  next = 0;
  auto faceWork = [&] {
    for (size_t i; (i = next.fetch_add(1)) < faces.size();) {
      const float l = faceRadiance(static_cast<uint32_t>(faces[i] / 2), faces[i] % 2 == 0);
      faceRadiances[i] = std::isfinite(l) ? std::max(l, 0.0f) : 0.0f;
    }
  };
  {
    std::vector<std::jthread> pool;
    for (uint32_t k = 1; k < threads; ++k) pool.emplace_back(faceWork);
    faceWork();
  }
  auto faceRadianceOf = [&](uint64_t face) {
    return double(
        faceRadiances[static_cast<size_t>(std::lower_bound(faces.begin(), faces.end(), face) - faces.begin())]);
  };

  // The distributions, per triangle (both faces together): (1 − kHitShare) of half by the spread shares
  // times the faces' mean radiance and half by the hits' own radiance estimates, kHitShare by the spread
  // shares alone.
  for (size_t c = 0; c < cellCandidates; ++c) {
    const std::vector<Spread>& spread = spreads[c];
    if (spread.empty()) continue;
    struct Weight {
      uint32_t triangle;
      double smooth, hit, count;
    };
    std::vector<Weight> weights;
    for (const Spread& x : spread) {
      const auto tri = static_cast<uint32_t>(x.face / 2);
      if (weights.empty() || weights.back().triangle != tri) weights.push_back({tri, 0.0, 0.0, 0.0});
      weights.back().smooth += x.share * faceRadianceOf(x.face);
      weights.back().count += x.share;
    }
    for (const TriangleHits& h : training[c].hits) {
      auto it = std::lower_bound(weights.begin(), weights.end(), h.triangle,
                                 [](const Weight& w, uint32_t t) { return w.triangle < t; });
      if (it != weights.end() && it->triangle == h.triangle) it->hit += h.radiance;
    }
    double smoothSum = 0.0, hitSum = 0.0, countSum = 0.0;
    for (const Weight& w : weights) {
      smoothSum += w.smooth;
      hitSum += w.hit;
      countSum += w.count;
    }
    if (!(smoothSum > 0.0) && !(hitSum > 0.0)) continue;  // nothing lit in sight: path sampling alone
    const double smoothShare = !(hitSum > 0.0) ? 1.0 : !(smoothSum > 0.0) ? 0.0 : 0.5;
    const auto first = static_cast<uint32_t>(entries_.size());
    double running = 0.0;
    for (const Weight& w : weights) {
      running += (1.0 - kHitShare) * (smoothShare * (smoothSum > 0.0 ? w.smooth / smoothSum : 0.0) +
                                      (1.0 - smoothShare) * (hitSum > 0.0 ? w.hit / hitSum : 0.0)) +
                 kHitShare * w.count / countSum;
      entries_.push_back({static_cast<float>(running), 0.0f, w.triangle});
    }
    entries_.back().cdf = 1.0f;
    // Each triangle's probability as sample() picks it: the width of its interval of [0, 1).
    for (size_t i = first; i < entries_.size(); ++i) {
      entries_[i].pmf = entries_[i].cdf - (i == first ? 0.0f : entries_[i - 1].cdf);
    }
    cellOfKey_.emplace(keys[c], static_cast<uint32_t>(cells_.size()));
    const auto count = static_cast<uint32_t>(weights.size());
    const auto firstGuide = static_cast<uint32_t>(guides_.size());
    uint32_t i = first;
    for (uint32_t g = 0; g < count; ++g) {
      const float threshold = float(g) / float(count);
      while (i + 1 < first + count && entries_[i].cdf <= threshold) ++i;
      guides_.push_back(i);
    }
    cells_.push_back({first, count, firstGuide});
  }

  if (maps && !cells_.empty()) buildMaps(scene, indices, positionsM, faces, radiance);

  size_t slots = 1;
  while (slots < 2 * entries_.size()) slots *= 2;
  slots_.assign(slots, {kEmptySlot, 0.0f});
  for (uint32_t c = 0; c < cells_.size(); ++c) {
    for (uint32_t i = cells_[c].first; i < cells_[c].first + cells_[c].count; ++i) {
      const uint64_t key = (uint64_t{c} << 32) | entries_[i].triangle;
      slots_[slotOf(key)] = {key, entries_[i].pmf};
    }
  }
}

void LitPatches::buildMaps(const EmbreeScene& scene, std::span<const uint32_t> indices,
                           std::span<const vec3> positionsM, std::span<const uint64_t> faces,
                           const RadianceEstimate& radiance) {
  // The triangles of some cell's distribution, with the faces of theirs that training reached (faces: 2 t +
  // back, sorted), and the level each would take.
  struct Candidate {
    uint32_t triangle;
    uint32_t faceBits;  // 1: front, 2: back
    uint32_t level;
  };
  std::vector<Candidate> candidates;
  std::vector<uint8_t> inSome(indices.size() / 3, 0);
  for (const Entry& e : entries_) inSome[e.triangle] = 1;
  const float targetEdgeM = cellSizeM_ / kMapSubdivisionsPerCell;
  for (uint64_t face : faces) {
    const auto t = static_cast<uint32_t>(face / 2);
    if (!inSome[t]) continue;
    const uint32_t bit = face % 2 == 0 ? 1u : 2u;
    if (!candidates.empty() && candidates.back().triangle == t) {
      candidates.back().faceBits |= bit;
      continue;
    }
    float longestM = 0.0f;
    for (size_t c = 0; c < 3; ++c) {
      longestM = std::max(longestM, glm::length(positionsM[indices[3 * size_t{t} + c]] -
                                                positionsM[indices[3 * size_t{t} + (c + 1) % 3]]));
    }
    const uint32_t level = splitLevel(longestM, targetEdgeM);
    if (level > 0) candidates.push_back({t, bit, level});
  }
  // The direct light at kMapPointsPerSubTriangle points of each sub-triangle of candidate c at `level` (its
  // centroid and the points three quarters of the way from it to each corner), summed over its faces; empty
  // where every point or none is lit (uniform).
  const float kPoints[kMapPointsPerSubTriangle][2] = {
      {1.0f / 3.0f, 1.0f / 3.0f}, {1.0f / 12.0f, 1.0f / 12.0f}, {5.0f / 6.0f, 1.0f / 12.0f}, {1.0f / 12.0f, 5.0f / 6.0f}};
  auto evaluate = [&](const Candidate& c, uint32_t level) {
    const vec3& ng = scene.triangleNormal(c.triangle);
    const uint32_t subs = 1u << (2 * level);
    std::vector<float> w(subs, 0.0f);
    uint32_t lit = 0;
    for (uint32_t s = 0; s < subs; ++s) {
      for (uint32_t k = 0; k < kMapPointsPerSubTriangle; ++k) {
        Hit hit;
        hit.triangle = c.triangle;
        hit.barycentric = subTrianglePoint(s, level, vec2(kPoints[k][0], kPoints[k][1]));
        hit.geometricNormal = ng;
        float sum = 0.0f;
        for (uint32_t face = 0; face < 2; ++face) {
          if (!(c.faceBits & (1u << face))) continue;
          const uint64_t seed = detail::mix64(~((uint64_t{c.triangle} << 28) ^ (uint64_t{level} << 24) ^
                                                (uint64_t{s} << 4) ^ (uint64_t{k} << 1) ^ face));
          const float l = radiance(hit, face == 0 ? -ng : ng, seed);
          if (std::isfinite(l) && l > 0.0f) sum += l;
        }
        w[s] += sum;
        lit += sum > 0.0f ? 1 : 0;
      }
    }
    if (lit == 0 || lit == subs * kMapPointsPerSubTriangle) w.clear();
    return w;
  };
  // In parallel over candidates, per candidate into its own slot: deterministic.
  auto parallel = [&](auto&& f) {
    std::atomic<size_t> next{0};
    auto work = [&] {
      for (size_t i; (i = next.fetch_add(1)) < candidates.size();) f(i);
    };
    const uint32_t threads = std::max(1u, std::thread::hardware_concurrency());
    std::vector<std::jthread> pool;
    for (uint32_t k = 1; k < threads; ++k) pool.emplace_back(work);
    work();
  };
  // A probe at level 2 at most first: triangles that the sun lights wholly, or not at all, get no map.
  std::vector<uint8_t> partlyLit(candidates.size(), 0);
  parallel([&](size_t i) {
    partlyLit[i] = evaluate(candidates[i], std::min(candidates[i].level, 2u)).empty() ? 0 : 1;
  });
  size_t kept = 0;
  for (size_t i = 0; i < candidates.size(); ++i) {
    if (partlyLit[i]) candidates[kept++] = candidates[i];
  }
  candidates.resize(kept);
  // Within the budget: the deepest levels lowered one at a time.
  for (;;) {
    uint64_t total = 0;
    uint32_t deepest = 0;
    for (const Candidate& c : candidates) {
      total += uint64_t{1} << (2 * c.level);
      deepest = std::max(deepest, c.level);
    }
    if (total <= kMapSubTriangleBudget || deepest <= 1) break;
    for (Candidate& c : candidates) c.level = std::min(c.level, deepest - 1);
  }
  std::vector<std::vector<float>> weights(candidates.size());
  parallel([&](size_t i) { weights[i] = evaluate(candidates[i], candidates[i].level); });
  for (size_t i = 0; i < candidates.size(); ++i) {
    const std::vector<float>& w = weights[i];
    if (w.empty()) continue;
    if (maps_.empty()) maps_.assign(indices.size() / 3, {0, 0});
    double total = 0.0;
    for (float x : w) total += x;
    const auto first = static_cast<uint32_t>(mapCdf_.size());
    const double uniform = double(kMapUniformShare) / double(w.size());
    double running = 0.0;
    for (float x : w) {
      running += (1.0 - kMapUniformShare) * double(x) / total + uniform;
      mapCdf_.push_back(static_cast<float>(running));
    }
    mapCdf_.back() = 1.0f;
    maps_[candidates[i].triangle] = {first, candidates[i].level};
    ++mapCount_;
  }
}

size_t LitPatches::slotOf(uint64_t key) const {
  const size_t mask = slots_.size() - 1;
  size_t slot = detail::mix64(key) & mask;
  while (slots_[slot].key != key && slots_[slot].key != kEmptySlot) slot = (slot + 1) & mask;
  return slot;
}

uint32_t LitPatches::cellOf(const vec3& p, const vec3& n) const {
  if (cells_.empty()) return kNoCell;
  const auto it = cellOfKey_.find(keyOf(p, n));
  return it == cellOfKey_.end() ? kNoCell : it->second;
}

LitPatches::Pick LitPatches::sample(uint32_t cell, float u) const {
  const Cell& c = cells_[cell];
  // The first entry whose running sum exceeds u (the last where none does), from the guide of u's interval.
  const uint32_t last = c.first + c.count - 1;
  const auto g = std::min(static_cast<uint32_t>(std::max(u, 0.0f) * float(c.count)), c.count - 1);
  uint32_t i = guides_[c.firstGuide + g];
  while (i < last && entries_[i].cdf <= u) ++i;
  while (i > c.first && entries_[i - 1].cdf > u) --i;
  const float below = i == c.first ? 0.0f : entries_[i - 1].cdf;
  const float width = entries_[i].cdf - below;
  const float remapped = width > 0.0f ? std::clamp((u - below) / width, 0.0f, 0x1.fffffep-1f) : 0.0f;
  return {entries_[i].triangle, entries_[i].pmf, remapped};
}

float LitPatches::pmf(uint32_t cell, uint32_t t) const {
  const uint64_t key = (uint64_t{cell} << 32) | t;
  const Slot& slot = slots_[slotOf(key)];
  return slot.key == key ? slot.pmf : 0.0f;
}

float LitPatches::density(uint32_t cell, uint32_t t, const vec2& b) const {
  const uint64_t key = (uint64_t{cell} << 32) | t;
  const Slot& slot = slots_[slotOf(key)];
  if (slot.key != key) return 0.0f;
  return slot.pmf * mapFactor(t, b);
}

LitPatches::PointPick LitPatches::samplePoint(const Pick& pick, const vec2& u) const {
  const uint32_t t = pick.triangle;
  const MapRef map = maps_.empty() ? MapRef{0, 0} : maps_[t];
  if (map.level == 0) {
    const vec3 b = sampleUniformTriangle(u);
    return {vec2(b.y, b.z), 1.0f};
  }
  const uint32_t subs = 1u << (2 * map.level);
  const auto begin = mapCdf_.begin() + map.first;
  const auto it = std::upper_bound(begin, begin + subs, u.x);
  const auto s = static_cast<uint32_t>(std::min<std::ptrdiff_t>(it - begin, subs - 1));
  const float below = s == 0 ? 0.0f : begin[s - 1];
  const float width = begin[s] - below;
  const float remapped = width > 0.0f ? std::clamp((u.x - below) / width, 0.0f, 0x1.fffffep-1f) : 0.0f;
  const vec3 c = sampleUniformTriangle(vec2(remapped, u.y));
  const vec2 b = subTrianglePoint(s, map.level, vec2(c.y, c.z));
  // The density as density() evaluates it at the point (the same sub-triangle but where rounding puts the
  // point on its edge into a neighbour's), so that both strategies' weights use one function.
  return {b, mapFactor(t, b)};
}

float LitPatches::mapFactor(uint32_t t, const vec2& b) const {
  if (maps_.empty()) return 1.0f;
  const MapRef map = maps_[t];
  if (map.level == 0) return 1.0f;
  const uint32_t subs = 1u << (2 * map.level);
  const uint32_t s = subTriangleOf(b, map.level);
  const float below = s == 0 ? 0.0f : mapCdf_[map.first + s - 1];
  return (mapCdf_[map.first + s] - below) * float(subs);
}

}  // namespace fly::raytracer
