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

LitPatches::LitPatches(const EmbreeScene& scene, std::span<const TrainingPoint> points,
                       std::span<const uint8_t> passesStraight,
                       std::span<const uint32_t> indices, std::span<const vec3> positionsM,
                       const RadianceEstimate& radiance, const FaceRadiance& faceRadiance) {
  if (points.empty()) return;
  vec3 lo = points.front().p, hi = lo;
  for (const TrainingPoint& q : points) {
    lo = glm::min(lo, q.p);
    hi = glm::max(hi, q.p);
  }
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
  cellSizeM_ = std::max(longest / kCellsAlongLongestSide, kCellsPerEdgeLength * medianEdgeM);
  if (!(cellSizeM_ > 0.0f) || !std::isfinite(cellSizeM_)) cellSizeM_ = 1.0f;
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

}  // namespace fly::raytracer
