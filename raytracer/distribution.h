// Piecewise-constant distributions for importance sampling tabulated functions: emitters by area or power
// (discrete), a sky table (2D). Sampling inverts the cumulative distribution (Pharr, Jakob & Humphreys,
// "Physically Based Rendering", 4th ed., §A.4.2 and §A.5).
//
// Precision: the cumulative table is summed in double and stored in float, and u has 24 bits, so a bin is
// chosen with its tabulated probability (the one pdf() reports) to within ~6·10⁻⁸ absolute; a bin whose
// probability is below that may never be chosen. The bias this leaves is below n · 6·10⁻⁸ of the integral for
// n bins, and far below that unless most of the table is that dark.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "base/math.h"

namespace fly::raytracer {

// A function f on [0, 1) that is constant on n equal bins, sampled with density f / ∫f.
class Distribution1D {
 public:
  // weights: f on each bin, n ≥ 1 values, each finite and ≥ 0 (std::invalid_argument otherwise). When all are
  // 0, the distribution samples uniformly (allZero() tells).
  explicit Distribution1D(std::span<const float> weights);

  uint32_t size() const { return static_cast<uint32_t>(func_.size()); }
  // ∫₀¹ f = Σ weights / n.
  double integral() const { return integral_; }
  bool allZero() const { return integral_ == 0.0; }

  struct Sample {
    float x;       // in [0, 1)
    float pdf;     // f(x) / ∫f, > 0
    uint32_t bin;  // binOf(x)
  };
  // x with density f / ∫f, u ∈ [0, 1).
  Sample sampleContinuous(float u) const {
    const uint32_t i = findBin(u);
    float x = std::min((static_cast<float>(i) + remap(u, i)) * invSize_, kOneMinusEpsilon);
    // Rounding can carry x across an edge of bin i; keep it inside, as binOf() sees it, so that its density
    // is that of bin i (a neighbour's may be 0).
    while (binOf(x) > i) x = std::nextafter(x, 0.0f);
    while (binOf(x) < i) x = std::nextafter(x, 1.0f);
    return {x, func_[i] * pdfScale_, i};
  }
  // Density at x ∈ [0, 1) (clamped into it).
  float pdf(float x) const { return func_[binOf(x)] * pdfScale_; }
  // The bin that holds x ∈ [0, 1) (clamped into it); sampleContinuous's x always lies in its `bin` by this
  // rule.
  uint32_t binOf(float x) const {
    return std::min(static_cast<uint32_t>(std::max(x, 0.0f) * static_cast<float>(size())), size() - 1);
  }

  struct DiscreteSample {
    uint32_t index;
    float pmf;        // weights[index] / Σ weights, > 0
    float uRemapped;  // u rescaled to [0, 1) within the chosen bin, free to reuse for a further choice
  };
  // A bin with probability weights[i] / Σ weights, u ∈ [0, 1).
  DiscreteSample sampleDiscrete(float u) const;
  float pmf(uint32_t i) const { return func_[i] * pdfScale_ / static_cast<float>(size()); }

 private:
  static constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;
  // Guide intervals per bin (findBin): with four, a sky table's search mostly ends in its guide entry.
  static constexpr uint32_t kGuideIntervalsPerBin = 4;

  // The bin i with cdf[i] ≤ u < cdf[i+1]: never one of probability 0.
  uint32_t findBin(float u) const {
    // The largest i < n with cdf[i] ≤ u (cdf[0] = 0 ≤ u). A guide table (Chen & Asau, "On generating random
    // variates from an empirical distribution", AIIE Trans. 6(2), 1974) narrows it to guide_[k] … guide_[k+1]
    // for u in the k-th of kGuideIntervalsPerBin · n equal intervals — usually one bin, so that the search
    // below mostly has nothing left to do — and a binary search whose step is a
    // conditional move rather than a branch (Khuong & Morin, "Array layouts for comparison-based
    // searching", JEA 22, 2017) finishes it: the same bin as a search of the whole table, in O(1) for tables
    // without long runs of tiny bins and O(log n) always. Then cdf[i+1] > u, so bin i has a probability
    // above 0.
    const uint32_t k = guideInterval(u);
    const float* first = cdf_.data() + guide_[k];
    for (uint32_t length = guide_[k + 1] - guide_[k] + 1; length > 1;) {
      const uint32_t half = length / 2;
      first = first[half] <= u ? first + half : first;
      length -= half;
    }
    return static_cast<uint32_t>(first - cdf_.data());
  }
  uint32_t guideInterval(float u) const {
    return std::min(static_cast<uint32_t>(std::max(u, 0.0f) * guideScale_), guideIntervals_ - 1);
  }
  float remap(float u, uint32_t i) const { return std::min((u - cdf_[i]) * invWidth_[i], kOneMinusEpsilon); }

  std::vector<float> func_;  // the weights, or all 1 when they are all 0
  std::vector<float> cdf_;   // n + 1 values from 0 to 1
  // guideIntervals_ + 1 values: guide_[k] is the bin of the smallest u in guide interval k (findBin), the
  // last n − 1; the bin of every u in interval k lies in guide_[k] … guide_[k+1].
  std::vector<uint32_t> guide_;
  uint32_t guideIntervals_ = 1;  // kGuideIntervalsPerBin · n
  float guideScale_ = 1.0f;      // guideIntervals_ as a float: u's interval is u · guideScale_
  // 1 / (cdf[i+1] − cdf[i]) (0 for an empty bin, which is never chosen) and 1 / n: sampling multiplies
  // rather than divides.
  std::vector<float> invWidth_;
  float invSize_ = 1.0f;
  double integral_ = 0.0;
  float pdfScale_ = 1.0f;  // 1 / ∫func_
};

// A function f on [0, 1)² that is constant on nu × nv cells, sampled with density f / ∬f as the marginal
// density of v times the conditional density of u given v. For a sky table over (u, v) = (φ / 2π, 1 − cos θ),
// equal-area over the upper hemisphere, tabulate L; a direction's density is pdf(u, v) / 2π per steradian.
// For a latitude–longitude table with θ = π v, tabulate L sin θ; the density is pdf(u, v) / (2π² sin θ).
class Distribution2D {
 public:
  // values: nu · nv values, row after row (row j holds f on v ∈ [j/nv, (j+1)/nv)), each finite and ≥ 0
  // (std::invalid_argument otherwise; also for nu or nv = 0 or a size other than nu · nv). When all are 0,
  // the distribution samples uniformly (allZero() tells).
  Distribution2D(std::span<const float> values, uint32_t nu, uint32_t nv);

  // ∬f over the unit square.
  double integral() const { return marginal_.integral(); }
  bool allZero() const { return marginal_.allZero(); }

  struct Sample {
    vec2 p;         // in [0, 1)²
    float pdf;      // f(p) / ∬f, > 0
    uint32_t cell;  // row · nu + column of the cell that holds p
  };
  // u.y chooses the row, u.x the position in it.
  Sample sample(const vec2& u) const {
    const Distribution1D::Sample v = marginal_.sampleContinuous(u.y);
    const Distribution1D::Sample uu = conditional_[v.bin].sampleContinuous(u.x);
    return {vec2(uu.x, v.x), uu.pdf * v.pdf, v.bin * conditional_[v.bin].size() + uu.bin};
  }
  float pdf(const vec2& p) const { return conditional_[marginal_.binOf(p.y)].pdf(p.x) * marginal_.pdf(p.y); }

 private:
  std::vector<Distribution1D> conditional_;  // one per row
  Distribution1D marginal_;                  // of the rows' integrals
};

}  // namespace fly::raytracer
