// Sample generators for the integrator: Owen-scrambled Sobol' points (quasi-Monte Carlo) and PCG32 random
// numbers (plain Monte Carlo, for comparison), behind one interface.
//
// Both are value types with the same members (the Sampler concept below). The integrator is a template over
// the sampler type rather than calling through a virtual interface: a sample costs a few nanoseconds, and
// inlining the hashes into the integrator's loop matters more than one compiled instance fewer.
//
// Dimensions. Every value a sampler returns is a pure function of (pointSeed, sampleIndex, dimension), so the
// result of a bake does not depend on which thread integrates which point, nor in which order. The dimensions
// of a sample are numbered 0, 1, 2, …; they come in groups of four (group g holds dimensions 4g … 4g+3):
//   - next1D() returns the next dimension; next2D() the next aligned pair (4g, 4g+1) or (4g+2, 4g+3),
//   skipping
//     one dimension when the next one is odd;
//   - a group that runs out continues in the next group;
//   - startGroup(g) jumps to dimension 4g. The integrator gives each bounce its own group(s), so a bounce's
//     dimensions stay the same whatever number of dimensions an earlier bounce used.
//
// SobolSampler (Burley, "Practical Hash-based Owen Scrambling", JCGT 9(4), 2020): each group is its own 4D
// Sobol' sequence — dimensions 0–3 of Sobol' with the direction numbers of Joe & Kuo, "Constructing Sobol
// sequences with better two-dimensional projections", SIAM J. Sci. Comput. 30 (2008) — whose sample index is
// shuffled and whose coordinates are Owen-scrambled (nested uniform scrambling) by hashes seeded from the
// point seed and the group: Burley's "padding" of a high-dimensional sample by independent, shuffled 4D sets.
// The shuffle is itself an Owen scramble of the index: samples 0 … 2^m − 1 of a point are an aligned block of
// 2^m consecutive Sobol' points, a net that is different for every point and group. Use power-of-two sample
// counts: any other count loses the net property of the last, incomplete block.
//
// Stratification within a group, for 2^m samples: the pair (0, 1) is a (0, m, 2)-net (every elementary
// interval of area 2^−m holds one point); the pair (2, 3) is a (t, m, 2)-net with t ≤ 2 (t = 0, 0, 1, 2, 0,
// 1, 1, 1, 1, 1, 1 for m = 0 … 10); all four are one 4D net. So the group's first pair should carry the
// integral that matters most (the direction). Four-dimensional groups beat independently padded 2D pairs
// where an integrand couples two pairs (a point of a vertex's neighbourhood and a direction): at 256 samples
// of a smooth 4D test integrand the RMSE is 9× lower, while a 2D integrand on the pair (2, 3) loses about 25
// % against a (0, 2) pair.
#pragma once

#include <array>
#include <concepts>
#include <cstdint>

#include "base/math.h"

namespace fly::raytracer {

// Every sampler offers this; the integrator is written against it.
template <class S>
concept Sampler = requires(S s, uint32_t n) {
  s.startSample(n);                       // sample index n of this point, dimension 0
  s.startGroup(n);                        // continue at dimension 4n
  { s.next1D() } -> std::same_as<float>;  // in [0, 1)
  { s.next2D() } -> std::same_as<vec2>;   // in [0, 1)²
  s.skip(n);                              // pass over n dimensions of the group, as n next1D() would
};

// Dimensions per group.
inline constexpr uint32_t kGroupDimensions = 4;

namespace detail {

// SplitMix64's finaliser (Steele, Lea & Flood, "Fast splittable pseudorandom number generators", OOPSLA 2014;
// Stafford's "Mix13" constants): a bijective 64-bit mix with full avalanche.
inline constexpr uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

inline constexpr uint32_t reverseBits(uint32_t x) {
  x = (x << 16) | (x >> 16);
  x = ((x & 0x00ff00ffu) << 8) | ((x >> 8) & 0x00ff00ffu);
  x = ((x & 0x0f0f0f0fu) << 4) | ((x >> 4) & 0x0f0f0f0fu);
  x = ((x & 0x33333333u) << 2) | ((x >> 2) & 0x33333333u);
  return ((x & 0x55555555u) << 1) | ((x >> 1) & 0x55555555u);
}

// A Laine–Karras permutation (Laine & Karras, "Stratified sampling for stochastic transparency", EGSR 2011):
// every bit of the result depends only on the same and lower bits of x, so applied to a bit-reversed fraction
// it flips each binary digit depending only on the digits above it — one random Owen scramble per seed
// (Burley 2020). The constants are Vegdahl's improved hash ("Building a better LK hash", 2021), which
// scrambles more uniformly than the original; the seed must itself be well mixed.
inline constexpr uint32_t laineKarrasPermutation(uint32_t x, uint32_t seed) {
  x ^= x * 0x3d20adeau;
  x += seed;
  x *= (seed >> 16) | 1u;
  x ^= x * 0x05526c56u;
  x ^= x * 0x53a22864u;
  return x;
}

// [0, 1) from the 24 high bits: exactly representable, never 1.
inline constexpr float toUnitFloat(uint32_t x) {
  return static_cast<float>(x >> 8) * 0x1p-24f;
}

// Each byte bit-reversed.
inline constexpr std::array<uint8_t, 256> kReversedBytes = [] {
  std::array<uint8_t, 256> table{};
  for (uint32_t b = 0; b < 256; ++b) table[b] = static_cast<uint8_t>(reverseBits(b) >> 24);
  return table;
}();

// toUnitFloat(reverseBits(x)): the 24 high bits of the reversed x are its 24 low bits reversed, three bytes
// through kReversedBytes (fewer operations than reversing all 32 bits by shifts and masks).
inline constexpr float reversedToUnitFloat(uint32_t x) {
  const uint32_t reversed24 = (uint32_t{kReversedBytes[x & 255u]} << 16) |
                              (uint32_t{kReversedBytes[(x >> 8) & 255u]} << 8) |
                              kReversedBytes[(x >> 16) & 255u];
  return static_cast<float>(reversed24) * 0x1p-24f;
}

// Sobol' of a bit-reversed index, bit-reversed, by nibbles: kSobolNibbles[d][k][x] = XOR of reverse(v_{32−j})
// over the set bits j = 4k + b of the nibble x (v_1 … v_32: the direction numbers of Sobol' dimension d as
// 32-bit binary fractions; sampler.cpp). XOR over the eight nibbles of reverse(i) then gives
// reverse(sobol(i)), so that the Owen scramble, which works on reversed fractions, needs one bit reversal per
// coordinate instead of three, and the matrix product takes 8 lookups in a 2 KiB table instead of a loop over
// 32 bits.
using SobolNibbleTable = std::array<std::array<std::array<uint32_t, 16>, 8>, kGroupDimensions>;
extern const SobolNibbleTable kSobolNibbles;

}  // namespace detail

class SobolSampler {
 public:
  // pointSeed identifies the integration point (vertex, texel, sensor); any 64-bit value, e.g. an id.
  explicit SobolSampler(uint64_t pointSeed) : pointHash_(detail::mix64(pointSeed)) {}

  // Group 0 is hashed only when its first dimension is asked for (callers that begin with startGroup()
  // skip that work): group_ + 1 wraps to 0.
  void startSample(uint32_t sampleIndex) {
    reversedSample_ = detail::reverseBits(sampleIndex);
    group_ = ~0u;
    component_ = kGroupDimensions;
  }

  void startGroup(uint32_t group) {
    group_ = group;
    component_ = 0;
    // The group's seeds do not depend on the sample: they are hashed once and kept in a direct-mapped cache
    // by group mod kCachedGroups, which a point's samples reuse (a sampler serves one point).
    CachedGroup& slot = cache_[group % kCachedGroups];
    if (slot.group != group) slot = {group, groupSeeds(group)};
    // The index shuffled by an Owen scramble of its own (Burley 2020), kept bit-reversed (see
    // kSobolNibbles).
    reversedIndex_ = detail::laineKarrasPermutation(reversedSample_, slot.seeds.shuffle);
    seeds_ = slot.seeds.scramble;
  }

  float next1D() {
    if (component_ == kGroupDimensions) startGroup(group_ + 1);
    return coordinate(component_++);
  }

  // Within the group (component + n ≤ 4): a dimension's value does not depend on which were computed.
  void skip(uint32_t n) { component_ += n; }

  vec2 next2D() {
    component_ += component_ & 1u;
    if (component_ == kGroupDimensions) startGroup(group_ + 1);
    const vec2 u(coordinate(component_), coordinate(component_ + 1));
    component_ += 2;
    return u;
  }

 private:
  // Coordinate d of the group's 4D point: Sobol' of the shuffled index, then Owen-scrambled with a seed of
  // its own per dimension (Burley 2020, shuffled_scrambled_sobol4d).
  float coordinate(uint32_t d) const {
    const std::array<std::array<uint32_t, 16>, 8>& nibbles = detail::kSobolNibbles[d];
    uint32_t reversed = 0;
    for (uint32_t k = 0; k < 8; ++k) reversed ^= nibbles[k][(reversedIndex_ >> (4 * k)) & 15u];
    return detail::reversedToUnitFloat(detail::laineKarrasPermutation(reversed, seeds_[d]));
  }

  // A group's hashed seeds: of its index shuffle, and of each dimension's scramble.
  struct GroupSeeds {
    uint32_t shuffle;
    std::array<uint32_t, kGroupDimensions> scramble;
  };
  struct CachedGroup {
    uint32_t group = ~0u;  // none: ~0u is never started (startSample's "before group 0")
    GroupSeeds seeds{};
  };
  // Groups kept: those of the first 21 path vertices (3 a vertex). The integrator's and the baker's own
  // groups (raytracer/integrator.cpp, raytracer/baker.cpp) fall in slots 27 … 63 while their vertex is among
  // the first 17, so that they evict the groups of deep path vertices only.
  static constexpr uint32_t kCachedGroups = 64;

  GroupSeeds groupSeeds(uint32_t group) const {
    const uint64_t groupHash = detail::mix64(pointHash_ + group);
    // A scrambling seed per dimension: both halves of two more hashes.
    const uint64_t a = detail::mix64(groupHash + 1);
    const uint64_t b = detail::mix64(groupHash + 2);
    return {static_cast<uint32_t>(groupHash),
            {static_cast<uint32_t>(a), static_cast<uint32_t>(a >> 32), static_cast<uint32_t>(b),
             static_cast<uint32_t>(b >> 32)}};
  }

  uint64_t pointHash_;
  uint32_t reversedSample_ = 0;  // the sample index, bit-reversed
  uint32_t group_ = 0;
  uint32_t component_ = 0;  // next dimension within the group, 0 … 4
  uint32_t reversedIndex_ = 0;
  std::array<uint32_t, kGroupDimensions> seeds_{};
  std::array<CachedGroup, kCachedGroups> cache_{};
};

// PCG32 (O'Neill, "PCG: A family of simple fast space-efficient statistically good algorithms for random
// number generation", HMC-CS-2014-0905, 2014): a 64-bit LCG with the XSH-RR output permutation.
class Pcg32 {
 public:
  // O'Neill's pcg32_srandom: `stream` selects one of 2^63 sequences, `initState` the start within it.
  Pcg32(uint64_t initState, uint64_t stream) : increment_((stream << 1) | 1u) {
    next();
    state_ += initState;
    next();
  }

  uint32_t next() {
    const uint64_t old = state_;
    state_ = old * 6364136223846793005ull + increment_;
    const auto xorShifted = static_cast<uint32_t>(((old >> 18) ^ old) >> 27);
    const auto rotation = static_cast<uint32_t>(old >> 59);
    return (xorShifted >> rotation) | (xorShifted << ((0u - rotation) & 31u));
  }

 private:
  uint64_t state_ = 0;
  uint64_t increment_;
};

// Independent uniform numbers with the dimension layout of SobolSampler: each (point, sample, group) starts
// PCG32 at a hashed state, in a stream of the point's own, and the group's dimensions are the next four
// outputs.
class RandomSampler {
 public:
  explicit RandomSampler(uint64_t pointSeed) : pointHash_(detail::mix64(pointSeed)) {}

  // As SobolSampler's: group 0 starts at the first dimension asked for.
  void startSample(uint32_t sampleIndex) {
    sampleIndex_ = sampleIndex;
    group_ = ~0u;
    component_ = kGroupDimensions;
  }

  void startGroup(uint32_t group) {
    group_ = group;
    component_ = 0;
    rng_ = Pcg32(pointHash_ ^ detail::mix64((static_cast<uint64_t>(group) << 32) | sampleIndex_), pointHash_);
  }

  float next1D() {
    if (component_ == kGroupDimensions) startGroup(group_ + 1);
    ++component_;
    return detail::toUnitFloat(rng_.next());
  }

  void skip(uint32_t n) {
    for (uint32_t i = 0; i < n; ++i) next1D();
  }

  vec2 next2D() {
    if (component_ & 1u) next1D();
    const float x = next1D();
    return vec2(x, next1D());
  }

 private:
  uint64_t pointHash_;
  uint32_t sampleIndex_ = 0;
  uint32_t group_ = 0;
  uint32_t component_ = 0;
  Pcg32 rng_{0, 0};
};

static_assert(Sampler<SobolSampler> && Sampler<RandomSampler>);

}  // namespace fly::raytracer
